#!/usr/bin/env bash
# The paper's six codes on camera.png under each restoration (docs/restoration-study.md):
# a campaign of 6 codes x 4 restorations (inverse; Tikhonov at its optimal lambda; Wiener with
# the power-law prior and with the oracle prior) x snr 10 and 100, numerical mode, v = 1,
# 10 trials each, then one Markdown table a snr: the mean RMSE over the trials with its
# standard error and, in brackets, the exact prediction sqrt(E[MSE]). Ten trials show the
# sizes, not a test of the prediction (tests/pipeline/restoration_prediction_test.cpp is one).
# About a minute and a half on two cores.
#
#   scripts/restoration_comparison.sh [OUTDIR]    (default out/restoration_comparison)
#
# FSSIM names the binary (default build/fssim).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
fssim=${FSSIM:-$root/build/fssim}
outdir=${1:-$root/out/restoration_comparison}
if [ ! -x "$fssim" ]; then
  echo "restoration_comparison: $fssim is not an executable (build first, or set FSSIM)" >&2
  exit 2
fi
"$fssim" campaign -i "$root/data/camera.png" \
  -c snapshot accumulation raskar random mip sinc \
  --restoration inverse,tikhonov,wiener --prior power-law,oracle \
  --snr 10,100 --trials 10 --no-progress -o "$outdir" >&2
python3 - "$outdir/results.csv" <<'PYTHON'
import csv
import math
import sys

rows = list(csv.DictReader(open(sys.argv[1], newline="")))
codes = ["snapshot", "accumulation", "raskar", "random", "mip", "sinc"]
variants = [("inverse", ""), ("tikhonov", ""), ("wiener", "power-law:2"), ("wiener", "oracle")]
titles = ["inverse", "Tikhonov, optimal λ", "Wiener, power-law prior", "Wiener, oracle prior"]
for snr in ["10", "100"]:
    print(f"\nsnr {snr}: mean RMSE of 10 trials ± its standard error (exact prediction)\n")
    print("| code | " + " | ".join(titles) + " |")
    print("|---|" + "---:|" * len(titles))
    for code in codes:
        cells = []
        for method, prior in variants:
            row = next(r for r in rows if r["code"] == code and r["snr"] == snr
                       and r["restoration"] == method and r["prior"] == prior)
            predicted = row["predicted_rmse"]
            finite = predicted and math.isfinite(float(predicted))
            predicted = f"{float(predicted):.3f}" if finite else "none"
            se = float(row["rmse_sd"]) / math.sqrt(float(row["trials"]))
            cells.append(f"{float(row['rmse_mean']):.3f} ± {se:.3f} ({predicted})")
        print(f"| {code} | " + " | ".join(cells) + " |")
PYTHON
