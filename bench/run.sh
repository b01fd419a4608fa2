#!/usr/bin/env bash
# Benchmark of fssim against a numpy implementation of the same model
# (bench/numpy_flutter.py): median wall time over RUNS runs (default 5) and
# peak resident memory (GNU time) of fssim with its per-frame photon noise,
# fssim with the aggregated noise (when this fssim has `--noise aggregated`)
# and numpy, on camera.png, astronaut.png, a generated 4000x3000 RGB image
# (bench/make_image) and a 4000x3000 RGB photograph (data/astronaut.png
# resized by bench/scale_image.py, Pillow's LANCZOS filter); the settings per
# second of two campaigns of 100 camera.png settings (`fssim campaign`); the
# runs per second of a Python loop over fss.simulate and over numpy's
# (bench/python_loop.py, LOOP_RUNS calls, default 50; left out when the build
# has no Python module); then numpy's own generators and the micro-benchmarks
# (SKIP_MICRO=1 leaves them out). The slow cases (4000x3000, 100 trials, the
# campaigns) run BIG_RUNS times (default 1): the machine may be shared. Builds
# in Release in build-bench/ (at nice 10).
#
# Prints a Markdown table, and writes the results as tab-separated lines to
# BENCH_RESULTS (default build-bench/results.tsv; a relative path is taken from
# the repository), which bench/report.py turns into docs/performance.md:
#   meta  KEY  VALUE                      date, commit, dirty, cpu, cores,
#                                         memory_gib, runs, big_runs, load_start,
#                                         load_end, fssim_version, note
#   case  NAME  PROGRAM  RUNS  MEDIAN_S  PEAK_MB  ARGUMENTS
#                                         PROGRAM: fssim, fssim-aggregated, numpy
#   campaign  NAME  RUNS  MEDIAN_S  PEAK_MB  SETTINGS  ARGUMENTS
#                                         `fssim campaign ARGUMENTS -o DIR`
#   loop  NAME  PROGRAM  RUNS  RUNS_PER_S  MEDIAN_S  ARGUMENTS
#                                         bench/python_loop.py; PROGRAM: fss, numpy
#   numpy_generator  NAME  M_VARIATES_PER_S
#   micro  NAME  REAL_TIME  TIME_UNIT  ITEMS_PER_SECOND (empty if none)
# BENCH_NOTE, free text, is recorded as the note (the conditions of the run).
# Usage: bench/run.sh            RUNS=3 BIG_RUNS=2 BENCH_NOTE="idle machine" bench/run.sh
set -euo pipefail
export LC_ALL=C  # a dot in $EPOCHREALTIME and in printf
cd "$(dirname "$0")/.."
runs=${RUNS:-5}
big_runs=${BIG_RUNS:-1}
build="build-bench"
results=${BENCH_RESULTS:-$build/results.tsv}
python=/usr/bin/python3  # Debian's, with python3-numpy and python3-pil
[ -x /usr/bin/time ] || { echo "bench: GNU time is needed (apt-get install time)" >&2; exit 1; }
"$python" -c 'import PIL' 2>/dev/null || {
  echo "bench: $python with PIL is needed for the 4000x3000 photograph (apt-get install python3-pil)" >&2
  exit 1
}
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DFSS_BUILD_TESTS=OFF -DFSS_BUILD_BENCH=ON >/dev/null
nice -n 10 cmake --build "$build" -j "$(nproc)" >/dev/null
big=$build/big_4000x3000.png
[ -f "$big" ] || "$build/bench/make_image" 4000 3000 "$big"
photo=$build/astronaut_4000x3000.png
[ -f "$photo" ] || "$python" bench/scale_image.py data/astronaut.png 4000 3000 "$photo"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$(dirname "$results")"
tsv=$out/results.tsv

have_numpy=1
if ! "$python" -c 'import numpy, PIL' 2>/dev/null; then
  have_numpy=0
  echo "bench: numpy column left out: $python lacks numpy or PIL (apt-get install python3-numpy python3-pil)" >&2
fi
# The aggregated noise is an option of newer fssim builds only.
have_aggregated=0
if "$build/fssim" --help | grep -q aggregated; then have_aggregated=1; fi

meta() { printf 'meta\t%s\t%s\n' "$1" "$2" >> "$tsv"; }
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')
meta date "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
meta commit "$(git rev-parse HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git status --porcelain --untracked-files=no 2>/dev/null | head -1)" ]; then
  meta dirty yes
else
  meta dirty no
fi
meta cpu "$cpu"
meta cores "$(nproc)"
meta memory_gib "$(awk '/^MemTotal:/ { printf "%.0f", $2 / 1048576 }' /proc/meminfo)"
meta runs "$runs"
meta big_runs "$big_runs"
meta load_start "$load_start"
meta fssim_version "$("$build/fssim" --version | head -1)"
meta note "${BENCH_NOTE:-}"

# median of the numbers on stdin
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# measure RUNS COMMAND...: prints "median_seconds peak_MB" of COMMAND --outdir DIR
# (of COMMAND $OUTOPT DIR when OUTOPT is set: a fresh DIR each run).
measure() {
  local count=$1; shift
  : > "$out/times"; : > "$out/rss"
  for _ in $(seq "$count"); do
    # Wall time from the shell's microsecond clock (GNU time's %e has only
    # two decimals and drops the third: 0.059 s prints as 0.05), so it
    # includes starting GNU time itself (about a millisecond); peak RSS from
    # GNU time.
    local start=$EPOCHREALTIME
    /usr/bin/time -f "%M" -o "$out/t" "$@" "${OUTOPT:---outdir}" "$out/o" >/dev/null
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
# record NAME PROGRAM RUNS SECONDS MB ARGUMENTS...: one case line of the results.
record() {
  local name=$1 program=$2 count=$3 seconds=$4 megabytes=$5; shift 5
  printf 'case\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$program" "$count" "$seconds" "$megabytes" \
    "$*" >> "$tsv"
}

# row NAME RUNS FSSIM_ARGS...: one line of the table; the numpy program takes
# the same arguments but --no-plots (it draws no plots). NUMPY=0 before the
# call leaves numpy out of that row. numpy's figures are kept by its
# arguments, so the rows of a case with and without plots share one
# measurement (a 4000x3000 numpy run takes one to two minutes).
declare -A numpy_seen
row() {
  local name=$1 count=$2; shift 2
  local frame agg="n/a" numpy="n/a" speed="" agg_speed="" result
  # Assigned apart from `local` so that a failing run stops the script.
  result=$(measure "$count" "$build/fssim" "$@")
  read -r ft fm <<< "$result"
  frame=$(cell "$ft" "$fm")
  record "$name" fssim "$count" "$ft" "$fm" "$@"
  if [ "$have_aggregated" = 1 ] && [[ " $* " == *" numerical "* ]]; then
    result=$(measure "$count" "$build/fssim" "$@" --noise aggregated)
    read -r at am <<< "$result"
    agg=$(cell "$at" "$am")
    record "$name" fssim-aggregated "$count" "$at" "$am" "$@" --noise aggregated
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
    record "$name" numpy "$count" "$nt" "$nm" "${numpy_args[@]}"
    speed=$(ratio "$nt" "$ft")
    [ "$agg" = "n/a" ] || agg_speed=$(ratio "$nt" "$at")
  fi
  printf '| %s | %s | %s | %s | %s | %s |\n' "$name" "$frame" "$agg" "$numpy" "$speed" "$agg_speed"
}

echo "fssim benchmark, $(nproc) cores, $cpu, median of $runs runs ($big_runs for the slow cases)"
[ "$have_aggregated" = 1 ] || echo "(this fssim has no --noise aggregated: that column is n/a)"
echo
echo "| case (raskar, v = 1, snr 100) | fssim per-frame | fssim aggregated | numpy per-frame | numpy / fssim | numpy / aggregated |"
echo "|---|---:|---:|---:|---:|---:|"
camera=(--input data/camera.png --code raskar)
astronaut=(--input data/astronaut.png --code raskar)
generated=(--input "$big" --code raskar)
photograph=(--input "$photo" --code raskar)
row "camera.png 512x512 gray, numerical" "$runs" "${camera[@]}" --mode numerical
row "camera.png, numerical, no plots" "$runs" "${camera[@]}" --mode numerical --no-plots
row "camera.png, analog" "$runs" "${camera[@]}" --mode analog
row "camera.png, analog, no plots" "$runs" "${camera[@]}" --mode analog --no-plots
row "astronaut.png 512x512 RGB, numerical" "$runs" "${astronaut[@]}" --mode numerical
row "astronaut.png, numerical, no plots" "$runs" "${astronaut[@]}" --mode numerical --no-plots
row "4000x3000 RGB (generated), numerical" "$big_runs" "${generated[@]}" --mode numerical
row "4000x3000 RGB (generated), numerical, no plots" "$big_runs" "${generated[@]}" --mode numerical --no-plots
row "4000x3000 RGB (photograph), numerical" "$big_runs" "${photograph[@]}" --mode numerical
row "4000x3000 RGB (photograph), numerical, no plots" "$big_runs" "${photograph[@]}" --mode numerical --no-plots
NUMPY=0 row "camera.png, numerical, 100 trials" "$big_runs" "${camera[@]}" --mode numerical --trials 100
echo
echo "fssim draws its plots (code.png, spectrum.png) but in the no-plots rows; the numpy program"
echo "draws none. Both write the observed, restored, residual and ground-truth PNGs."
# campaign_row NAME RUNS SETTINGS CAMPAIGN_ARGS...: settings per second of
# `fssim campaign CAMPAIGN_ARGS`, a fresh directory each run.
campaign_row() {
  local name=$1 count=$2 settings=$3 result; shift 3
  result=$(OUTOPT=--output measure "$count" "$build/fssim" campaign --no-progress "$@")
  read -r ct cm <<< "$result"
  printf 'campaign\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$count" "$ct" "$cm" "$settings" "$*" \
    >> "$tsv"
  awk -v n="$name" -v s="$settings" -v t="$ct" -v m="$cm" \
    'BEGIN { printf "| %s | %d | %.3f s, %d MB | %.1f |\n", n, s, t, m, s / t }'
}
echo
echo "| campaign (camera.png, raskar, numerical) | settings | fssim campaign | settings per second |"
echo "|---|---:|---:|---:|"
campaign_row "100 velocities 0.5:1.49:0.01, snr 100" "$big_runs" 100 \
  -i data/camera.png -c raskar -m numerical --snr 100 -v 0.5:1.49:0.01
campaign_row "100 snr values 1:100:1, v = 1" "$big_runs" 100 \
  -i data/camera.png -c raskar -m numerical --snr 1:100:1 -v 1
# A Python loop over fss.simulate (the module built into build-bench/python).
echo
if PYTHONPATH=$build/python "$python" -c 'import fss' 2>/dev/null; then
  loop_numpy=${LOOP_RUNS:-50}
  [ "$have_numpy" = 1 ] || loop_numpy=0
  PYTHONPATH=$build/python "$python" bench/python_loop.py --input data/camera.png --code raskar \
    --mode numerical --runs "${LOOP_RUNS:-50}" --numpy-runs "$loop_numpy" --results "$tsv"
else
  echo "bench: Python loop left out: $build has no Python module (needs pybind11-dev, python3-dev)" >&2
fi
# numpy's own generators, per variate: the floor a numpy user starts from.
if [ "$have_numpy" = 1 ]; then
  echo
  "$python" - "$tsv" <<'PY'
import sys
import time
import numpy as np
rng = np.random.default_rng(0)
lam = 100.0 * (20.0 + (np.arange(4000) * 37 % 230))  # a row at snr 100, as micro_bench's
with open(sys.argv[1], "a") as results:
    for name, draw in (("standard_normal", lambda: rng.standard_normal(4000)),
                       ("poisson (row at snr 100)", lambda: rng.poisson(lam))):
        draw()
        best = float("inf")
        for _ in range(5):
            start = time.perf_counter()
            for _ in range(200):
                draw()
            best = min(best, time.perf_counter() - start)
        rate = 200 * 4000 / best / 1e6
        print(f"numpy Generator.{name}: {rate:.0f} M variates/s")
        print(f"numpy_generator\t{name}\t{rate:.1f}", file=results)
PY
fi
if [ "${SKIP_MICRO:-0}" != 1 ]; then
  echo
  "$build/bench/micro_bench" --benchmark_counters_tabular=true \
    --benchmark_out="$out/micro.json" --benchmark_out_format=json
  "$python" - "$out/micro.json" >> "$tsv" <<'PY'
import json
import sys
with open(sys.argv[1]) as f:
    for b in json.load(f)["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration":
            continue  # aggregates of repetitions
        items = b.get("items_per_second")
        print("\t".join(["micro", b["name"], repr(b["real_time"]), b["time_unit"],
                         "" if items is None else repr(items)]))
PY
fi
meta load_end "$(cut -d' ' -f1-3 /proc/loadavg)"
cp "$tsv" "$results"
echo
echo "bench: results in $results (bench/report.py renders docs/performance.md from them)"
