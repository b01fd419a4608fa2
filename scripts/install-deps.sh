#!/usr/bin/env bash
# Installs the Debian packages fssim needs to build, test and benchmark.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libpng-dev libfftw3-dev libcli11-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  jq
  clang libclang-rt-14-dev  # sanitizer and libFuzzer builds (scripts/test-sanitize.sh, fuzz.sh)
)
if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
echo "install-deps: ${#packages[@]} packages installed"
