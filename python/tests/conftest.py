"""Shared helpers of the fss module's tests: where fssim and the data are, a
way to run fssim, and an 8-bit PNG decoder of our own (zlib and the five PNG
row filters), so that the CLI's images are read without the module."""

import json
import os
import pathlib
import struct
import subprocess
import zlib

import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("FSS_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


@pytest.fixture(scope="session")
def fssim():
    """Path of the fssim binary the suite compares against (CTest sets FSSIM)."""
    path = os.environ.get("FSSIM")
    if not path:
        pytest.skip("FSSIM is not set (CTest sets it to the build's fssim)")
    return path


@pytest.fixture(scope="session")
def camera():
    return SOURCE_DIR / "data" / "camera.png"


@pytest.fixture(scope="session")
def astronaut():
    return SOURCE_DIR / "data" / "astronaut.png"


def run_fssim(fssim, *args, cwd=None):
    """Runs fssim; returns its stdout, failing the test on a non-zero exit."""
    result = subprocess.run([fssim, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert result.returncode == 0, result.stderr
    return result.stdout


def read_report(outdir):
    return json.loads((pathlib.Path(outdir) / "report.json").read_text())


def _paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def _unfilter(raw, height, stride, bpp):
    rows = np.zeros((height, stride), dtype=np.uint8)
    previous = np.zeros(stride, dtype=np.uint8)
    raw = np.frombuffer(raw, dtype=np.uint8).reshape(height, 1 + stride)
    for y in range(height):
        kind, row = raw[y, 0], raw[y, 1:].copy()
        if kind == 2:  # up: the only filter fssim writes, done in numpy
            row += previous
        elif kind != 0:
            for i in range(stride):
                left = int(row[i - bpp]) if i >= bpp else 0
                up = int(previous[i])
                upper_left = int(previous[i - bpp]) if i >= bpp else 0
                predictor = [0, left, up, (left + up) // 2, _paeth(left, up, upper_left)][kind]
                row[i] = (int(row[i]) + predictor) & 0xFF
        rows[y] = row
        previous = row
    return rows.tobytes()


def read_png8(path):
    """An 8-bit gray or RGB, non-interlaced PNG as a uint8 array H x W (x 3)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    position, idat, header = 8, b"", None
    while position < len(data):
        length, kind = struct.unpack(">I4s", data[position:position + 8])
        body = data[position + 8:position + 8 + length]
        position += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (0, 2) and interlace == 0, header
    channels = 1 if colour == 0 else 3
    pixels = _unfilter(zlib.decompress(idat), height, width * channels, channels)
    array = np.frombuffer(pixels, dtype=np.uint8).reshape(height, width, channels)
    return array[:, :, 0] if channels == 1 else array


def png8_samples(values):
    """What fssim writes to an 8-bit PNG for float values: rounded, halves away
    from zero, and clamped to [0, 255]; NaN gives 0."""
    values = np.asarray(values, dtype=np.float64)
    whole = np.trunc(values)
    rounded = whole + (values - whole >= 0.5)
    return np.where(~(values >= 0.5), 0, np.where(values >= 255.0, 255, rounded)).astype(np.uint8)


@pytest.fixture(scope="session")
def camera_array(camera):
    """data/camera.png as an 8-bit array, read by the decoder above."""
    return read_png8(camera)


@pytest.fixture(scope="session")
def astronaut_array(astronaut):
    """data/astronaut.png as an 8-bit H x W x 3 array."""
    return read_png8(astronaut)
