#!/usr/bin/env bash
# Installs the Debian packages fssim needs to build, test and benchmark.
# Usage: scripts/install-deps.sh [--browser]
#   --browser  also installs chromium, for the test that renders report.html
#              in a headless browser (CI passes it; without it that test skips).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  ccache  # scripts/test.sh: the install test's shared build reuses the Release build's compiles
  libpng-dev libtiff-dev libfftw3-dev libcli11-dev nlohmann-json3-dev
  libisal-dev  # ISA-L: the deflate of the image PNGs (src/io/png_write.cpp)
  libplplot-dev plplot-driver-cairo fonts-dejavu-core
  libgtest-dev libgmock-dev libbenchmark-dev
  jq time
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module fss (python/)
  python3-pil  # with python3-numpy: the numpy column of bench/run.sh (bench/numpy_flutter.py)
  python3-skimage  # the outside check of SSIM (python/tests/test_restoration.py)
  python3-venv  # `python3 -m venv` for pip installs of fss (docs/python.md#installing)
  python3-pip  # pip, which builds and installs the package fssim (pyproject.toml)
  python3-setuptools  # the build backend of pyproject.toml (setup.py), for --no-build-isolation
  python3-wheel  # setuptools 66 makes wheels with it (pip install, pip wheel)
  python3-matplotlib  # the figures of the gallery (python/examples/)
  libgsl-dev  # GSL's normal and Poisson generators, a reference in bench/micro_bench
  strace  # fault injection into output publishing (tests/cli/fault_injection_test.cpp)
  man-db  # the install test renders the installed man page (scripts/test-install.sh)
  clang libclang-rt-14-dev  # sanitizer and libFuzzer builds (scripts/test-sanitize.sh, fuzz.sh)
  lld  # links the test builds faster (scripts/build-flags.sh)
  clang-format clang-tidy  # scripts/lint.sh (version 14, with run-clang-tidy)
  slurmctld slurmd slurm-client munge  # the campaign's single-node Slurm cluster test (label slurm)
  parallel  # the GNU parallel recipe of docs/campaign.md for campaign shards
  gnuplot-nox  # the plot of scripts/read_noise_study.sh (docs/read_noise_study.png)
)
for argument in "$@"; do
  case "$argument" in
    --browser) packages+=(chromium) ;;
    *) echo "install-deps: unknown argument '$argument' (expected --browser)" >&2; exit 2 ;;
  esac
done
if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
echo "install-deps: ${#packages[@]} packages installed"
