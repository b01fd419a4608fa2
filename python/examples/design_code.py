#!/usr/bin/env python3
"""A code designed for one velocity, analyzed and simulated against the paper's (raskar).

fss.optimize_code searches the binary code of 52 time slots with at least 26 open (the light
raskar's code collects) that maximizes the SNR at level 100 at velocity 1, the stationary
figure of merit of docs/designing-codes.md; fss.analyze_code gives both codes' figures, and
fss.simulate checks both on a crop of data/camera.png: the measured RMSE beside the exact
prediction, split into its noise part (which the design lowers) and its noise-free part (the
restoration's error without noise, which the figure of merit does not count). The figure
shows both codes, their |K(xi)| and their restorations' errors without noise.

    python3 python/examples/design_code.py [OUTDIR]

writes OUTDIR/design_code.png (default OUTDIR: out/python-examples/) when matplotlib is
installed, and prints the numbers.
"""
import argparse
import pathlib
import shutil

import numpy as np

import fss

SOURCE = pathlib.Path(__file__).resolve().parents[2]
FIGURE = "design_code.png"
VELOCITY = 1.0
SNR = 100
TRIALS = 10
ROWS = slice(160, 288)


def plot(codes, runs, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: figure skipped")
        return False
    xi = np.linspace(0, np.pi, 1001)
    fig, axes = plt.subplots(2, 2, figsize=(10, 5.6), layout="constrained",
                             gridspec_kw={"height_ratios": [0.8, 1]})
    strips_axis, k_axis = axes[0]
    names = list(codes)
    strips = np.array([codes[n] for n in names])
    strips_axis.imshow(strips, cmap="gray_r", vmin=0, vmax=1, aspect="auto",
                       interpolation="nearest",
                       extent=(-0.5, strips.shape[1] - 0.5, len(names) - 0.5, -0.5))
    strips_axis.set_yticks(range(len(names)), names)
    strips_axis.set_xlabel("time slot")
    strips_axis.set_title("the codes (black: open, gain 1; white: closed)", fontsize=9)
    for index, name in enumerate(names):
        k = np.abs(fss.transfer_function(codes[name], xi, velocity=VELOCITY))
        k_axis.plot(xi, k, color="C%d" % index, lw=1, label="%s (min %.2f)" % (name, k.min()))
    k_axis.set_yscale("log")
    k_axis.set_xlabel("frequency ξ (radians per pixel)")
    k_axis.set_ylabel("|K(ξ)|")
    k_axis.set_title("transfer function at v = %g pixel per time slot" % VELOCITY, fontsize=9)
    k_axis.set_xlim(0, np.pi)
    k_axis.grid(True, which="both", alpha=0.3)
    k_axis.legend(fontsize=8)
    for axis, name in zip(axes[1], names):
        r, clean = runs[name]
        error = axis.imshow(clean.restored - clean.groundtruth, cmap="RdBu_r", vmin=-30,
                            vmax=30, interpolation="antialiased")
        for column in r.geometry["rmse_columns"]:  # the RMSE window [first, last)
            axis.axvline(column - 0.5, color="k", lw=0.8, ls="--")
        p = r.prediction
        axis.set_title("%s without noise: restored − true, RMSE %.2f\n"
                       "predicted with noise: %.2f = √(%.2f² + %.2f² noise)"
                       % (name, clean.metrics["rmse"], p["rmse"], p["rmse_noise_free"],
                          p["noise"]), fontsize=9)
        axis.set_xlabel("output column (dashed: the RMSE window)")
        axis.set_ylabel("row")
    fig.colorbar(error, ax=axes[1], shrink=0.8, label="error (gray levels)")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("outdir", nargs="?", default="out/python-examples",
                        help="folder of the figure (default out/python-examples)")
    parser.add_argument("--update-docs", action="store_true",
                        help="also copy the figure to docs/python_" + FIGURE)
    args = parser.parse_args()
    outdir = pathlib.Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)

    raskar = fss.read_code("raskar")
    design = fss.optimize_code(length=raskar.size, velocity=VELOCITY, snr=SNR, binary=True,
                               min_light=raskar.sum(), seed=0)
    codes = {"designed": design["gains"], "raskar": raskar}
    image = fss.read_png(SOURCE / "data" / "camera.png")[ROWS]  # uint8, 128 rows
    print("search: %d starts, best start %d, %d iterations"
          % (design["starts"], design["best_start"], design["iterations"]))
    print("%-9s %5s %12s %8s %8s %10s %6s %10s %20s"
          % ("code", "light", "snr_level100", "min |K|", "at xi", "predicted", "noise",
             "noise-free", "measured (mean ± SE)"))
    runs = {}
    for name, gains in codes.items():
        a = fss.analyze_code(gains, velocity=VELOCITY, snr=SNR)
        r = fss.simulate(image, code=gains, velocity=VELOCITY, snr=SNR, trials=TRIALS, seed=2)
        # The same run without noise: the restoration's own error, drawn in the figure.
        runs[name] = r, fss.simulate(image, code=gains, velocity=VELOCITY, noise="none")
        p, rmse = r.prediction, r.trial_metrics["rmse"]
        print("%-9s %5g %12.3f %8.4f %8.4f %10.4f %6.3f %10.4f %11.4f ± %.4f"
              % (name, a["sum"], a["snr_level100"], a["min_abs"], a["min_abs_xi"], p["rmse"],
                 p["noise"], p["rmse_noise_free"], rmse.mean(),
                 rmse.std(ddof=1) / np.sqrt(rmse.size)))
    if plot(codes, runs, outdir / FIGURE):
        print("wrote", outdir / FIGURE)
        if args.update_docs:
            shutil.copyfile(outdir / FIGURE, SOURCE / "docs" / ("python_" + FIGURE))
            print("wrote", SOURCE / "docs" / ("python_" + FIGURE))


if __name__ == "__main__":
    main()
