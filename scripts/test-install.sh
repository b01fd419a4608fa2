#!/usr/bin/env bash
# Installs fss and fssim into temporary prefixes, once with the static library
# and once with BUILD_SHARED_LIBS=ON, and checks each install as a user would:
# the files are where they belong, the installed fssim runs (and finds
# libfss.so through its RUNPATH), its man page renders, its bash completion
# completes, and two consumers build and run against the prefix: one with
# find_package(fss) (tests/install/cmake_consumer), one with pkg-config
# (tests/install/pkgconfig_consumer); and, when the build made the Python
# module, the installed module imports from the prefix (PYTHONPATH) and runs a
# small simulation.
#
# Usage: scripts/test-install.sh [--reuse-build DIR] [--keep]
#   --reuse-build DIR  install the variant of the existing, already built
#                      build directory DIR (static, or shared if it was
#                      configured with BUILD_SHARED_LIBS=ON) from DIR instead
#                      of configuring and building a fresh one (CTest's
#                      `install` test does this); the other variant is built
#                      fresh, through DIR's compiler launcher if it has one
#                      (scripts/test.sh's ccache: what DIR compiled with the
#                      same flags is not compiled again; the fresh build is
#                      made in a directory build-install-*.XXXXXX at the top
#                      of the checkout, as build/ is, so that under a
#                      CCACHE_BASEDIR the compiler sees the same relative
#                      paths, ../src/...).
#   --keep             leave the temporary directory and the fresh build
#                      directories (printed) for inspection.
# Prints one line per check and "test-install: N passed, M failed"; exits 1 on
# any failure. Builds with all cores; a fresh library build takes minutes.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
reuse=""
reuse_variant=""
keep=0
while [ $# -gt 0 ]; do
  case $1 in
    --reuse-build) reuse=$(realpath "${2:?--reuse-build needs a directory}"); shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "test-install: unknown argument '$1' (expected --reuse-build DIR or --keep)" >&2; exit 2 ;;
  esac
done
if [ -n "$reuse" ]; then
  [ -f "$reuse/CMakeCache.txt" ] || { echo "test-install: $reuse is not a CMake build directory" >&2; exit 2; }
  case $(sed -n 's/^BUILD_SHARED_LIBS:[A-Z]*=//p' "$reuse/CMakeCache.txt") in
    ON | on | TRUE | true | 1 | YES | yes) reuse_variant=shared ;;
    *) reuse_variant=static ;;
  esac
fi
jobs=$(nproc 2>/dev/null || echo 2)
launcher=()
if [ -n "$reuse" ]; then
  value=$(sed -n 's/^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=//p' "$reuse/CMakeCache.txt")
  [ -z "$value" ] || launcher=("-DCMAKE_CXX_COMPILER_LAUNCHER=$value")
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/fss-test-install.XXXXXX")
fresh_builds=()  # the fresh build directories, at the top of the checkout
if [ "$keep" -eq 1 ]; then
  echo "test-install: working in $work (kept)"
else
  trap 'rm -rf "$work" "${fresh_builds[@]}"' EXIT
fi

passed=0
failed=0
# check NAME COMMAND...: runs COMMAND, its output to a log; one line per check.
check() {
  local name=$1 log
  shift
  log="$work/log.$((passed + failed))"
  if "$@" >"$log" 2>&1; then
    passed=$((passed + 1))
    echo "ok    $name"
  else
    failed=$((failed + 1))
    echo "FAIL  $name"
    tail -n 30 "$log" | sed 's/^/      /'
  fi
}
# Prints the output of the last check.
last_output() { cat "$work/log.$((passed + failed - 1))"; }

# configure_and_build BUILD_DIR CMAKE_ARGS...
configure_and_build() {
  local build=$1
  shift
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=OFF "${launcher[@]}" "$@" &&
    cmake --build "$build" -j "$jobs"
}

# The files an install must hold, relative to the prefix ($1); $2 is the
# variant, $3 the libdir.
expect_files() {
  local prefix=$1 variant=$2 libdir=$3 missing=0 file code
  local files=(bin/fssim include/fss/core/error.h include/fss/pipeline/simulate.h
    include/fss/io/outputs.h "$libdir/cmake/fss/fssConfig.cmake"
    "$libdir/cmake/fss/fssConfigVersion.cmake" "$libdir/cmake/fss/fssTargets.cmake"
    "$libdir/pkgconfig/fss.pc" share/man/man1/fssim.1 share/bash-completion/completions/fssim)
  for code in snapshot accumulation raskar random mip sinc; do
    files+=("share/fssim/codes/$code.txt")
  done
  if [ "$variant" = shared ]; then
    files+=("$libdir/libfss.so" "$libdir/libfss.so.0.1")
  else
    files+=("$libdir/libfss.a")
  fi
  for file in "${files[@]}"; do
    if [ ! -e "$prefix/$file" ]; then
      echo "missing: $file"
      missing=1
    fi
  done
  [ "$variant" = static ] && [ -e "$prefix/$libdir/libfss.so" ] && { echo "libfss.so in a static install"; missing=1; }
  [ "$missing" -eq 0 ] && (cd "$prefix" && find . -type f -o -type l | sort)
}

# The installed fssim finds libfss.so through its RUNPATH ($ORIGIN/...), with
# no LD_LIBRARY_PATH, and uses the installed library.
check_runpath() {
  local prefix=$1 libdir=$2 runpath resolved
  runpath=$(readelf -d "$prefix/bin/fssim" | sed -n 's/.*(RUNPATH).*\[\(.*\)\]/\1/p')
  echo "RUNPATH: $runpath"
  # shellcheck disable=SC2016 # the literal $ORIGIN
  [[ $runpath == *'$ORIGIN'* ]] || return 1
  resolved=$(env -u LD_LIBRARY_PATH ldd "$prefix/bin/fssim" | sed -n 's/.*libfss\.so[^ ]* => \([^ ]*\).*/\1/p')
  echo "libfss.so => $resolved"
  [ "$(realpath "$resolved")" = "$(realpath "$prefix/$libdir/libfss.so.0.1")" ]
}

# fssim --version: the same string as the build's own fssim.
check_version() {
  local prefix=$1 build=$2 installed built
  installed=$(env -u LD_LIBRARY_PATH "$prefix/bin/fssim" --version) || return 1
  built=$("$build/fssim" --version) || return 1
  echo "$installed"
  [[ $installed == "fssim 0.1.0"* ]] && [ "$installed" = "$built" ]
}

# The installed fssim computes: the raskar code's figures.
check_analyze() {
  local output
  output=$(env -u LD_LIBRARY_PATH "$1/bin/fssim" code analyze raskar) || return 1
  echo "$output"
  grep -qx 'Sum of gains: 26.000000' <<<"$output" && grep -qx 'SNR at level 100: 48.127577' <<<"$output"
}

# The man page renders (man -l, or groff where man-db is missing) without a
# warning and holds every section.
check_man() {
  local page=$1 text section
  if command -v man >/dev/null; then
    text=$(MANWIDTH=80 man -l "$page" 2>&1) || return 1
  else
    text=$(groff -man -Tutf8 "$page" 2>&1) || return 1
  fi
  if command -v groff >/dev/null && [ -n "$(groff -man -ww -z -Tutf8 "$page" 2>&1)" ]; then
    groff -man -ww -z -Tutf8 "$page"
    return 1
  fi
  for section in NAME SYNOPSIS DESCRIPTION OPTIONS OUTPUTS 'EXIT STATUS' EXAMPLES 'SEE ALSO' \
    'fssim spectra' 'fssim code generate' 'fssim code analyze' 'fssim code optimize' 'fssim sweep'; do
    grep -q "$section" <<<"$text" || { echo "man page: no '$section'"; return 1; }
  done
  head -n 5 <<<"$text"  # not echo | head: under pipefail, SIGPIPE would fail the check
}

# The installed page's .TH line: the project's version, and the date of the
# last commit that changed docs/fssim.1 (cmake/install.cmake).
check_man_version() {
  local page=$1 build=$2 version date
  version=$(sed -n 's/^CMAKE_PROJECT_VERSION:[A-Z]*=//p' "$build/CMakeCache.txt")
  date=$(git -C "$root" log -1 --format=%cs -- docs/fssim.1 2>/dev/null) || date=""
  grep '^\.TH' "$page"
  grep -q "^\.TH FSSIM 1 \"[0-9-]*\" \"fssim $version\"" "$page" &&
    { [ -z "$date" ] || grep -q "^\.TH FSSIM 1 \"$date\"" "$page"; }
}

# complete_words SCRIPT WORDS...: what the completion offers after WORDS (the
# last word is the one being completed), one per line.
complete_words() {
  local script=$1
  shift
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _fssim; printf "%s\n" "${COMPREPLY[@]}"' \
    _ "$script" "$@"
}

check_completion() {
  local script=$1
  [ "$(complete_words "$script" fssim code '' | sort | tr '\n' ' ')" = "analyze generate optimize " ] &&
    [ "$(complete_words "$script" fssim --mode '' | sort | tr '\n' ' ')" = "analog numerical " ] &&
    [ "$(complete_words "$script" fssim --noise n)" = none ] &&
    complete_words "$script" fssim -i x.png --code ra | grep -x raskar >/dev/null &&
    complete_words "$script" fssim code generate --length 8 '' | grep -x mip >/dev/null &&
    complete_words "$script" fssim sweep --pl | grep -x -- --plot >/dev/null &&
    complete_words "$script" fssim --ver | grep -x -- --version >/dev/null &&
    [ -z "$(complete_words "$script" fssim --velocity '')" ] &&
    complete_words "$script" fssim -i "$root/data/cam" | grep -x "$root/data/camera.png" >/dev/null
}

# The find_package consumer, built against PREFIX.
check_cmake_consumer() {
  local prefix=$1 build=$2
  cmake -S "$root/tests/install/cmake_consumer" -B "$build" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" &&
    cmake --build "$build" &&
    env -u LD_LIBRARY_PATH "$build/cmake_consumer" "$prefix/share/fssim/codes/raskar.txt"
}

# The pkg-config consumer, built against PREFIX; the shared variant's binary
# gets an rpath to the prefix's libdir.
check_pkgconfig_consumer() {
  local prefix=$1 libdir=$2 dir=$3
  cp -r "$root/tests/install/pkgconfig_consumer" "$dir" &&
    PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig" pkg-config --cflags --libs fss &&
    PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig" make -C "$dir" LDFLAGS="-Wl,-rpath,$prefix/$libdir" &&
    env -u LD_LIBRARY_PATH "$dir/pkgconfig_consumer" "$dir/out"
}

# The installed Python package (when the build made one), <platlib>/fss:
# the files of python/fss/ and the compiled module, nothing else; in the
# shared variant the module finds the prefix's libfss.so through its RUNPATH;
# imported from the prefix alone, with the version of the installed fssim,
# and a small simulation (600 x 8 ramp, snapshot, no noise) whose report
# matches its arrays.
check_python() {
  local prefix=$1 build=$2 variant=$3 libdir=$4 python pydir expected installed resolved
  python=$(sed -n 's/^_\{0,1\}Python3_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt" | head -n 1)
  pydir=$(sed -n 's/^FSS_PYTHON_INSTALL_DIR:[A-Z]*=//p' "$build/CMakeCache.txt")
  [[ $pydir == /* ]] || pydir="$prefix/$pydir"
  expected=$( (cd "$root/python/fss" && ls -1 -- *.py *.pyi py.typed 2>/dev/null
    "$python" -c 'import sysconfig; print("_fss" + sysconfig.get_config_var("EXT_SUFFIX"))') | sort)
  installed=$(cd "$pydir/fss" && find . -path ./__pycache__ -prune -o -type f -printf '%P\n' | sort) || return 1
  echo "installed in $pydir/fss: $(echo "$installed" | tr '\n' ' ')"
  [ "$expected" = "$installed" ] || { echo "expected: $(echo "$expected" | tr '\n' ' ')"; return 1; }
  if [ "$variant" = shared ]; then
    readelf -d "$pydir"/fss/_fss*.so | grep -E 'RPATH|RUNPATH'
    resolved=$(env -u LD_LIBRARY_PATH ldd "$pydir"/fss/_fss*.so | sed -n 's/.*libfss\.so[^ ]* => \([^ ]*\).*/\1/p')
    echo "libfss.so => $resolved"
    [ "$(realpath "$resolved")" = "$(realpath "$prefix/$libdir/libfss.so.0.1")" ] || return 1
  fi
  (cd "$work" && env -u LD_LIBRARY_PATH PYTHONPATH="$pydir" FSSIM="$prefix/bin/fssim" "$python" -c '
import os, subprocess, numpy as np, fss
assert os.path.realpath(fss.__file__).startswith(os.path.realpath(os.environ["PYTHONPATH"])), fss.__file__
version = subprocess.run([os.environ["FSSIM"], "--version"], capture_output=True, text=True).stdout
assert version.strip() == "fssim " + fss.__version__, (version, fss.__version__)
image = np.tile((np.arange(600) % 256).astype(np.uint8), (8, 1))
run = fss.simulate(image, code="snapshot", noise="none")
assert run.restored.shape == (8, 600 - 3 * 52) and run.restored.dtype == np.float64
assert run.geometry["output_width"] == 444 and run.report["fssim_version"] == fss.__version__
print("fss", fss.__version__, "from", fss.__file__, "RMSE", run.metrics["rmse"])
')
}

# Checks one variant: static or shared.
test_variant() {
  local variant=$1 build prefix libdir
  prefix="$work/prefix-$variant"
  if [ "$variant" = "$reuse_variant" ]; then
    build=$reuse
    echo "-- $variant: installing the build in $build"
  else
    build=$(mktemp -d "$root/build-install-$variant.XXXXXX")
    fresh_builds+=("$build")
    local shared=OFF
    [ "$variant" = shared ] && shared=ON
    echo "-- $variant: configuring and building in $build"
    check "$variant: configure and build (BUILD_SHARED_LIBS=$shared)" \
      configure_and_build "$build" -DBUILD_SHARED_LIBS=$shared
  fi
  check "$variant: cmake --install --prefix" cmake --install "$build" --prefix "$prefix"
  libdir=$(sed -n 's/^CMAKE_INSTALL_LIBDIR:PATH=//p' "$build/CMakeCache.txt")
  check "$variant: installed files" expect_files "$prefix" "$variant" "${libdir:-lib}"
  if [ "$variant" = shared ]; then
    check "$variant: fssim finds libfss.so through its RUNPATH" check_runpath "$prefix" "$libdir"
  fi
  check "$variant: fssim --version" check_version "$prefix" "$build"
  echo "      $(last_output | tail -n 1)"
  check "$variant: fssim code analyze raskar" check_analyze "$prefix"
  check "$variant: man page" check_man "$prefix/share/man/man1/fssim.1"
  check "$variant: man page names the version" check_man_version "$prefix/share/man/man1/fssim.1" "$build"
  check "$variant: bash completion" check_completion "$prefix/share/bash-completion/completions/fssim"
  check "$variant: find_package(fss) consumer" check_cmake_consumer "$prefix" "$work/cmake-consumer-$variant"
  last_output | grep -E '^(raskar|snapshot|cmake_consumer)' | sed 's/^/      /'
  check "$variant: pkg-config consumer" check_pkgconfig_consumer "$prefix" "$libdir" "$work/pkgconfig-consumer-$variant"
  last_output | grep -E '^(snapshot|pkgconfig_consumer)' | sed 's/^/      /'
  if grep -q '^FSS_BUILD_PYTHON:BOOL=ON' "$build/CMakeCache.txt"; then
    check "$variant: Python package from the prefix" check_python "$prefix" "$build" "$variant" "$libdir"
    last_output | grep -E '^fss ' | sed 's/^/      /'
  else
    echo "skip  $variant: Python module (not built: FSS_BUILD_PYTHON is OFF)"
  fi
}

test_variant static
test_variant shared
echo "test-install: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
