#!/usr/bin/env bash
# Installs the Python package fss (distribution fssim) from a fresh clone of
# this checkout as docs/python.md#installing tells a Debian user to: a venv
# with the system's site packages, `pip install --no-build-isolation .` with no
# package index (Debian's setuptools, wheel and numpy only), then the wheel
# path: `pip wheel --no-build-isolation --no-deps .` installed into a second,
# fresh venv. Each install must import fss from the venv, hold every file of
# python/fss/ and the compiled module, match the build's module to the last
# bit (a simulation of a crop of data/camera.png) and in its help text, and
# leave the clone's `git status` clean.
#
# Usage: scripts/test-python-install.sh [--build DIR] [--worktree] [--keep]
#   --build DIR  the build (default: build) whose module DIR/python the installs
#                are compared with, whose interpreter (Python3_EXECUTABLE)
#                makes the venvs, and whose compiler launcher the pip build
#                uses (scripts/test.sh's ccache: with CCACHE_BASEDIR set to a
#                directory holding the checkout, the pip build compiles none
#                of the sources DIR compiled, since its clone is made inside
#                DIR and its CMake build is build-python-pip/ at the clone's
#                top, one level down as DIR is: the same relative paths).
#   --worktree   copy the working tree (tracked and untracked files, as on
#                disk, but not the ignored ones) instead of cloning HEAD, to
#                try uncommitted changes; CTest's test clones.
#   --keep       leave the temporary directory (printed) for inspection.
# Prints one line per check and "test-python-install: N passed, M failed";
# exits 1 on a failure, 77 (skipped) when the checkout is not a git
# repository (a source tarball) and --worktree is not given.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build
worktree=0
keep=0
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$(realpath "${2:?--build needs a directory}"); shift 2 ;;
    --worktree) worktree=1; shift ;;
    --keep) keep=1; shift ;;
    *) echo "test-python-install: unknown argument '$1' (expected --build DIR, --worktree or --keep)" >&2; exit 2 ;;
  esac
done
cache=$build/CMakeCache.txt
[ -f "$cache" ] || { echo "test-python-install: $build is not a CMake build directory" >&2; exit 2; }
grep -q '^FSS_BUILD_PYTHON:BOOL=ON' "$cache" ||
  { echo "test-python-install: $build does not build the Python module (FSS_BUILD_PYTHON)" >&2; exit 2; }
python=$(sed -n 's/^_\{0,1\}Python3_EXECUTABLE:[A-Z]*=//p' "$cache" | head -n 1)
launcher=$(sed -n 's/^CMAKE_CXX_COMPILER_LAUNCHER:[A-Z]*=//p' "$cache")
if [ "$worktree" -eq 0 ] && ! git -C "$root" rev-parse --verify -q HEAD >/dev/null; then
  echo "test-python-install: skipped: $root is not a git checkout (use --worktree)"
  exit 77
fi

# Inside the build directory: see --build.
work=$(mktemp -d "$build/python-install.XXXXXX")
if [ "$keep" -eq 1 ]; then
  echo "test-python-install: working in $work (kept)"
else
  trap 'rm -rf "$work"' EXIT
fi
source=$work/fssim

# pip as on a machine with Debian's packages only: no index, no other
# configuration, its cache in the temporary directory.
unset PIP_FIND_LINKS PIP_INDEX_URL PIP_EXTRA_INDEX_URL PIP_REQUIRE_VIRTUALENV
export PIP_NO_INDEX=1 PIP_CONFIG_FILE=/dev/null PIP_CACHE_DIR=$work/pip-cache
export PIP_DISABLE_PIP_VERSION_CHECK=1 PYTHONDONTWRITEBYTECODE=1
export CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc 2>/dev/null || echo 2)}
if [ -n "$launcher" ]; then
  export CMAKE_ARGS="-DCMAKE_CXX_COMPILER_LAUNCHER=$launcher${CMAKE_ARGS:+ $CMAKE_ARGS}"
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

# The source: a clone of HEAD, or the working tree's files.
get_source() {
  if [ "$worktree" -eq 1 ]; then
    mkdir "$source" &&
      (cd "$root" && git ls-files -z --cached --others --exclude-standard |
        while IFS= read -r -d '' file; do
          [ -e "$file" ] && printf '%s\0' "$file"  # a deleted file is still listed
        done | xargs -0 cp --parents -t "$source")
  else
    git clone -q "$root" "$source" && git -C "$source" checkout -q --detach "$(git -C "$root" rev-parse HEAD)"
  fi
}

# make_venv [--without-pip] DIR: as docs/python.md says.
make_venv() { "$python" -m venv --system-site-packages "$@"; }

# The smoke check run by VENV_PYTHON (with PYTHONPATH unset) or by the build's
# interpreter with PYTHONPATH=$build/python: prints what the installs must
# share with the build, one fact a line.
smoke() {
  local interpreter=$1 pythonpath=${2:-}
  (cd "$work" && env -u PYTHONPATH ${pythonpath:+PYTHONPATH="$pythonpath"} \
    "$interpreter" -c '
import hashlib, pydoc, sys
import numpy as np
import fss
image = np.ascontiguousarray(fss.read_png(sys.argv[1])[224:256, :])
run = fss.simulate(image, code="raskar", velocity=1, snr=100, seed=3, trials=2)
for name in ("observed", "restored", "groundtruth"):
    array = np.ascontiguousarray(getattr(run, name))
    print(name, array.shape, array.dtype, hashlib.sha256(array.tobytes()).hexdigest())
print("metrics", sorted(run.metrics.items()))
text = pydoc.render_doc(fss.simulate, renderer=pydoc.plaintext)
assert "simulate(" in text and "Parameters" in text, text[:500]
print("help", hashlib.sha256(text.encode()).hexdigest(), len(text))
print("version", fss.__version__.split()[0])
' "$root/data/camera.png")
}

# check_install VENV: fss comes from VENV's site packages, holds the files of
# python/fss/ and the compiled module, and computes as the build's module.
check_install() {
  local venv=$1 package expected installed
  package=$("$venv/bin/python" -c 'import os, fss; print(os.path.dirname(os.path.realpath(fss.__file__)))' 2>&1) ||
    { echo "$package"; return 1; }
  echo "fss from $package"
  [[ $package == "$(realpath "$venv")"/lib/python3*/site-packages/fss ]] || return 1
  expected=$( (cd "$source/python/fss" && ls -1 -- *.py *.pyi py.typed 2>/dev/null
    "$venv/bin/python" -c 'import sysconfig; print("_fss" + sysconfig.get_config_var("EXT_SUFFIX"))') | sort)
  installed=$(cd "$package" && find . -path ./__pycache__ -prune -o -type f -printf '%P\n' | sort)
  echo "installed: $(echo "$installed" | tr '\n' ' ')"
  [ "$expected" = "$installed" ] || { echo "expected: $(echo "$expected" | tr '\n' ' ')"; return 1; }
  smoke "$venv/bin/python" >"$work/smoke.$(basename "$venv")" || { cat "$work/smoke.$(basename "$venv")"; return 1; }
  diff "$work/smoke.build" "$work/smoke.$(basename "$venv")"
}

# The clone is as it was: nothing but ignored files added (build-python-pip/).
check_clean() {
  local status
  status=$(git -C "$source" status --porcelain) || return 1
  echo "$status"
  [ -z "$status" ] && [ ! -e "$source/build" ]
}

install_package() { (cd "$source" && "$work/venv/bin/pip" install --no-build-isolation .); }
make_wheel() { (cd "$source" && "$work/venv/bin/pip" wheel --no-build-isolation --no-deps . -w "$work/wheels"); }
install_wheel() { "$work/venv-wheel/bin/python" -m pip install "$work"/wheels/fssim-*.whl; }

echo "-- interpreter $python, pip build in $source/build-python-pip${launcher:+ through $launcher}"
if [[ $launcher == *ccache* ]] && [ -z "${CCACHE_BASEDIR:-}" ]; then
  echo "note: CCACHE_BASEDIR is unset: the pip build compiles everything again"
fi
check "source: $([ "$worktree" -eq 1 ] && echo "working tree copied" || echo "clone of HEAD")" get_source
check "the build's module: simulate a crop of data/camera.png" smoke "$python" "$build/python"
cp "$work/log.$((passed + failed - 1))" "$work/smoke.build"
check "python3 -m venv --system-site-packages" make_venv "$work/venv"
check "pip install --no-build-isolation . (no index)" install_package
check "installed package imports and matches the build" check_install "$work/venv"
check "pip wheel --no-build-isolation --no-deps ." make_wheel
if [ "$worktree" -eq 0 ]; then
  check "the clone's git status is clean" check_clean
else
  echo "skip  the clone's git status (a copy of the working tree, not a clone)"
fi
# Without a pip of its own: Debian's, from the system's site packages, installs
# the wheel (ensurepip's copy of pip and setuptools takes seconds).
check "a fresh venv" make_venv --without-pip "$work/venv-wheel"
check "pip install the wheel (no index)" install_wheel
check "the wheel's package imports and matches the build" check_install "$work/venv-wheel"
echo "test-python-install: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
