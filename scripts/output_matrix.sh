#!/usr/bin/env bash
# Records, or checks, every output byte of a matrix of fssim runs: the guard of
# every refactor ("behaviour identical" means these bytes do not change).
#
#   scripts/output_matrix.sh record FSSIM RECORD_FILE   run the matrix, write the record
#   scripts/output_matrix.sh check  FSSIM RECORD_FILE   run it again, compare, exit 1 on a difference
#
# FSSIM is the binary to run (e.g. build/fssim). The record lists, for every
# case, the SHA-256 of each file it wrote, of its stdout and stderr, and its exit
# status. Record with the build before a refactor, check with the build after.
# The runs take about a minute on two cores. report.json names the build
# (fssim_version, with its git commit): that one line is removed before the
# file is hashed, so that two commits with the same behaviour compare equal.
# KEEP=DIR keeps every case's outputs in DIR (for a closer look at a
# difference: scripts/compare_outputs.py compares two such folders by pixels
# and numbers).
# A record is only comparable on the same machine kind (PNG plots depend on the
# installed PLplot, cairo and zlib, the image PNGs on ISA-L and, without
# SSE4.2, on the processor). A change of the PNG encoder changes the image
# PNGs' bytes but not their pixels: compare two KEEP folders with
# build/bench/png_same_pixels (libpng, 16-bit samples exactly).
set -euo pipefail
if [ $# -ne 3 ] || { [ "$1" != record ] && [ "$1" != check ]; }; then
  echo "usage: $0 record|check FSSIM RECORD_FILE" >&2
  exit 2
fi
action=$1
fssim=$(realpath "$2")
record=$(realpath -m "$3")
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/in" "$work/cases"
cp "$root/data/camera.png" "$root/data/astronaut.png" "$work/in/"
cp "$root/codes/mip.txt" "$work/in/mip.txt"
printf '0.5 1 0.25\n1; 0.75\n' >"$work/in/short.txt"

# Each case: a name, then the arguments. Inputs are referred to relatively
# (../../in/...), outputs go to the case's own folder, so nothing in the bytes
# depends on where the matrix runs.
cases=(
  "camera_default|--input ../../in/camera.png --outdir out"
  "camera_noisefree|--input ../../in/camera.png --noise none --outdir out"
  "camera_analog|--input ../../in/camera.png --mode analog --outdir out --seed 3"
  "camera_analog_v-1|--input ../../in/camera.png --mode analog --velocity -1 --outdir out"
  "camera_sinc_dt05|--input ../../in/camera.png --code sinc --dt 0.5 --outdir out --no-plots"
  "camera_mip_v037|--input ../../in/camera.png --code mip --velocity 0.37 --snr 200 --outdir out"
  "camera_random_v073|--input ../../in/camera.png --code random --velocity -0.73 --outdir out --no-plots"
  "camera_snapshot|--input ../../in/camera.png --code snapshot --outdir out --no-plots"
  "camera_accumulation|--input ../../in/camera.png --code accumulation --outdir out"
  "camera_fast|--input ../../in/camera.png --code snapshot --velocity 1.6 --rmse-margin 10 --outdir out --no-plots"
  "camera_trials|--input ../../in/camera.png --trials 3 --seed 11 --outdir out --no-plots"
  "camera_sheet_report|--input ../../in/camera.png --sheet --report --outdir out"
  "camera_restore_velocity|--input ../../in/camera.png --restore-velocity 1.05 --outdir out --no-plots"
  "camera_codefile|--input ../../in/camera.png --code ../../in/short.txt --mode analog --outdir out --no-plots"
  "camera_snr5|--input ../../in/camera.png --snr 5 --code sinc --outdir out --no-plots"
  "camera_threads1|--input ../../in/camera.png --threads 1 --outdir out"
  "camera_aggregated|--input ../../in/camera.png --noise aggregated --code mip --velocity 0.37 --trials 3 --outdir out --no-plots"
  "camera_aggregated_knuth|--input ../../in/camera.png --noise aggregated --snr 5 --read-noise 4 --dark-current 1 --trials 2 --outdir out --no-plots"
  "camera_sensor|--input ../../in/camera.png --read-noise 3 --full-well 20000 --adc-bits 10 --adc-gain 4 --outdir out --no-plots"
  "astronaut_default|--input ../../in/astronaut.png --outdir out"
  "astronaut_analog_sheet|--input ../../in/astronaut.png --mode analog --sheet --report --outdir out"
  "astronaut_mip_noisefree|--input ../../in/astronaut.png --code mip --velocity 0.37 --noise none --outdir out --no-plots"
  "astronaut_trials|--input ../../in/astronaut.png --code sinc --dt 0.5 --trials 2 --outdir out --no-plots"
  "camera_depth16|--input ../../in/camera.png --png-depth 16 --outdir out --no-plots"
  "astronaut_depth16_sheet|--input ../../in/astronaut.png --png-depth 16 --sheet --outdir out --no-plots"
  "err_not_png|--input ../../in/short.txt --outdir out"
  "err_analog_gain|--input ../../in/camera.png --code random --mode analog --outdir out"
  "err_bad_snr|--input ../../in/camera.png --snr -1 --outdir out"
  "err_missing_input|--outdir out"
  "spectra_five|spectra --output spectra.png snapshot raskar random mip sinc"
  "spectra_linear|spectra --output s.png --linear -v 0.5 --dt 2 --width 300 --height 200 --title T raskar ../../in/mip.txt"
  "generate_sinc|code generate sinc --length 52"
  "generate_mip_file|code generate mip --length 40 --velocity 0.8 --output mip40.txt"
  "generate_random|code generate random --length 20 --seed 5 --analog"
  "analyze_raskar|code analyze raskar"
  "analyze_grid_json|code analyze mip --velocity 0.37 --grid 920 --json a.json"
  "analyze_analog|code analyze ../../in/short.txt --mode analog --snr 50"
  "optimize_small|code optimize --length 8 --velocity 1 --restarts 3 --iterations 50 --output opt.txt"
  "optimize_binary|code optimize --length 10 --velocity 1 --binary --restarts 2 --iterations 40"
  "sweep_velocity|sweep --input ../../in/camera.png --velocity 0.5:1.5:0.5 --output sweep.csv --plot sweep.png"
  "sweep_snr|sweep --input ../../in/camera.png --code raskar --mode analog --snr 50:150:50 --trials 2 --output sweep.csv"
  "err_sweep_range|sweep --input ../../in/camera.png --velocity 1:0:1 --output sweep.csv"
)

manifest="$work/manifest"
: >"$manifest"
for entry in "${cases[@]}"; do
  name=${entry%%|*}
  read -r -a args <<<"${entry#*|}"
  dir="$work/cases/$name"
  mkdir -p "$dir"
  status=0
  (cd "$dir" && "$fssim" "${args[@]}" >../"$name.stdout" 2>../"$name.stderr" </dev/null) || status=$?
  mv "$work/cases/$name.stdout" "$work/cases/$name.stderr" "$dir/"
  while IFS= read -r -d '' report; do
    grep -v '"fssim_version"' "$report" >"$report.tmp" || true
    mv "$report.tmp" "$report"
  done < <(find "$dir" -name report.json -print0)
  echo "$name exit $status" >>"$manifest"
  (cd "$dir" && find . -type f -print0 | sort -z | xargs -0 sha256sum | sed "s|^|$name |") >>"$manifest"
done

if [ -n "${KEEP:-}" ]; then
  mkdir -p "$KEEP"
  cp -a "$work/cases/." "$KEEP/"
fi
if [ "$action" = record ]; then
  cp "$manifest" "$record"
  echo "output_matrix: recorded ${#cases[@]} cases, $(wc -l <"$record") lines, in $record"
  exit 0
fi
if diff -u "$record" "$manifest" >"$work/diff"; then
  echo "output_matrix: ${#cases[@]} cases, every byte identical to $record"
else
  cat "$work/diff"
  echo "output_matrix: differences from $record (above)" >&2
  exit 1
fi
