#!/usr/bin/env bash
# The read noise study of docs/sensor-model.md ("Read noise study"): the SNR at level
# 100 (fssim code analyze, docs/method.md §6 and §10) of the snapshot, the
# raskar code (both modes), the sinc code (numerical) and the numerical and
# analog optima of length 52, at v = 1, dt = 1, against the read noise
# sigma_r = 0, 1, ..., 20 e- RMS per readout, at two light levels:
# snr 100 (lambda2 = 100 photo-electrons per gray level per slot) and snr 20
# (lambda2 = 4). No dark current, no ADC.
#
# The optima: `fssim code optimize` (default search: 24 seeded restarts, seed
# 0) at every read noise value of the grid, in both modes, and in the analog
# mode also at 25, 30 and 40 e-. The column analog_optimum is, at each
# sigma_r, the best SNR at that sigma_r of all the analog codes found (a code
# found at 20 e- may do better at 19 e- than the one found at 19 e-: the
# search is local). It is the best code found, a lower bound on the true
# analog optimum. The numerical optimum does not change with read noise
# (docs/method.md §10: every numerical code's noise is scaled by
# 1 + sigma_r^2 / (100 dt lambda2)); the script checks that the codes found
# at every sigma_r have the same SNR at 0 e- to within 1e-6, and reports the
# one found at 0 e-.
#
# Usage: scripts/read_noise_study.sh [--update-docs] [OUT_DIR]
#   OUT_DIR (default out/read_noise_study, under the checkout) receives
#   read_noise_study.csv and, when gnuplot is installed (scripts/install-deps.sh
#   installs it), the figure read_noise_study.png and read_noise_study.svg.
#   --update-docs also copies the CSV to results/ and the PNG to docs/ (the
#   files docs/sensor-model.md shows); nothing else in the checkout is written.
# Prints the read noise from which an analog code found beats the numerical
# optimum. Needs a built fssim (FSSIM=path to override, default build/fssim)
# and jq. About 2 minutes of one core's time.
set -euo pipefail
source "$(dirname "$0")/study-arguments.sh"
study_arguments read_noise_study "$@"
[ -x "$fssim" ] || { echo "read_noise_study: $fssim not found; build first (cmake -S . -B build && cmake --build build)" >&2; exit 1; }
command -v jq >/dev/null || { echo "read_noise_study: jq not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
mkdir -p "$out"
csv=$out/read_noise_study.csv
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
noise_values=$(seq 0 20)
light_levels="100 20"

# snr_of CODE MODE SNR READ_NOISE: the SNR at level 100.
snr_of() {
  "$fssim" code analyze "$1" --mode "$2" --snr "$3" --read-noise "$4" --json - |
    jq -r '.analysis.snr_level100'
}

# The optimizer at every grid value: $work/<mode>_<snr>_<r>.txt; analog
# codes also at 25, 30 and 40 e-, as candidates only (they let in more light).
for snr in $light_levels; do
  for r in $noise_values; do
    for mode in numerical analog; do
      "$fssim" code optimize -L 52 -v 1 --mode "$mode" --snr "$snr" --read-noise "$r" \
        -o "$work/${mode}_${snr}_$r.txt" >/dev/null
    done
  done
  for r in 25 30 40; do
    "$fssim" code optimize -L 52 -v 1 --mode analog --snr "$snr" --read-noise "$r" \
      -o "$work/analog_${snr}_$r.txt" >/dev/null
  done
  # The numerical codes found under read noise are the noiseless optimum.
  reference=$(snr_of "$work/numerical_${snr}_0.txt" numerical "$snr" 0)
  for r in $noise_values; do
    found=$(snr_of "$work/numerical_${snr}_$r.txt" numerical "$snr" 0)
    awk -v a="$found" -v b="$reference" -v r="$r" 'BEGIN {
      d = a - b; if (d < 0) d = -d
      if (d > 1e-6 * b) { printf "read_noise_study: numerical optimum at %s e- differs: %s vs %s\n", r, a, b > "/dev/stderr"; exit 1 } }'
  done
done

# best_of MODE SNR R: the best SNR at R of the codes found in MODE at SNR,
# and the light (sum of gains) of that code.
best_of() {
  local best=0 light=0 value code
  for code in "$work/$1_$2_"*.txt; do
    value=$("$fssim" code analyze "$code" --mode "$1" --snr "$2" --read-noise "$3" --json - |
      jq -r '[.analysis.snr_level100, .analysis.sum] | @tsv')
    read -r s l <<<"$value"
    if awk -v s="$s" -v b="$best" 'BEGIN { exit !(s > b) }'; then best=$s; light=$l; fi
  done
  echo "$best $light"
}

tmp_csv="$work/study.csv"
echo "snr,read_noise_electrons,snapshot,raskar_numerical,raskar_analog,sinc_numerical,numerical_optimum,analog_optimum,analog_optimum_light_slots" >"$tmp_csv"
for snr in $light_levels; do
  for r in $noise_values; do
    numerical_best=$(snr_of "$work/numerical_${snr}_0.txt" numerical "$snr" "$r")
    read -r analog_best analog_light <<<"$(best_of analog "$snr" "$r")"
    echo "$snr,$r,$(snr_of snapshot numerical "$snr" "$r"),$(snr_of raskar numerical "$snr" "$r"),$(snr_of raskar analog "$snr" "$r"),$(snr_of sinc numerical "$snr" "$r"),$numerical_best,$analog_best,$analog_light" >>"$tmp_csv"
  done
done
mv "$tmp_csv" "$csv"
echo "read_noise_study: wrote $csv"

# Where an analog code overtakes the numerical optimum. With read noise
# alone (dt = 1), c = sigma_r^2 / snr^2 and both noise figures are linear in
# c: numerical (1 + c) N (N = Q M of the numerical optimum), analog
# (Q + c) M, so an analog code with M < N overtakes at
# c = (Q M - N) / (N - M). The smallest over the analog codes found:
for snr in $light_levels; do
  n=$("$fssim" code analyze "$work/numerical_${snr}_0.txt" --json - | jq -r '.analysis.noise_figure')
  for code in "$work/analog_${snr}_"*.txt; do
    "$fssim" code analyze "$code" --mode analog --json - | jq -r '[.analysis.q, .analysis.m] | @tsv'
  done | awk -v n="$n" -v snr="$snr" '
    $2 < n { c = ($1 * $2 - n) / (n - $2); if (!found || c < best) { best = c; q = $1 } found = 1 }
    END {
      if (!found) { printf "snr %s: no analog code found overtakes the numerical optimum\n", snr; exit }
      printf "snr %s: the best analog code found (%.2f slots of light) overtakes the numerical optimum from %.2f e- on (read noise / snr = %.4f)\n", snr, q, snr * sqrt(best), sqrt(best)
    }'
done

# plot_figure TERMINAL FILE: both light levels side by side and one legend
# under them, in a strip of its own (a plot of no data, so that the legend
# has the whole width). The snapshot is a wide gray band under the others:
# the analog optimum and sinc coincide with it at snr 100.
plot_figure() {
  gnuplot <<EOF
set terminal $1
set output "$2"
set datafile separator ","
set style line 1 lw 7 lc rgb "#b0b0b0"
set style line 2 lw 2 lc rgb "#1f77b4"
set style line 3 lw 2 lc rgb "#d62728"
set style line 4 lw 2 dt 2 lc rgb "#2ca02c"
set style line 5 lw 2 dt 3 lc rgb "#1f77b4"
set style line 6 lw 2 dt 3 lc rgb "#d62728"
set multiplot title "SNR at level 100 against read noise (L = 52, v = 1, dt = 1)"
set xlabel "read noise σ_r (e- RMS per readout)"
set ylabel "SNR at level 100"
set grid
unset key
set size 0.5, 0.8
panel = 0
do for [s in "100 20"] {
  set origin 0.5 * panel, 0.14
  panel = panel + 1
  set title sprintf("snr %s (%d photo-electrons per gray level per slot)", s, int(s) * int(s) / 100)
  plot "$csv" using (\$1 == int(s) ? \$2 : NaN):3 with lines ls 1, \
       "" using (\$1 == int(s) ? \$2 : NaN):7 with lines ls 2, \
       "" using (\$1 == int(s) ? \$2 : NaN):8 with lines ls 3, \
       "" using (\$1 == int(s) ? \$2 : NaN):6 with lines ls 4, \
       "" using (\$1 == int(s) ? \$2 : NaN):4 with lines ls 5, \
       "" using (\$1 == int(s) ? \$2 : NaN):5 with lines ls 6
}
set origin 0, 0
set size 1, 0.14
unset title
unset xlabel
unset ylabel
unset tics
unset border
unset grid
set xrange [0:1]
set yrange [0:1]
set key center center horizontal maxrows 2 samplen 4 width 2 box
plot NaN with lines ls 1 title "snapshot (both modes)", \
     NaN with lines ls 2 title "numerical optimum", \
     NaN with lines ls 3 title "analog optimum", \
     NaN with lines ls 4 title "sinc (numerical)", \
     NaN with lines ls 5 title "raskar (numerical)", \
     NaN with lines ls 6 title "raskar (analog)"
unset multiplot
EOF
}

if command -v gnuplot >/dev/null; then
  plot_figure 'pngcairo size 1100,560 font "DejaVu Sans,10"' "$work/study.png"
  plot_figure 'svg size 1100,560 font "DejaVu Sans,10" dynamic background rgb "white"' "$work/study.svg"
  mv "$work/study.png" "$out/read_noise_study.png"
  mv "$work/study.svg" "$out/read_noise_study.svg"
  echo "read_noise_study: wrote $out/read_noise_study.png and .svg"
else
  echo "read_noise_study: gnuplot not found, no plot (scripts/install-deps.sh installs gnuplot-nox)" >&2
fi
if [ "$update_docs" -eq 1 ]; then
  cp "$csv" "$root/results/read_noise_study.csv"
  echo "read_noise_study: updated results/read_noise_study.csv"
  if [ -f "$out/read_noise_study.png" ]; then
    cp "$out/read_noise_study.png" "$root/docs/read_noise_study.png"
    echo "read_noise_study: updated docs/read_noise_study.png"
  fi
fi
