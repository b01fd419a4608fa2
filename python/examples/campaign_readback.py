#!/usr/bin/env python3
"""A small campaign run from Python and read back: measured RMSE against the prediction.

fss.run_campaign runs three codes at seven velocities on a crop of data/camera.png (written
with fss.write_png), as `fssim campaign` would; fss.read_campaign reads its results.csv back
as a dict of numpy columns. The figure shows each setting's rmse_mean (+/- its standard error
rmse_sd / sqrt(trials)) against the velocity with predicted_rmse as lines, and their difference
in standard errors.

    python3 python/examples/campaign_readback.py [OUTDIR]

writes OUTDIR/campaign/ (the campaign's files) and OUTDIR/campaign_readback.png (default
OUTDIR: out/python-examples/) when matplotlib is installed, and prints the numbers.
"""
import argparse
import pathlib
import shutil

import numpy as np

import fss

SOURCE = pathlib.Path(__file__).resolve().parents[2]
FIGURE = "campaign_readback.png"
CODES = ["raskar", "mip", "sinc"]


def plot(rows, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: figure skipped")
        return False
    fig, (left, right) = plt.subplots(1, 2, figsize=(9.5, 3.8), layout="constrained")
    se = rows["rmse_sd"] / np.sqrt(rows["trials"])
    z = (rows["rmse_mean"] - rows["predicted_rmse"]) / se
    for index, code in enumerate(CODES):
        mine = rows["code"] == code
        v = rows["velocity"][mine]
        color = "C%d" % index
        left.errorbar(v, rows["rmse_mean"][mine], yerr=se[mine], fmt="o", ms=4, capsize=2,
                      color=color, label=code)
        left.plot(v, rows["predicted_rmse"][mine], "-", color=color, lw=1.2)
        right.plot(v + (index - 1) * 0.03, z[mine], "o", ms=4, color=color, label=code)
    left.plot([], [], "ko", ms=4, label="rmse_mean ± SE")
    left.plot([], [], "k-", lw=1.2, label="predicted_rmse")
    left.set_xlabel("velocity (pixels per time slot)")
    left.set_ylabel("RMSE (gray levels)")
    left.set_title("results.csv read back: %d settings, %d trials each"
                   % (z.size, rows["trials"][0]), fontsize=9)
    left.grid(True, alpha=0.3)
    left.legend(fontsize=8)
    right.axhline(0, color="k", lw=0.8)
    for bound in (-2, 2):
        right.axhline(bound, color="k", lw=0.8, ls=":")
    right.set_ylim(-4, 4)
    right.set_xlabel("velocity (pixels per time slot)")
    right.set_ylabel("(rmse_mean − predicted_rmse) / SE")
    right.set_title("measured against predicted, in standard errors (dotted: ±2)", fontsize=9)
    right.grid(True, alpha=0.3)
    right.legend(fontsize=8, ncol=3, loc="lower center")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir", nargs="?", default="out/python-examples",
                        help="folder of the campaign and the figure (default out/python-examples)")
    parser.add_argument("--update-docs", action="store_true",
                        help="also copy the figure to docs/python_" + FIGURE)
    args = parser.parse_args()
    outdir = pathlib.Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)

    crop = outdir / "camera_rows_192_255.png"
    fss.write_png(crop, fss.read_png(SOURCE / "data" / "camera.png")[192:256])
    spec = {"input": str(crop), "code": CODES, "velocity": "0.25:1.75:0.25", "snr": 100,
            "trials": 8, "seed": 1}
    written = fss.run_campaign(spec, outdir / "campaign")  # resumes when already there
    rows = fss.read_campaign(outdir / "campaign")
    same = list(written) == list(rows) and all(
        np.array_equal(column, rows[name], equal_nan=column.dtype.kind == "f")
        for name, column in written.items())
    print("read_campaign: %d rows of %d columns, %s run_campaign returned"
          % (rows["code"].size, len(rows), "as" if same else "NOT as"))

    print("%-7s %8s %20s %10s" % ("code", "velocity", "rmse_mean ± SE", "predicted"))
    for i in range(rows["code"].size):
        se = rows["rmse_sd"][i] / np.sqrt(rows["trials"][i])
        print("%-7s %8.2f %11.4f ± %.4f %10.4f" % (rows["code"][i], rows["velocity"][i],
                                                  rows["rmse_mean"][i], se,
                                                  rows["predicted_rmse"][i]))
    z = (rows["rmse_mean"] - rows["predicted_rmse"]) / (rows["rmse_sd"] / np.sqrt(rows["trials"]))
    print("largest |measured - predicted| / SE: %.2f over %d settings" % (np.abs(z).max(), z.size))
    if plot(rows, outdir / FIGURE):
        print("wrote", outdir / FIGURE)
        if args.update_docs:
            shutil.copyfile(outdir / FIGURE, SOURCE / "docs" / ("python_" + FIGURE))
            print("wrote", SOURCE / "docs" / ("python_" + FIGURE))


if __name__ == "__main__":
    main()
