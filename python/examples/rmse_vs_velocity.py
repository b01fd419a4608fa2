#!/usr/bin/env python3
"""RMSE against velocity for the six built-in codes, measured and predicted.

On a crop of data/camera.png, each code runs a few trials at each velocity: the points are
the measured RMSE (mean +/- standard error of the trials, from result.trial_metrics), the
lines the exact prediction (result.prediction["rmse"], on a finer grid of velocities). A code
whose kernel vanishes at some frequency (accumulation) has no finite prediction (inf): its
points stand alone, in a panel of their own.

    python3 python/examples/rmse_vs_velocity.py [OUTDIR]

writes OUTDIR/rmse_vs_velocity.png (default OUTDIR: out/python-examples/) when matplotlib is
installed, and prints the numbers.
"""
import argparse
import pathlib
import shutil
import warnings

import numpy as np

import fss

SOURCE = pathlib.Path(__file__).resolve().parents[2]
FIGURE = "rmse_vs_velocity.png"
VELOCITIES = np.round(np.arange(0.2, 1.81, 0.2), 2)  # measured
FINE_VELOCITIES = np.round(np.arange(0.2, 1.801, 0.1), 2)  # predicted
ROWS = slice(192, 224)  # 32 rows of camera.png (the cameraman's head), all 512 columns
TRIALS = 8
SNR = 100
# The RMSE is taken MARGIN columns inside the output's borders at every velocity, so that its
# window changes smoothly with the blur length B = L v: the default 3B would leave this 512-wide
# image a window of 44 columns at v = 1 and none beyond v = 1.08 (rmse_margin='auto' then
# shrinks the margin, moving the window by jumps).
MARGIN = 90


def measure(image, code):
    """Mean, standard error and prediction of the RMSE at each velocity (gray levels), and the
    prediction on a finer grid of velocities (one trial each: the prediction is exact)."""
    mean, se, predicted = [], [], []
    for velocity in VELOCITIES:
        r = simulate(image, code, velocity, TRIALS)
        rmse = r.trial_metrics["rmse"]  # one value per trial
        mean.append(rmse.mean())
        se.append(rmse.std(ddof=1) / np.sqrt(rmse.size))
        predicted.append(r.prediction["rmse"])  # inf when the kernel is not invertible
    known = dict(zip(VELOCITIES, predicted))
    if np.isfinite(predicted).any():
        line = [known[v] if v in known else simulate(image, code, v, 1).prediction["rmse"]
                for v in FINE_VELOCITIES]
    else:
        line = [np.inf] * FINE_VELOCITIES.size
    return np.array(mean), np.array(se), np.array(predicted), np.array(line)


def simulate(image, code, velocity, trials):
    with warnings.catch_warnings():
        # Not invertible, or a margin below 3B: also listed in r.warnings.
        warnings.simplefilter("ignore", fss.FssimWarning)
        return fss.simulate(image, code=code, velocity=velocity, snr=SNR, trials=trials,
                            seed=1, rmse_margin=MARGIN)


def plot(results, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
    except ImportError:
        print("matplotlib not available: figure skipped")
        return False
    # Two panels: the codes without a finite prediction (accumulation) far above the others.
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5.4), layout="constrained",
                                      gridspec_kw={"height_ratios": [1, 2.6]})
    for index, (code, (mean, se, predicted, line)) in enumerate(results.items()):
        color = "C%d" % index
        finite = np.isfinite(line)
        ax = bottom if finite.any() else top
        label = code if finite.any() else code + ": not invertible, no finite prediction"
        ax.errorbar(VELOCITIES, mean, yerr=se, fmt="o", ms=4, color=color, capsize=2,
                    label=label)
        ax.plot(FINE_VELOCITIES[finite], line[finite], "-", color=color, lw=1.2)
    bottom.plot([], [], "ko", ms=4, label="measured: mean ± SE of %d trials\n(bars within the markers)" % TRIALS)
    bottom.plot([], [], "k-", lw=1.2, label="exact prediction")
    for ax in (top, bottom):
        ax.set_yscale("log")
        # Plain numbers at 1, 2, 5 x 10^k, not only at the powers of ten.
        ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(subs=(1, 2, 5)))
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.12)
    top.legend(fontsize=8, loc="lower right")
    bottom.legend(fontsize=8, ncol=2, loc="upper left")
    bottom.set_xlabel("velocity v (pixels per time slot)")
    fig.supylabel("RMSE (gray levels, 0..255)", fontsize=10)
    top.set_title("The six built-in codes on camera.png rows %d-%d, snr %g, RMSE margin %d columns"
                  % (ROWS.start, ROWS.stop - 1, SNR, MARGIN), fontsize=9)
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

    image = fss.read_png(SOURCE / "data" / "camera.png")[ROWS]  # uint8: no data_range needed
    results = {code: measure(image, code) for code in fss.builtin_codes()}
    print("RMSE (gray levels), measured mean +/- SE of %d trials / predicted" % TRIALS)
    print("v    " + "".join("%-24s" % code for code in results))
    for i, velocity in enumerate(VELOCITIES):
        cells = ["%.3f±%.3f / %.3f" % (m[i], s[i], p[i]) for m, s, p, _ in results.values()]
        print("%-4.1f " % velocity + "".join("%-24s" % c for c in cells))
    if plot(results, outdir / FIGURE):
        print("wrote", outdir / FIGURE)
        if args.update_docs:
            shutil.copyfile(outdir / FIGURE, SOURCE / "docs" / ("python_" + FIGURE))
            print("wrote", SOURCE / "docs" / ("python_" + FIGURE))


if __name__ == "__main__":
    main()
