#!/usr/bin/env bash
# The velocity-robustness study: how well the paper's codes, the best snapshot, the code
# optimized for v = 1 and codes optimized for a distribution of velocities do when the velocity
# is uncertain (docs/velocity-robustness.md; docs/method.md §13).
#
# For L = 52, dt = 1, numerical mode, snr 100 and the inverse filter, it computes
#   the expected SNR at level 100 (100 / sqrt of the error averaged over the distribution,
#   `fssim code analyze --velocity-distribution`) of raskar, sinc, mip, the best box code
#   (1, ..., 1, 0, ..., 0) of n ones (n = 1 ... 52: the best snapshot of n slots), the code
#   `fssim code optimize` finds for v = 1, and the code it finds for the distribution itself,
#   under uniform distributions around v = 1 of widths 0, 0.25, 0.5 and 1 and the normal
#   distribution of mean 1 and sd 0.2 (truncated to [0.2, 1.8]);
#   for each code, the velocities below and above 1 at which its single-velocity SNR at level
#   100 falls below the best snapshot's at that velocity (a scan in steps of 0.01 over
#   [0.01, 1.99]);
#   a figure of the single-velocity SNR at level 100 of those codes against the velocity,
#   relative to the best snapshot's at each velocity.
# The optimizer's default search (24 seeded restarts, seed 0; RESTARTS=N to change).
#
# Usage: scripts/velocity_robustness.sh [--update-docs] [OUT_DIR]
#   OUT_DIR (default out/velocity_robustness, under the checkout) receives
#   velocity_robustness.tsv (expected SNRs), velocity_crossings.tsv (where each code falls
#   below the snapshot), velocity_curves.tsv and velocity_robustness.{png,svg} (the figure)
#   and the optimized codes (codes/). --update-docs also copies the TSVs but the curves, the
#   PNG and the SVG to docs/; nothing else in the checkout is written.
# Needs a built fssim (FSSIM=path to override, default build/fssim), jq and gnuplot
# (scripts/install-deps.sh installs them). JOBS (default 2) processes at once; a few minutes on
# two cores.
set -euo pipefail
source "$(dirname "$0")/study-arguments.sh"
study_arguments velocity_robustness "$@"
jobs=${JOBS:-2}
restarts=${RESTARTS:-24}
[ -x "$fssim" ] || { echo "velocity_robustness: $fssim not found; build first (cmake --build build)" >&2; exit 1; }
for tool in jq gnuplot; do
  command -v "$tool" >/dev/null ||
    { echo "velocity_robustness: $tool not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/codes" "$work/rows" "$work/curves"
distributions=(uniform:1:1 uniform:0.875:1.125 uniform:0.75:1.25 uniform:0.5:1.5 normal:1:0.2)
# The box codes of n ones, one gain a line.
for n in $(seq 1 52); do
  for k in $(seq 1 52); do
    if [ "$k" -le "$n" ]; then echo 1; else echo 0; fi
  done >"$work/codes/box_$n.txt"
done
for name in raskar sinc mip; do cp "$root/codes/$name.txt" "$work/codes/$name.txt"; done

# The optimized codes: for v = 1 and for each distribution (file names without colons).
optimize() {
  local name=$1
  shift
  "$fssim" code optimize -L 52 "$@" --restarts "$restarts" -o "$work/codes/$name.txt" >/dev/null
}
export -f optimize
export fssim work restarts
{
  echo "optimum_v1 -v 1"
  for d in "${distributions[@]}"; do echo "optimum_${d//:/_} --velocity-distribution $d"; done
} | xargs -P "$jobs" -L 1 bash -c 'optimize "$@"' optimize

# snr CODE_FILE MOTION...: the SNR at level 100 (0 when the code is not invertible).
snr() {
  local code=$1
  shift
  "$fssim" code analyze "$code" "$@" --json - | jq -r '.analysis.snr_level100'
}
export -f snr

# One row of the table: the expected SNR of every code under distribution $1.
expected_row() {
  local d=$1 best=0 best_n=0 value n row
  row="$d"
  for name in raskar sinc mip; do row+=$'\t'$(snr "$work/codes/$name.txt" --velocity-distribution "$d"); done
  for n in $(seq 1 52); do
    value=$(snr "$work/codes/box_$n.txt" --velocity-distribution "$d")
    if awk -v s="$value" -v b="$best" 'BEGIN { exit !(s > b) }'; then best=$value; best_n=$n; fi
  done
  row+=$'\t'"$best"$'\t'"$best_n"
  row+=$'\t'$(snr "$work/codes/optimum_v1.txt" --velocity-distribution "$d")
  row+=$'\t'$(snr "$work/codes/optimum_${d//:/_}.txt" --velocity-distribution "$d")
  printf '%s\n' "$row" >"$work/rows/${d//:/_}.tsv"
}
export -f expected_row
printf '%s\n' "${distributions[@]}" | xargs -P "$jobs" -L 1 bash -c 'expected_row "$@"' expected_row

# The single-velocity curves: v = 0.01 ... 1.99, every code, and the best box code there (a box
# of n ones has K = 0 at xi = 2 pi / (n v dt), inside the band once n v dt >= 2: only the
# invertible ones are tried).
curve_row() {
  local v=$1 best=0 value n row
  row=$v
  for name in raskar sinc mip optimum_v1 optimum_uniform_0.5_1.5 optimum_normal_1_0.2; do
    row+=$'\t'$(snr "$work/codes/$name.txt" -v "$v")
  done
  for n in $(seq 1 52); do
    awk -v n="$n" -v v="$v" 'BEGIN { exit !(n * v < 2) }' || break
    value=$(snr "$work/codes/box_$n.txt" -v "$v")
    if awk -v s="$value" -v b="$best" 'BEGIN { exit !(s > b) }'; then best=$value; fi
  done
  printf '%s\t%s\n' "$row" "$best" >"$work/curves/$v.tsv"
}
export -f curve_row
seq 0.01 0.01 1.99 | xargs -P "$jobs" -L 1 bash -c 'curve_row "$@"' curve_row

table="$work/velocity_robustness.tsv"
{
  printf 'distribution\traskar\tsinc\tmip\tbest_box\tbest_box_ones\toptimum_v1\toptimum_distribution\n'
  for d in "${distributions[@]}"; do cat "$work/rows/${d//:/_}.tsv"; done
} >"$table"
curves="$work/velocity_curves.tsv"
{
  printf 'velocity\traskar\tsinc\tmip\toptimum_v1\toptimum_uniform_0.5_1.5\toptimum_normal_1_0.2\tbest_box\n'
  cat "$work/curves/"*.tsv | sort -g
} >"$curves"
[ "$(wc -l <"$curves")" -eq 200 ] || { echo "velocity_robustness: expected 199 velocities" >&2; exit 1; }

# Where each code's curve falls below the best box's: around v = 1, the largest v < 1 and the
# smallest v > 1 with a lower SNR ("none" when it stays above over the scan); "at 1" for both
# when the code is already below at v = 1.
crossings="$work/velocity_crossings.tsv"
awk -F '\t' -v OFS='\t' '
  NR == 1 { for (c = 2; c < NF; ++c) name[c] = $c; last = NF; next }
  { for (c = 2; c < last; ++c) {
      below = $c < $last
      if ($1 < 1 && below) low[c] = $1
      if ($1 == 1 && below) at_one[c] = 1
      if ($1 > 1 && below && !(c in high)) high[c] = $1
  } }
  END {
    print "code", "below_snapshot_under_1", "below_snapshot_over_1"
    for (c = 2; c < last; ++c) {
      if (c in at_one) print name[c], "at 1", "at 1"
      else print name[c], (c in low ? low[c] : "none"), (c in high ? high[c] : "none")
    }
  }' "$curves" >"$crossings"

plot() {
  local terminal=$1 file=$2
  gnuplot <<EOF
set terminal $terminal
set output "$file"
set datafile separator "\t"
set title "SNR at level 100 against the velocity, relative to the best snapshot at that velocity\n(L = 52, dt = 1, numerical mode, snr 100, inverse filter)"
set xlabel "velocity v (pixels per slot)"
set ylabel "SNR at level 100 / best snapshot's (box code of n slots)"
set xrange [0:2]
set yrange [0:1.2]
set ytics 0.1
set grid xtics ytics
set key outside right top
plot 1 with lines lw 3 lc rgb "black" title "best snapshot", \
  "$curves" using 1:(\$2 / \$8) with lines lw 2 lc rgb "#1f77b4" title "raskar", \
  "" using 1:(\$3 / \$8) with lines lw 2 lc rgb "#ff7f0e" title "sinc", \
  "" using 1:(\$4 / \$8) with lines lw 2 lc rgb "#2ca02c" title "mip", \
  "" using 1:(\$5 / \$8) with lines lw 2 dt 2 lc rgb "#d62728" title "optimum for v = 1", \
  "" using 1:(\$6 / \$8) with lines lw 2 lc rgb "#9467bd" title "optimum for uniform:0.5:1.5", \
  "" using 1:(\$7 / \$8) with lines lw 2 dt 4 lc rgb "#8c564b" title "optimum for normal:1:0.2"
EOF
}
plot 'pngcairo size 1200,700 font "DejaVu Sans,10"' "$work/velocity_robustness.png"
plot 'svg size 1200,700 font "DejaVu Sans,10" dynamic background rgb "white"' "$work/velocity_robustness.svg"

mkdir -p "$out/codes"
cp "$work/codes/"optimum_*.txt "$out/codes/"
for file in velocity_robustness.tsv velocity_crossings.tsv velocity_curves.tsv \
  velocity_robustness.png velocity_robustness.svg; do
  cp "$work/$file" "$out/$file"
  if [ "$update_docs" -eq 1 ] && [ "$file" != velocity_curves.tsv ]; then cp "$work/$file" "$root/docs/$file"; fi
done
echo "velocity_robustness: wrote $out/velocity_{robustness,crossings,curves}.tsv, the figure and $out/codes/"
[ "$update_docs" -eq 0 ] || echo "velocity_robustness: updated docs/velocity_{robustness,crossings}.tsv and the figure"
column -t -s $'\t' "$out/velocity_robustness.tsv"
column -t -s $'\t' "$out/velocity_crossings.tsv"
