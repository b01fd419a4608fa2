#!/usr/bin/env bash
# Benchmark of fssim: median wall time over RUNS runs (default 5) and peak
# resident memory (GNU time) for the four cases of the performance issue,
# then the micro-benchmarks. Builds in Release in build-bench/.
# Usage: bench/run.sh            RUNS=3 bench/run.sh
set -euo pipefail
export LC_ALL=C  # a dot in $EPOCHREALTIME and in printf
cd "$(dirname "$0")/.."
runs=${RUNS:-5}
build=build-bench
[ -x /usr/bin/time ] || { echo "bench: GNU time is needed (apt-get install time)" >&2; exit 1; }
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=OFF -DFSS_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
big=$build/big_4000x3000.png
[ -f "$big" ] || "$build/bench/make_image" 4000 3000 "$big"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# median of the numbers on stdin
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

measure() {  # name, then fssim arguments
  local name=$1; shift
  : > "$out/times"; : > "$out/rss"
  for _ in $(seq "$runs"); do
    # Wall time from the shell's microsecond clock (GNU time's %e has only
    # two decimals and drops the third: 0.059 s prints as 0.05), so it
    # includes starting GNU time itself (about a millisecond); peak RSS from
    # GNU time.
    local start=$EPOCHREALTIME
    /usr/bin/time -f "%M" -o "$out/t" "$build/fssim" "$@" --outdir "$out/o" >/dev/null
    local end=$EPOCHREALTIME
    awk -v s="$start" -v e="$end" 'BEGIN { printf "%.3f\n", e - s }' >> "$out/times"
    cat "$out/t" >> "$out/rss"
    rm -rf "$out/o"
  done
  printf '| %s | %s s | %s MB |\n' "$name" "$(median < "$out/times")" \
    "$(awk '{ if ($1 > m) m = $1 } END { printf "%.0f", m / 1024 }' "$out/rss")"
}

echo "fssim benchmark, $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $runs runs each"
echo
echo "| case | median wall | peak RSS |"
echo "|---|---:|---:|"
measure "1. camera.png 512x512 gray, numerical, raskar, v=1, snr=100" --input data/camera.png --code raskar --mode numerical
measure "2. camera.png, analog, raskar" --input data/camera.png --code raskar --mode analog
measure "3. astronaut.png 512x512 RGB, numerical, raskar" --input data/astronaut.png --code raskar --mode numerical
measure "4. 4000x3000 RGB (generated), numerical, raskar" --input "$big" --code raskar --mode numerical
echo
"$build/bench/micro_bench" --benchmark_counters_tabular=true
