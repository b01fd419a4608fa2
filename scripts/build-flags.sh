# Sourced by the build scripts of the tests (test.sh, test-sanitize.sh, fuzz.sh):
# sets fast_link, the CMake options that link with LLVM's lld when it is
# installed (scripts/install-deps.sh installs it). A test build links about 70
# executables; lld links one of the sanitizer build's in 0.6 s where the
# default GNU linker takes 2.2 s. Without lld the default linker is kept.
fast_link=()
if command -v ld.lld >/dev/null; then
  fast_link=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=lld
             -DCMAKE_MODULE_LINKER_FLAGS=-fuse-ld=lld)
fi
