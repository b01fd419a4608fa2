#!/usr/bin/env bash
# Configures with the tests on (FSS_BUILD_TESTS, off in a plain configure),
# builds (Release) and runs the whole test suite with CTest, including the
# install test (scripts/test-install.sh, CTest label install).
# Usage: scripts/test.sh [build-dir]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=ON >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
