#!/usr/bin/env bash
# Configures with the tests on (FSS_BUILD_TESTS, off in a plain configure),
# builds (Release) and runs the whole test suite with CTest, including the
# install test (scripts/test-install.sh, CTest label install).
# With ccache installed, the compiler runs through it, with a cache of this run
# alone (a temporary directory; CCACHE_DIR instead when it is set): the install
# test's shared build of the library then compiles none of the sources this
# build compiled with the same flags (ccache compares the preprocessed source
# and the flags) instead of building everything a second time.
# Usage: scripts/test.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
jobs=$(nproc 2>/dev/null || echo 2)
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # Paths under the checkout are hashed relative to the build directory, so
  # that the pip build of the package in a clone inside build/
  # (scripts/test-python-install.sh) and the install test's shared build
  # beside build/ reuse these compiles.
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
  if [ -z "${CCACHE_DIR:-}" ]; then
    CCACHE_DIR=$(mktemp -d "${TMPDIR:-/tmp}/fss-ccache.XXXXXX")
    export CCACHE_DIR
    trap 'rm -rf "$CCACHE_DIR"' EXIT
  fi
fi
source scripts/build-flags.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=ON "${launcher[@]}" \
  "${fast_link[@]}" >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
