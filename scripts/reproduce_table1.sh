#!/usr/bin/env bash
# Reproduces the comparison of the paper's Table 1 with one campaign:
# numerical flutter shutter, v = 1, snr = 100, the paper's six codes, TRIALS
# noise realizations each (each code's seeds derive from the campaign seed 0).
# Usage: scripts/reproduce_table1.sh [--update-docs] [-o OUT_DIR] [IMAGE] [TRIALS]
#   IMAGE    default data/camera.png        TRIALS  default 20
#   OUT_DIR  default out/table1 (under the checkout, ignored by git) receives
#            table1.csv (the campaign's results.csv, docs/campaign.md),
#            table1.md (the table, with the paper's figures beside), the
#            figure sheets sheet_<code>.png (observed | restored | residual,
#            as the paper's Figures 9-14), spectra_overlay.png (|K| of the
#            five invertible codes, as Figures 2-7) and the campaign
#            directory campaign_<image>_<trials>, kept: a rerun resumes it.
#   --update-docs  (with the defaults IMAGE and TRIALS only) also copies
#            table1.csv, table1.md, sheet_raskar.png and spectra_overlay.png
#            to results/, the files README.md and docs/designing-codes.md
#            show; without it nothing in the checkout but OUT_DIR is written.
# On camera.png it checks the RMSE against the reference program's (fssim
# campaign check, tests/fixtures/table1_reference.csv). Needs a built fssim
# (FSSIM=path to override, default build/fssim).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
usage="usage: scripts/reproduce_table1.sh [--update-docs] [-o OUT_DIR] [IMAGE] [TRIALS]"
update_docs=0
out=""
positional=()
while [ $# -gt 0 ]; do
  case "$1" in
    --update-docs) update_docs=1; shift ;;
    -o | --output)
      [ $# -ge 2 ] || { echo "reproduce_table1: $1 needs a directory ($usage)" >&2; exit 2; }
      out=$2; shift 2 ;;
    -h | --help) sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;;
    -*) echo "reproduce_table1: unknown option $1 ($usage)" >&2; exit 2 ;;
    *) positional+=("$1"); shift ;;
  esac
done
[ ${#positional[@]} -le 2 ] || { echo "reproduce_table1: at most IMAGE and TRIALS ($usage)" >&2; exit 2; }
image=${positional[0]:-data/camera.png}
trials=${positional[1]:-20}
# Paths given relative to where the script was started; then it works from the checkout.
[ -z "$out" ] || out=$(realpath -m -- "$out")
# An image in the checkout keeps a relative name: the results name it.
[ ${#positional[@]} -eq 0 ] || image=$(realpath -m --relative-base="$root" -- "$image")
fssim=$(realpath -m -- "${FSSIM:-$root/build/fssim}")
cd "$root"
out=${out:-$root/out/table1}
[ -x "$fssim" ] || { echo "reproduce_table1: $fssim not found; build first (cmake -S . -B build && cmake --build build)" >&2; exit 1; }
[ -f "$image" ] || { echo "reproduce_table1: image '$image' not found" >&2; exit 1; }
case "$trials" in ''|*[!0-9]*|0) echo "reproduce_table1: TRIALS must be a positive integer, got '$trials'" >&2; exit 2;; esac
case "$image" in *,*|*\"*) echo "reproduce_table1: the image path must not hold a comma or a quote" >&2; exit 2;; esac
if [ "$update_docs" = 1 ] && { [ "$image" != data/camera.png ] || [ "$trials" != 20 ]; }; then
  echo "reproduce_table1: --update-docs writes the docs' table of data/camera.png with 20 trials; give no other IMAGE or TRIALS" >&2
  exit 2
fi
codes=(snapshot raskar random mip sinc accumulation)
name=$(basename "$image")
campaign=$out/campaign_${name%.*}_$trials
mkdir -p "$out"

# The table: one campaign.
"$fssim" campaign -i "$image" -c "${codes[@]}" --mode numerical --velocity 1 --snr 100 --dt 1 \
  --trials "$trials" --seed 0 -o "$campaign"

# table1.md from its results.csv. The paper's Table 1 (House image,
# numerical, v = 1, snr = 100): RMSE / RMSE_CI.
awk -F, -v image="$name" -v trials="$trials" '
  function f(x) { return x == "inf" || x == "" ? "∞" : sprintf("%.3f", x) }
  function big(x) { return x + 0 > 1e6 ? sprintf("~1e%d", int(log(x) / log(10))) : f(x) }
  BEGIN {
    paper["snapshot"] = "1.34 / 1.33"; paper["raskar"] = "2.34 / 3.14"; paper["random"] = "2.01 / 2.48"
    paper["mip"] = "2.11 / 2.10"; paper["sinc"] = "1.33 / 1.33"; paper["accumulation"] = "not invertible"
    printf "# Table 1 reproduced: %s, numerical flutter shutter, v = 1, snr = 100, %d trials per code\n\n", image, trials
    print "| code | ‖α‖₁/sup\\|α\\| | RMSE (mean ± sd) | RMSE_CI (mean ± sd) | predicted RMSE | noise-free RMSE | SNR at level 100 | paper (House) RMSE / RMSE_CI |"
    print "|---|---:|---:|---:|---:|---:|---:|---:|"
  }
  NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
  {
    code = $col["code"]
    predicted = $col["status"] == "ok" ? f($col["predicted_rmse"]) : "∞ (not invertible)"
    printf "| %s | %s | %s ± %s | %s ± %s | %s | %s | %s | %s |\n", code, f($col["code_normalized_l1"]),
      big($col["rmse_mean"]), big($col["rmse_sd"]), big($col["rmse_ci_mean"]), big($col["rmse_ci_sd"]),
      predicted, big($col["predicted_rmse_noise_free"]), f($col["snr_level100"]), paper[code]
  }
  END {
    print ""
    print "Measured: mean ± sample sd over the trials of each setting (seeds from the campaign seed 0, docs/campaign.md). Predicted: the exact expectation sqrt(E[MSE]) = sqrt(RMSE_0² + noise part), docs/method.md §6b; SNR at level 100: the stationary, image-independent figure of merit, §6."
    print "The paper'"'"'s column is for the House image, which is not bundled; on camera.png the reference program gives"
    print "snapshot 1.355, raskar 2.352, random 1.993, sinc 1.354, mip 2.116 (mean of 12 runs)."
  }' "$campaign/results.csv" > "$out/table1.md.tmp"
mv "$out/table1.md.tmp" "$out/table1.md"
cp "$campaign/results.csv" "$out/table1.csv.tmp"
mv "$out/table1.csv.tmp" "$out/table1.csv"

# On camera.png, the reference program's figures (mean of 12 runs) as a check.
if [ "$name" = camera.png ]; then
  "$fssim" campaign check "$campaign/results.csv" tests/fixtures/table1_reference.csv --k-se 4 >&2 ||
    echo "reproduce_table1: warning: the RMSE departs from the reference program's (above)" >&2
fi

# The figures: each code's sheet (first trial of a run with seed 0) and the spectra.
sheets=$(mktemp -d)
trap 'rm -rf "$sheets"' EXIT
for code in "${codes[@]}"; do
  "$fssim" --input "$image" --code "$code" --mode numerical --velocity 1 --snr 100 --seed 0 \
    --sheet --no-plots --outdir "$sheets/$code" >/dev/null 2>&1
  cp "$sheets/$code/sheet.png" "$out/sheet_$code.png.tmp" && mv "$out/sheet_$code.png.tmp" "$out/sheet_$code.png"
done
"$fssim" spectra --velocity 1 --dt 1 --output "$out/spectra_overlay.png" \
  snapshot raskar random mip sinc >/dev/null
echo "reproduce_table1: wrote table1.md, table1.csv, sheet_<code>.png and spectra_overlay.png into $out" >&2

# The copies the docs show.
if [ "$update_docs" = 1 ]; then
  for f in table1.csv table1.md sheet_raskar.png spectra_overlay.png; do
    cp "$out/$f" "results/$f.tmp" && mv "results/$f.tmp" "results/$f"
  done
  echo "reproduce_table1: updated results/table1.csv, table1.md, sheet_raskar.png and spectra_overlay.png" >&2
fi
