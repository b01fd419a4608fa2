#!/usr/bin/env bash
# Builds the whole test suite with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer (CMake option FSS_SANITIZE) and runs it with CTest
# (all but the install test, which checks the package, not the code).
# Usage: scripts/test-sanitize.sh [build-dir]   (default: build-asan)
#
# Any report fails: UBSan stops at the first error (-fno-sanitize-recover=all),
# ASan and LeakSanitizer end the process with exit status 1 after printing
# their report. That covers the fssim processes the end-to-end tests start:
# they check the exit status and that stderr holds exactly the expected line,
# so a report there fails the test too. (abort_on_error would kill with
# SIGABRT instead; exit statuses are easier to read in a test.)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-asan}
jobs=$(nproc 2>/dev/null || echo 2)
if ! command -v clang++ >/dev/null; then
  echo "test-sanitize: clang++ not found (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
export ASAN_OPTIONS=detect_leaks=1:check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Line tables only (-gline-tables-only): the reports' stack traces keep their
# files and lines, and the build compiles about 10% faster than with -g.
source scripts/build-flags.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" "${fast_link[@]}" \
  -DFSS_SANITIZE=ON -DFSS_BUILD_TESTS=ON >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
