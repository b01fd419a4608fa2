#!/usr/bin/env bash
# fssim's performance targets, each measured side by side: paired runs of two
# programs A and B, interleaved (pair i runs A then B, pair i + 1 B then A),
# whole-process wall time from the shell's microsecond clock; for each case
# the median time of A, of B, and the median of the per-pair ratios A / B,
# against its target:
#   a. camera.png numerical, default options (plots): A bench/numpy_flutter.py
#      (no plots, it draws none), B NEW                          A / B >= 15
#   b. camera.png numerical --noise none --no-plots: A BASE, B NEW   A / B >= 3
#   c. camera.png analog (plots): A the reference program ($REFERENCE), B NEW
#      (skipped without REFERENCE)                                A / B >= 30
#   d. fssim campaign, camera.png, raskar, numerical, snr 100, velocities
#      0.5:1.49:0.01 (100 settings): A BASE, B NEW; A / B is the ratio of
#      settings per second                                        A / B >= 2
#      NEW runs with $CAMPAIGN_OPTIONS (default --rmse-margin -1
#      --skip-unrunnable): the same work as a BASE without the automatic
#      margin, which runs 58 of the settings and finds 42 too narrow for the
#      3B margin. CAMPAIGN_OPTIONS= (empty) runs all 100 under the auto margin.
#   e. the 4000x3000 photograph (bench/run.sh's), raskar, numerical: A NEW
#      --noise aggregated, B NEW --noise none                     A / B <= 1.3
# Every case uses the raskar code, velocity 1 (but d), snr 100, seed 0.
# Environment:
#   BASE       the fssim to compare with (required), e.g. a build of an older commit
#   NEW        the fssim measured (default build-bench/fssim)
#   REFERENCE  a shell command line running the reference program on camera.png
#              in analog mode with its plots (evaluated by bash from the
#              repository root; $TARGETS_OUT is a scratch directory for its files)
#   PAIRS      pairs of the cases a to d (default 5), after one unpaired warm-up
#              run of each program in a to c
#   BIG_PAIRS  pairs of case e (default 2)
#   CAMPAIGN_OPTIONS  NEW's options in case d (see d)
#   CASES      the letters of the cases to run (default abcde)
# Writes nothing into the repository but build-bench/astronaut_4000x3000.png
# (made as bench/run.sh makes it, when missing); outputs go to a temporary
# directory, removed at exit. The figures mean something only on an otherwise
# idle machine: the load average is printed at the start and at the end.
# Usage: BASE=../old/build/fssim bench/targets.sh
# shellcheck disable=SC2317 # side_a and side_b are called by name, through wall
set -euo pipefail
export LC_ALL=C  # a dot in $EPOCHREALTIME and in printf
cd "$(dirname "$0")/.."
python=/usr/bin/python3
new=${NEW:-build-bench/fssim}
base=${BASE:-}
pairs=${PAIRS:-5}
big_pairs=${BIG_PAIRS:-2}
cases=${CASES:-abcde}
fail() { echo "targets: $*" >&2; exit 2; }
[ -n "$base" ] || fail "BASE is needed: the fssim to compare with (BASE=PATH bench/targets.sh)"
[ -x "$base" ] || fail "BASE=$base: not an executable"
[ -x "$new" ] || fail "NEW=$new: not an executable (build it: bench/run.sh, or cmake --build build-bench)"
[[ "$pairs" =~ ^[1-9][0-9]*$ ]] || fail "PAIRS=$pairs: expected a positive integer"
[[ "$big_pairs" =~ ^[1-9][0-9]*$ ]] || fail "BIG_PAIRS=$big_pairs: expected a positive integer"
[[ "$cases" =~ ^[a-e]+$ ]] || fail "CASES=$cases: expected letters among a, b, c, d and e"
# wanted LETTER: whether the case LETTER is among CASES.
wanted() { [[ "$cases" == *"$1"* ]]; }
photo=build-bench/astronaut_4000x3000.png
if wanted e && [ ! -f "$photo" ]; then
  mkdir -p build-bench
  "$python" bench/scale_image.py data/astronaut.png 4000 3000 "$photo"
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export TARGETS_OUT=$out/reference

median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

# wall FUNCTION: runs FUNCTION (its output directory $out/o, fresh) and prints
# its wall time in seconds; a failing run stops the script.
wall() {
  rm -rf "$out/o" "$TARGETS_OUT"
  mkdir -p "$TARGETS_OUT"
  local start=$EPOCHREALTIME
  "$1" > "$out/log" 2>&1 || { cat "$out/log" >&2; echo "targets: $1 failed" >&2; exit 1; }
  local end=$EPOCHREALTIME
  awk -v s="$start" -v e="$end" 'BEGIN { printf "%.4f\n", e - s }'
}

# compare NAME COUNT WARMUP TARGET_OP TARGET A_LABEL B_LABEL: COUNT interleaved
# pairs of the functions side_a and side_b (after one unpaired run of each if
# WARMUP is 1); appends the case's row to $out/table and leaves the medians of
# A and B in last_a and last_b.
compare() {
  local name=$1 count=$2 warmup=$3 op=$4 target=$5 a_label=$6 b_label=$7 a b
  if [ "$warmup" = 1 ]; then wall side_a >/dev/null; wall side_b >/dev/null; fi
  : > "$out/pairs"
  for i in $(seq "$count"); do
    if [ $((i % 2)) = 1 ]; then
      a=$(wall side_a); b=$(wall side_b)
    else
      b=$(wall side_b); a=$(wall side_a)
    fi
    echo "$a $b" >> "$out/pairs"
  done
  local ma mb mr
  ma=$(cut -d' ' -f1 "$out/pairs" | median)
  mb=$(cut -d' ' -f2 "$out/pairs" | median)
  mr=$(awk '{ printf "%.6f\n", $1 / $2 }' "$out/pairs" | median)
  last_a=$ma last_b=$mb
  awk -v n="$name" -v al="$a_label" -v bl="$b_label" -v a="$ma" -v b="$mb" -v r="$mr" \
      -v op="$op" -v t="$target" -v c="$count" 'BEGIN {
    met = (op == ">=") ? (r >= t) : (r <= t)
    printf "| %s | %d | %s %.3f s | %s %.3f s | %.2fx | %s %sx | %s |\n", n, c, al, a, bl, b, r,
           (op == ">=") ? "≥" : "≤", t, met ? "met" : "not met"
  }' >> "$out/table"
}

camera=(--input data/camera.png --code raskar)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
: > "$out/table"
: > "$out/notes"

if wanted a; then
  side_a() { "$python" bench/numpy_flutter.py "${camera[@]}" --mode numerical --outdir "$out/o"; }
  side_b() { "$new" "${camera[@]}" --mode numerical --outdir "$out/o"; }
  compare "a. camera.png numerical, default options" "$pairs" 1 ">=" 15 numpy NEW
fi

if wanted b; then
  side_a() { "$base" "${camera[@]}" --mode numerical --noise none --no-plots --outdir "$out/o"; }
  side_b() { "$new" "${camera[@]}" --mode numerical --noise none --no-plots --outdir "$out/o"; }
  compare "b. camera.png numerical, --noise none --no-plots" "$pairs" 1 ">=" 3 BASE NEW
fi

if wanted c && [ -n "${REFERENCE:-}" ]; then
  side_a() { (eval "$REFERENCE"); }
  side_b() { "$new" "${camera[@]}" --mode analog --outdir "$out/o"; }
  compare "c. camera.png analog, plots" "$pairs" 1 ">=" 30 reference NEW
elif wanted c; then
  echo "| c. camera.png analog, plots | | skipped (no reference program) | | | ≥ 30x | |" \
    >> "$out/table"
fi

if wanted d; then
  campaign=(campaign --no-progress -i data/camera.png -c raskar -m numerical --snr 100
            -v 0.5:1.49:0.01)
  side_a() { "$base" "${campaign[@]}" -o "$out/o"; }
  read -r -a campaign_options <<< "${CAMPAIGN_OPTIONS---rmse-margin -1 --skip-unrunnable}"
  side_b() { "$new" "${campaign[@]}" "${campaign_options[@]}" -o "$out/o"; }
  compare "d. campaign of 100 settings (settings/s B / A)" "$pairs" 0 ">=" 2 BASE NEW
  awk -v a="$last_a" -v b="$last_b" 'BEGIN {
    printf "d: BASE %.1f settings/s, NEW %.1f settings/s (100 settings / median wall time)\n",
           100 / a, 100 / b }' >> "$out/notes"
fi

if wanted e; then
  photograph=(--input "$photo" --code raskar --mode numerical)
  side_a() { "$new" "${photograph[@]}" --noise aggregated --outdir "$out/o"; }
  side_b() { "$new" "${photograph[@]}" --noise none --outdir "$out/o"; }
  compare "e. 4000x3000 photograph, aggregated / noise-free" "$big_pairs" 0 "<=" 1.3 \
    aggregated none
fi

echo "fssim targets, side by side: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "NEW  $new: $("$new" --version | head -1)"
echo "BASE $base: $("$base" --version | head -1)"
echo "load average (1, 5, 15 min): $load_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end"
echo "pairs: $pairs (a to d), $big_pairs (e); times are medians of wall time, the ratio the median of A / B per pair"
echo
echo "| case | pairs | A median | B median | median ratio A / B | target | |"
echo "|---|---:|---:|---:|---:|---:|---|"
cat "$out/table"
if [ -s "$out/notes" ]; then echo; cat "$out/notes"; fi
