#!/usr/bin/env python3
"""Checks fssim's predicted RMSE against the mean of many noise realizations.

The prediction (docs/method.md §6b) is the exact expectation sqrt(E[MSE]) of
the run's error. For every case of a matrix -- code, mode, velocity, dt, snr --
this runs `fssim --trials N` once and compares report.json's prediction.rmse
with the Monte Carlo estimate of sqrt(E[MSE]) from the trials,

    measured = sqrt(mean RMSE^2) = sqrt(rmse_mean^2 + rmse_sd^2 (n - 1) / n),
    SE       = rmse_sd / sqrt(n)           (its standard error),
    z        = (predicted - measured) / SE,   rel = predicted / measured - 1,

and prints each case's z (also that of the stationary approximation, §6, for
comparison), then the worst. The default matrix is the paper's: every
built-in code in both modes where admissible (analog needs gains in [0, 1]),
v in {1, 0.37, -0.73}, dt in {1, 0.5}, snr in {5, 100, 200}; codes that are
not invertible at a velocity have no finite prediction and are listed as
skipped (a noise-free probe finds them before any trial runs). A case passes when |z| < 4 and |rel| < 0.2% (with a hundred cases,
a few |z| above 3 are expected by chance: they are counted, not failed).
Exit status 1 when a case fails. Every case uses seeds --seed .. --seed + N - 1,
and fssim's noise streams depend on the seed, channel, slot and row but not on
snr or dt, so cases that differ only in snr or dt see the same normals and
uniforms: their z-scores are correlated (a fluctuation shows up in several
rows at once; rerun such a case with another --seed to tell).

The default RMSE margin is B (--rmse-margin 52 for the paper's codes at
|v| dt <= 1): a window 5.7 times wider than fssim's default 3B on a 512-wide
image, so that 40 trials give a standard error of about 0.03%. --margin
default uses fssim's own window.

    scripts/verify_prediction.py --fssim build/fssim [--image data/camera.png]
        [--trials 40] [--margin 52|default] [--codes raskar,mip] [--modes analog]
        [--velocities 1,0.37] [--dts 1] [--snrs 100] [--seed 0] [--csv FILE]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

BUILTIN_CODES = ["snapshot", "accumulation", "raskar", "random", "mip", "sinc"]


def number_list(text):
    return [float(x) for x in text.split(",") if x]


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--fssim", default=os.path.join(root, "build", "fssim"))
    parser.add_argument("--image", default=os.path.join(root, "data", "camera.png"))
    parser.add_argument("--trials", type=int, default=40)
    parser.add_argument("--margin", default="52", help="RMSE margin in columns, or 'default'")
    parser.add_argument("--codes", default=",".join(BUILTIN_CODES))
    parser.add_argument("--modes", default="numerical,analog")
    parser.add_argument("--velocities", type=number_list, default=[1.0, 0.37, -0.73])
    parser.add_argument("--dts", type=number_list, default=[1.0, 0.5])
    parser.add_argument("--snrs", type=number_list, default=[5.0, 100.0, 200.0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--csv", help="also write every case's figures to this CSV file")
    args = parser.parse_args()
    if args.trials < 2:
        parser.error("--trials must be at least 2 (a standard error needs two)")
    return args


def run_fssim(args, outdir, code, mode, velocity, dt, snr, trials, extra=()):
    """Runs one case; returns report.json, or None with the error line."""
    command = [args.fssim, "--input", args.image, "--code", code, "--mode", mode,
               "--velocity", repr(velocity), "--dt", repr(dt), "--snr", repr(snr),
               "--trials", str(trials), "--seed", str(args.seed), "--threads", str(args.threads),
               "--outdir", outdir, "--no-plots", *extra]
    if args.margin != "default":
        command += ["--rmse-margin", args.margin]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        return None, (result.stderr.strip().splitlines() or ["exit %d" % result.returncode])[0]
    with open(os.path.join(outdir, "report.json"), encoding="utf-8") as f:
        return json.load(f), ""


def admissible_in_analog(args, outdir, code):
    """True when the code's gains lie in [0, 1] (a noise-free probe)."""
    report, _ = run_fssim(args, outdir, code, "analog", 1.0, 1.0, 100.0, 1, ["--noise", "none"])
    return report is not None


def compare(report):
    """The Monte Carlo estimate of sqrt(E[MSE]) and the z-scores of both predictions."""
    t, p = report["trials"], report["prediction"]
    n = t["n"]
    measured = math.sqrt(t["rmse_mean"] ** 2 + t["rmse_sd"] ** 2 * (n - 1) / n)
    se = t["rmse_sd"] / math.sqrt(n)
    return {
        "predicted": p["rmse"],
        "stationary": p["rmse_stationary"],
        "measured": measured,
        "se": se,
        "z": (p["rmse"] - measured) / se,
        "rel": p["rmse"] / measured - 1.0,
        "z_stationary": (p["rmse_stationary"] - measured) / se,
    }


def main():
    args = parse_arguments()
    codes = [c for c in args.codes.split(",") if c]
    modes = [m for m in args.modes.split(",") if m]
    rows, skipped, failed = [], [], []
    print("%-13s %-9s %6s %4s %5s  %10s %10s %9s %7s %9s %8s" %
          ("code", "mode", "v", "dt", "snr", "predicted", "measured", "se", "z", "rel", "z_stat"))
    with tempfile.TemporaryDirectory() as work:
        for code in codes:
            for mode in modes:
                if mode == "analog" and not admissible_in_analog(args, work, code):
                    skipped.append("%s analog: gains outside [0, 1]" % code)
                    continue
                for v in args.velocities:
                    for dt in args.dts:
                        probe, _ = run_fssim(args, work, code, mode, v, dt, 100.0, 1,
                                             ["--noise", "none"])
                        if probe is not None and not probe["prediction"]["finite"]:
                            skipped.append("%s %s v %g dt %g: not invertible" % (code, mode, v, dt))
                            continue
                        for snr in args.snrs:
                            name = "%s %s v %g dt %g snr %g" % (code, mode, v, dt, snr)
                            report, error = run_fssim(args, work, code, mode, v, dt, snr,
                                                      args.trials)
                            if report is None:
                                failed.append("%s: fssim failed: %s" % (name, error))
                                print("%s: fssim failed: %s" % (name, error), flush=True)
                                continue
                            if not report["prediction"]["finite"]:
                                skipped.append("%s: not invertible" % name)
                                continue
                            c = compare(report)
                            c.update(code=code, mode=mode, v=v, dt=dt, snr=snr, n=args.trials)
                            rows.append(c)
                            print("%-13s %-9s %6g %4g %5g  %10.6f %10.6f %9.6f %7.2f %8.4f%% %8.2f" %
                                  (code, mode, v, dt, snr, c["predicted"], c["measured"], c["se"],
                                   c["z"], 100 * c["rel"], c["z_stationary"]), flush=True)
                            if abs(c["z"]) >= 4.0 or abs(c["rel"]) >= 0.002:
                                failed.append("%s: z %.2f, rel %.4f%%" % (name, c["z"],
                                                                          100 * c["rel"]))
    if args.csv and rows:
        with open(args.csv, "w", newline="", encoding="utf-8") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            writer.writeheader()
            writer.writerows(rows)
    for line in skipped:
        print("skipped: " + line)
    if rows:
        worst = max(rows, key=lambda r: abs(r["z"]))
        worst_rel = max(rows, key=lambda r: abs(r["rel"]))
        worst_stationary = max(rows, key=lambda r: abs(r["z_stationary"]))
        print("cases: %d, |z| >= 3: %d" % (len(rows), sum(abs(r["z"]) >= 3 for r in rows)))
        print("worst z: %.2f (%s %s v %g dt %g snr %g)" %
              (worst["z"], worst["code"], worst["mode"], worst["v"], worst["dt"], worst["snr"]))
        print("worst rel: %.4f%% (%s %s v %g dt %g snr %g)" %
              (100 * worst_rel["rel"], worst_rel["code"], worst_rel["mode"], worst_rel["v"],
               worst_rel["dt"], worst_rel["snr"]))
        print("largest relative standard error: %.4f%%" %
              (100 * max(r["se"] / r["measured"] for r in rows)))
        print("stationary approximation, worst z: %.2f" % worst_stationary["z_stationary"])
    for line in failed:
        print("FAILED: " + line)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
