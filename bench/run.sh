#!/usr/bin/env bash
# Benchmark of fssim against a numpy implementation of the same model
# (bench/numpy_flutter.py): median wall time over RUNS runs (default 5) and
# peak resident memory (GNU time) of fssim with its per-frame photon noise,
# fssim with the aggregated noise (when this fssim has `--noise aggregated`)
# and numpy, on camera.png, astronaut.png and a generated 4000x3000 RGB image;
# then the micro-benchmarks (SKIP_MICRO=1 leaves them out). The slow cases
# (4000x3000, 100 trials) run BIG_RUNS times (default 1): the machine may be
# shared. Builds in Release in build-bench/.
# Usage: bench/run.sh            RUNS=3 BIG_RUNS=2 bench/run.sh
set -euo pipefail
export LC_ALL=C  # a dot in $EPOCHREALTIME and in printf
cd "$(dirname "$0")/.."
runs=${RUNS:-5}
big_runs=${BIG_RUNS:-1}
build="build-bench"
python=/usr/bin/python3  # Debian's, with python3-numpy and python3-pil
[ -x /usr/bin/time ] || { echo "bench: GNU time is needed (apt-get install time)" >&2; exit 1; }
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=OFF -DFSS_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
big=$build/big_4000x3000.png
[ -f "$big" ] || "$build/bench/make_image" 4000 3000 "$big"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

have_numpy=1
if ! "$python" -c 'import numpy, PIL' 2>/dev/null; then
  have_numpy=0
  echo "bench: numpy column left out: $python lacks numpy or PIL (apt-get install python3-numpy python3-pil)" >&2
fi
# The aggregated noise is an option of newer fssim builds only.
have_aggregated=0
if "$build/fssim" --help | grep -q aggregated; then have_aggregated=1; fi

# median of the numbers on stdin
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# measure RUNS COMMAND...: prints "median_seconds peak_MB" of COMMAND --outdir DIR.
measure() {
  local count=$1; shift
  : > "$out/times"; : > "$out/rss"
  for _ in $(seq "$count"); do
    # Wall time from the shell's microsecond clock (GNU time's %e has only
    # two decimals and drops the third: 0.059 s prints as 0.05), so it
    # includes starting GNU time itself (about a millisecond); peak RSS from
    # GNU time.
    local start=$EPOCHREALTIME
    /usr/bin/time -f "%M" -o "$out/t" "$@" --outdir "$out/o" >/dev/null
    local end=$EPOCHREALTIME
    awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f\n", e - s }' >> "$out/times"
    cat "$out/t" >> "$out/rss"
    rm -rf "$out/o"
  done
  printf '%s %s\n' "$(median < "$out/times")" \
    "$(awk '{ if ($1 > m) m = $1 } END { printf "%.0f", m / 1024 }' "$out/rss")"
}

cell() { awk -v t="$1" -v m="$2" 'BEGIN { printf "%.3f s, %d MB", t, m }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1fx", a / b }'; }

# row NAME RUNS FSSIM_ARGS...: one line of the table; the numpy program takes
# the same arguments but --no-plots (it draws no plots). NUMPY=0 before the
# call leaves numpy out of that row. numpy's figures are kept by its
# arguments, so the rows of a case with and without plots share one
# measurement (the 4000x3000 numpy run takes about 95 s).
declare -A numpy_seen
row() {
  local name=$1 count=$2; shift 2
  local frame agg="n/a" numpy="n/a" speed="" agg_speed="" result
  # Assigned apart from `local` so that a failing run stops the script.
  result=$(measure "$count" "$build/fssim" "$@")
  read -r ft fm <<< "$result"
  frame=$(cell "$ft" "$fm")
  if [ "$have_aggregated" = 1 ] && [[ " $* " == *" numerical "* ]]; then
    result=$(measure "$count" "$build/fssim" "$@" --noise aggregated)
    read -r at am <<< "$result"
    agg=$(cell "$at" "$am")
  fi
  if [ "$have_numpy" = 1 ] && [ "${NUMPY:-1}" = 1 ]; then
    local numpy_args=()
    for argument in "$@"; do [ "$argument" = --no-plots ] || numpy_args+=("$argument"); done
    local key="${numpy_args[*]}"
    if [ -z "${numpy_seen[$key]:-}" ]; then
      numpy_seen[$key]=$(measure "$count" "$python" bench/numpy_flutter.py "${numpy_args[@]}")
    fi
    read -r nt nm <<< "${numpy_seen[$key]}"
    numpy=$(cell "$nt" "$nm")
    speed=$(ratio "$nt" "$ft")
    [ "$agg" = "n/a" ] || agg_speed=$(ratio "$nt" "$at")
  fi
  printf '| %s | %s | %s | %s | %s | %s |\n' "$name" "$frame" "$agg" "$numpy" "$speed" "$agg_speed"
}

echo "fssim benchmark, $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), median of $runs runs ($big_runs for the slow cases)"
[ "$have_aggregated" = 1 ] || echo "(this fssim has no --noise aggregated: that column is n/a)"
echo
echo "| case (raskar, v = 1, snr 100) | fssim per-frame | fssim aggregated | numpy per-frame | numpy / fssim | numpy / aggregated |"
echo "|---|---:|---:|---:|---:|---:|"
camera=(--input data/camera.png --code raskar)
astronaut=(--input data/astronaut.png --code raskar)
generated=(--input "$big" --code raskar)
row "camera.png 512x512 gray, numerical" "$runs" "${camera[@]}" --mode numerical
row "camera.png, numerical, no plots" "$runs" "${camera[@]}" --mode numerical --no-plots
row "camera.png, analog" "$runs" "${camera[@]}" --mode analog
row "camera.png, analog, no plots" "$runs" "${camera[@]}" --mode analog --no-plots
row "astronaut.png 512x512 RGB, numerical" "$runs" "${astronaut[@]}" --mode numerical
row "astronaut.png, numerical, no plots" "$runs" "${astronaut[@]}" --mode numerical --no-plots
row "4000x3000 RGB (generated), numerical" "$big_runs" "${generated[@]}" --mode numerical
row "4000x3000 RGB, numerical, no plots" "$big_runs" "${generated[@]}" --mode numerical --no-plots
NUMPY=0 row "camera.png, numerical, 100 trials" "$big_runs" "${camera[@]}" --mode numerical --trials 100
echo
echo "fssim draws its plots (code.png, spectrum.png) but in the no-plots rows; the numpy program"
echo "draws none. Both write the observed, restored, residual and ground-truth PNGs."
# numpy's own generators, per variate: the floor a numpy user starts from.
if [ "$have_numpy" = 1 ]; then
  echo
  "$python" - <<'PY'
import time
import numpy as np
rng = np.random.default_rng(0)
lam = 100.0 * (20.0 + (np.arange(4000) * 37 % 230))  # a row at snr 100, as micro_bench's
for name, draw in (("standard_normal", lambda: rng.standard_normal(4000)),
                   ("poisson (row at snr 100)", lambda: rng.poisson(lam))):
    draw()
    best = float("inf")
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(200):
            draw()
        best = min(best, time.perf_counter() - start)
    print(f"numpy Generator.{name}: {200 * 4000 / best / 1e6:.0f} M variates/s")
PY
fi
if [ "${SKIP_MICRO:-0}" != 1 ]; then
  echo
  "$build/bench/micro_bench" --benchmark_counters_tabular=true
fi
