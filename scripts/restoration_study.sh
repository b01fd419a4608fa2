#!/usr/bin/env bash
# The restoration study: how much SNR a fluttered code gains over the best
# snapshot, for the inverse filter and for a Wiener restoration with a
# power-law prior, against the light level and the read noise
# (docs/designing-codes.md, "Under a Wiener or Tikhonov restoration";
# docs/method.md §12).
#
# For L = 52, v = 1, dt = 1, both modes (numerical, analog), read noise 0 and
# 4 e- RMS per readout, snr 5, 10, 20, 50, 100, 200, 500, 1000 and the two
# criteria (--restoration inverse; --restoration wiener with the default prior
# power-law:2:180), it computes
#   optimized: the SNR at level 100 of the code `fssim code optimize` finds
#              (default search: 24 seeded restarts, seed 0; RESTARTS=N to
#              change), re-analysed by `fssim code analyze`;
#   best box:  the best SNR at level 100 of the box codes (1, ..., 1, 0, ...,
#              0) of n ones, n = 1 ... 52, under the same criterion, mode,
#              sensor and snr: the best snapshot (a longer exposure);
#   gain:      optimized / best box.
# Under the inverse filter the box codes of n >= 2 ones are not invertible at
# v = 1 (K vanishes at xi = 2 pi / n), so the best box is the one-slot
# snapshot.
#
# Usage: scripts/restoration_study.sh [--update-docs] [OUT_DIR]
#   OUT_DIR (default out/restoration_study, under the checkout) receives
#   restoration_study.tsv, restoration_study.png and restoration_study.svg,
#   and the optimized codes (codes/). --update-docs also copies the TSV, the
#   PNG and the SVG to docs/; nothing else in the checkout is written.
# Needs a built fssim (FSSIM=path to override, default build/fssim), jq and
# gnuplot (scripts/install-deps.sh installs them). JOBS (default 2) cases run
# at once; about 5 minutes on two cores.
set -euo pipefail
source "$(dirname "$0")/study-arguments.sh"
study_arguments restoration_study "$@"
jobs=${JOBS:-2}
restarts=${RESTARTS:-24}
[ -x "$fssim" ] || { echo "restoration_study: $fssim not found; build first (cmake --build build)" >&2; exit 1; }
for tool in jq gnuplot; do
  command -v "$tool" >/dev/null ||
    { echo "restoration_study: $tool not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/boxes" "$work/codes" "$work/rows"
# The box codes of n ones, one gain a line.
for n in $(seq 1 52); do
  for k in $(seq 1 52); do
    if [ "$k" -le "$n" ]; then echo 1; else echo 0; fi
  done >"$work/boxes/box_$n.txt"
done

# run_case MODE READ_NOISE RESTORATION SNR: one row of the table in
# $work/rows/, the optimized code in $work/codes/.
run_case() {
  local mode=$1 noise=$2 restoration=$3 snr=$4
  local name="${mode}_${noise}_${restoration}_${snr}"
  local setting=(--mode "$mode" --snr "$snr" --read-noise "$noise" --restoration "$restoration")
  "$fssim" code optimize -L 52 -v 1 "${setting[@]}" --restarts "$restarts" \
    -o "$work/codes/$name.txt" >/dev/null
  local optimized light
  read -r optimized light < <("$fssim" code analyze "$work/codes/$name.txt" "${setting[@]}" --json - |
    jq -r '[.analysis.snr_level100, .analysis.sum] | @tsv')
  local best=0 best_n=0 snapshot="" value n
  for n in $(seq 1 52); do
    value=$("$fssim" code analyze "$work/boxes/box_$n.txt" "${setting[@]}" --json - |
      jq -r '.analysis.snr_level100')
    [ "$n" -eq 1 ] && snapshot=$value
    if awk -v s="$value" -v b="$best" 'BEGIN { exit !(s > b) }'; then
      best=$value
      best_n=$n
    fi
  done
  awk -v OFS='\t' -v m="$mode" -v r="$noise" -v c="$restoration" -v s="$snr" -v o="$optimized" \
    -v l="$light" -v n="$best_n" -v b="$best" -v p="$snapshot" \
    'BEGIN { print m, r, c, s, o, l, n, b, o / b, p }' >"$work/rows/$name.tsv"
}
export -f run_case
export fssim work restarts

for mode in numerical analog; do
  for noise in 0 4; do
    for restoration in inverse wiener; do
      for snr in 5 10 20 50 100 200 500 1000; do
        echo "$mode $noise $restoration $snr"
      done
    done
  done
done | xargs -P "$jobs" -L 1 bash -c 'run_case "$@"' run_case

table="$work/restoration_study.tsv"
{
  printf 'mode\tread_noise_electrons\trestoration\tsnr\toptimized_snr100\toptimized_light_slots\tbest_box_ones\tbest_box_snr100\tgain\tsnapshot_snr100\n'
  cat "$work/rows/"*.tsv | sort -t $'\t' -k1,1r -k2,2n -k3,3 -k4,4n
} >"$table"
[ "$(wc -l <"$table")" -eq 65 ] || { echo "restoration_study: expected 64 rows" >&2; exit 1; }

# One figure: the gain against snr, one panel per mode and read noise, the two
# criteria in each.
plot() {
  local terminal=$1 file=$2
  gnuplot <<EOF
set terminal $terminal
set output "$file"
set datafile separator "\t"
set multiplot layout 2,2 title "Gain of the optimized code over the best box code (snapshot of n slots), L = 52, v = 1, dt = 1"
set logscale x
set xrange [4:1250]
set xtics ("5" 5, "10" 10, "20" 20, "50" 50, "100" 100, "200" 200, "500" 500, "1000" 1000)
set mxtics 10
set yrange [0.995:1.025]
set ytics 0.005 format "%.3f"
set xlabel "snr (SNR of a level-100 landscape through one slot)"
set ylabel "gain: optimized / best box"
set grid xtics ytics
set key below horizontal
do for [m in "numerical analog"] {
  do for [r in "0 4"] {
    set title sprintf("%s, read noise %s e-", m, r)
    plot 1 with lines lc rgb "gray" dt 2 notitle, \
      "$table" using (strcol(1) eq m && strcol(2) eq r && strcol(3) eq "inverse" ? \$4 : NaN):9 \
        with linespoints lw 2 pt 6 ps 1.4 lc rgb "#1f77b4" title "inverse filter", \
      "" using (strcol(1) eq m && strcol(2) eq r && strcol(3) eq "wiener" ? \$4 : NaN):9 \
        with linespoints lw 2 dt 2 pt 5 ps 0.6 lc rgb "#d62728" title "Wiener, power-law prior (gamma 2, C 180)"
  }
}
unset multiplot
EOF
}
plot 'pngcairo size 1200,900 font "DejaVu Sans,10"' "$work/restoration_study.png"
plot 'svg size 1200,900 font "DejaVu Sans,10" dynamic background rgb "white"' "$work/restoration_study.svg"

mkdir -p "$out/codes"
cp "$work/codes/"*.txt "$out/codes/"
for file in restoration_study.tsv restoration_study.png restoration_study.svg; do
  cp "$work/$file" "$out/$file"
  if [ "$update_docs" -eq 1 ]; then cp "$work/$file" "$root/docs/$file"; fi
done
echo "restoration_study: wrote $out/restoration_study.{tsv,png,svg} and $out/codes/"
[ "$update_docs" -eq 0 ] || echo "restoration_study: updated docs/restoration_study.{tsv,png,svg}"
column -t -s $'\t' "$out/restoration_study.tsv"
