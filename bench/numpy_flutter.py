#!/usr/bin/python3
"""The flutter shutter simulation of fssim, written with numpy as a user would.

The same model (docs/method.md §1 to §5): the observation through the code's
transfer function, photon noise drawn per frame with numpy's Generator.poisson,
the crop, mirror extension, inverse filter and output crop, and the RMSE. Used
by bench/run.sh to compare fssim's speed and memory with a plain numpy program;
run with Debian's python3 (python3-numpy, python3-pil).

    numpy_flutter.py --input IMAGE.png [--code raskar] [--mode numerical] [--noise poisson]
                     [--velocity 1] [--dt 1] [--snr 100] [--seed 0] [--outdir DIR]

(the options of fssim of the same names).

It prints the RMSE (and a plain sort-based contrast-invariant RMSE) and writes
observed.png, restored.png, residual.png and groundtruth.png into DIR. Its
simulate() is one run in memory, without the files (bench/python_loop.py
calls it in a loop).
"""

import argparse
import json
import math
import os

import numpy as np
from PIL import Image

CODES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "codes")


def read_code(name):
    """Gains of a code: a built-in name (codes/NAME.txt) or a file, one gain a line, # comments."""
    path = name if os.path.exists(name) else os.path.join(CODES_DIR, name + ".txt")
    gains = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                gains.append(float(line))
    return np.array(gains)


def read_image(path):
    """(channels, height, width) float64 array of the image's 8-bit values."""
    image = Image.open(path)
    image = image.convert("L" if image.mode in ("L", "I", "I;16", "P", "LA") else "RGB")
    array = np.asarray(image, dtype=np.float64)
    return array[np.newaxis] if array.ndim == 2 else np.moveaxis(array, 2, 0)


def write_png(path, array):
    """Writes a (channels, height, width) array, rounded and clipped to 0..255."""
    pixels = np.clip(np.rint(array), 0, 255).astype(np.uint8)
    pixels = pixels[0] if pixels.shape[0] == 1 else np.moveaxis(pixels, 0, 2)
    Image.fromarray(pixels).save(path)


def frequencies(n):
    """xi = 2 pi n / N at the rfft bins of an N-point row."""
    return 2.0 * np.pi * np.fft.rfftfreq(n)


def transfer(gains, xi, velocity, dt, first_slot=0):
    """K(xi) = dt sinc_h(theta) sum_k alpha_k exp(-i theta (k + 1/2)), theta = xi v dt."""
    theta = xi * velocity * dt
    sinc_h = np.sinc(theta / (2.0 * np.pi))  # sin(theta/2) / (theta/2)
    slots = np.arange(first_slot, first_slot + len(gains)) + 0.5
    phases = np.exp(-1j * np.outer(theta, slots))
    return dt * sinc_h * (phases @ gains)


def observe(u, gains, mode, velocity, dt, snr, noisy, rng):
    """The observation o of every row: analog PoissonSNR(e), numerical sum_k alpha_k PoissonSNR(e_k)."""
    width = u.shape[-1]
    spectrum = np.fft.rfft(u, axis=-1)
    xi = frequencies(width)
    lambda2 = snr * snr / 100.0

    def noise(e):  # PoissonSNR(e) = P / lambda2, P ~ Poisson(max(e, 0) lambda2)
        if not noisy:
            return np.maximum(e, 0.0)
        return rng.poisson(np.maximum(e, 0.0) * lambda2) / lambda2

    if mode == "analog":
        e = np.fft.irfft(spectrum * transfer(gains, xi, velocity, dt), n=width, axis=-1)
        return noise(e)
    o = np.zeros_like(u)
    for k, alpha in enumerate(gains):
        if alpha == 0.0:
            continue
        # Frame k: the code (0, ..., 1, ..., 0) with its 1 at slot k.
        e_k = np.fft.irfft(spectrum * transfer(np.ones(1), xi, velocity, dt, k), n=width, axis=-1)
        o += alpha * noise(e_k)
    return o


def restore(o, gains, velocity, dt, blur):
    """Crop, mirror extension, inverse filter (docs/method.md §4); the deconvolved rows."""
    width = o.shape[-1]
    half = blur // 2
    crop = o[..., half : half + width - blur]
    mirror = np.concatenate([crop, crop[..., ::-1]], axis=-1)
    n = mirror.shape[-1]
    k = transfer(gains, frequencies(n), velocity, dt)
    spectrum = np.fft.rfft(mirror, axis=-1)
    nonzero = k != 0
    spectrum[..., nonzero] /= k[nonzero]
    spectrum[..., ~nonzero] = 0.0
    return np.fft.irfft(spectrum, n=n, axis=-1)


def midway_rmse(g, r):
    """Contrast-invariant RMSE: midway equalization of each channel by sorting (ties in sort order)."""
    total = 0.0
    for gc, rc in zip(g, r):
        gi = np.argsort(gc, axis=None, kind="stable")
        ri = np.argsort(rc, axis=None, kind="stable")
        mid = 0.5 * (gc.ravel()[gi] + rc.ravel()[ri])
        ge = np.empty(gc.size)
        re = np.empty(rc.size)
        ge[gi] = mid
        re[ri] = mid
        total += np.sum((ge - re) ** 2)
    return math.sqrt(total / g.size)


def simulate(u, gains, mode="numerical", velocity=1.0, dt=1.0, snr=100.0, noisy=True, seed=0):
    """One run on the image u (channels, height, width): a dict of the observed, restored,
    ground-truth and residual arrays (output columns) and the RMSE, PSNR and RMSE_CI."""
    width = u.shape[-1]
    blur = max(len(gains), math.ceil(abs(velocity) * dt * len(gains)))
    half = blur // 2
    out_width = width - 3 * blur
    rng = np.random.default_rng(seed)

    o = observe(u, gains, mode, velocity, dt, snr, noisy, rng)
    deconvolved = restore(o, gains, velocity, dt, blur)
    restored = deconvolved[..., 2 * half : 2 * half + out_width]
    observed = o[..., 3 * half : 3 * half + out_width]
    truth = u[..., 3 * half : 3 * half + out_width]
    d = truth - restored
    rmse = math.sqrt(np.mean(d[..., 3 * blur : out_width - 3 * blur] ** 2))
    window = slice(blur, out_width - blur)
    rmse_ci = midway_rmse(truth[..., window], restored[..., window])
    return {"observed": observed, "restored": restored, "groundtruth": truth, "residual": d,
            "rmse": rmse, "psnr": 10 * math.log10(255.0**2 / rmse**2), "rmse_ci": rmse_ci}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-i", "--input", required=True)
    parser.add_argument("--code", default="raskar")
    parser.add_argument("--mode", choices=["numerical", "analog"], default="numerical")
    parser.add_argument("--noise", choices=["poisson", "none"], default="poisson")
    parser.add_argument("--velocity", type=float, default=1.0)
    parser.add_argument("--dt", type=float, default=1.0)
    parser.add_argument("--snr", type=float, default=100.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--outdir", default="out_numpy")
    args = parser.parse_args()

    gains = read_code(args.code)
    u = read_image(args.input)
    run = simulate(u, gains, args.mode, args.velocity, args.dt, args.snr,
                   args.noise == "poisson", args.seed)
    observed, restored, truth, d = (run[key] for key in
                                    ("observed", "restored", "groundtruth", "residual"))
    rmse, rmse_ci = run["rmse"], run["rmse_ci"]

    os.makedirs(args.outdir, exist_ok=True)
    k0 = args.dt * gains.sum()
    write_png(os.path.join(args.outdir, "observed.png"), observed / (k0 if k0 != 0 else args.dt * abs(gains).max()))
    write_png(os.path.join(args.outdir, "restored.png"), restored)
    write_png(os.path.join(args.outdir, "groundtruth.png"), truth)
    span = d.max() - d.min()
    write_png(os.path.join(args.outdir, "residual.png"), (d - d.min()) * (255.0 / span if span > 0 else 0.0))
    metrics = {"rmse": rmse, "psnr": run["psnr"], "rmse_ci": rmse_ci}
    with open(os.path.join(args.outdir, "metrics.json"), "w") as f:
        json.dump(metrics, f, indent=1)
    print(f"RMSE: {rmse:.6f}")
    print(f"PSNR: {metrics['psnr']:.6f}")
    print(f"Contrast Invariant RMSE (sort order ties): {rmse_ci:.6f}")


if __name__ == "__main__":
    main()
