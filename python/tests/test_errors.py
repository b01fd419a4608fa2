"""Errors: the library's messages, as ValueError (usage) or RuntimeError, and
the module's own checks of arrays and names."""

import subprocess

import numpy as np
import pytest

import fss
from conftest import read_png8


def fssim_error(fssim, *args):
    """The message of fssim's one error line, without the 'fssim: error: ' prefix."""
    result = subprocess.run([fssim, *map(str, args)], capture_output=True, text=True)
    assert result.returncode != 0
    line = result.stderr.strip()
    assert line.startswith("fssim: error: ") and "\n" not in line, line
    return line[len("fssim: error: "):]


@pytest.fixture(scope="module")
def gray(camera):
    return read_png8(camera)


def test_usage_errors_have_fssims_messages(fssim, gray, camera, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(ValueError) as error:
        fss.simulate(gray, code="/no/such/code")
    # Named as each front end takes it: fssim's option --code, the keyword code=.
    assert "--" + str(error.value) == fssim_error(fssim, "-i", camera, "-o", out, "--code",
                                                  "/no/such/code")
    with pytest.raises(ValueError) as error:
        fss.simulate(gray, code="random", mode="analog")
    # fssim's advice in Python words (convert.cpp's translation).
    cli = fssim_error(fssim, "-i", camera, "-o", out, "--code", "random", "--mode", "analog")
    assert cli.endswith("(use --mode numerical)")
    assert str(error.value) == cli.replace("--mode numerical", "mode='numerical'")


def test_runtime_errors_have_fssims_messages(fssim, gray, camera, tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("1 2 x\n")
    with pytest.raises(RuntimeError) as error:
        fss.simulate(gray, code=bad)
    assert str(error.value) == fssim_error(fssim, "-i", camera, "-o", tmp_path / "out",
                                           "--code", bad)
    with pytest.raises(RuntimeError) as error:
        fss.read_png(bad)
    assert "bad.txt" in str(error.value)


@pytest.mark.parametrize("keywords,message", [
    ({"snr": -1}, "snr = -1: must be finite and > 0"),
    ({"dt": 0}, "dt = 0: must be finite and > 0"),
    ({"velocity": float("nan")}, "must be a finite number"),
    ({"trials": 0}, "trials = 0: must be >= 1"),
    ({"mode": "digital"}, "mode: 'digital' is not 'numerical' or 'analog'"),
    ({"noise": "gauss"}, "noise: 'gauss' is not 'poisson', 'aggregated' or 'none'"),
    ({"seed": -1}, "seed = -1: must be an integer in [0, 18446744073709551615]"),
    ({"code": [0, 0]}, "zero"),
    ({"code": [[1, 2]]}, "code: gains of shape (1, 2) are not one-dimensional"),
    ({"code": [1, float("inf")]}, "code: gain inf at index 1 is not finite"),
])
def test_bad_options(gray, keywords, message):
    with pytest.raises(ValueError) as error:
        fss.simulate(gray, **keywords)
    assert message in str(error.value)


def test_bad_images(gray):
    with pytest.raises(ValueError, match=r"image: shape \(4, 4, 4\) is not H x W"):
        fss.simulate(np.zeros((4, 4, 4)))
    with pytest.raises(ValueError, match=r"image: shape \(4,\) is not H x W"):
        fss.simulate(np.zeros(4))
    with pytest.raises(ValueError, match="image: dtype complex128 is not a real numeric type"):
        fss.simulate(gray.astype(np.complex128))
    nan = gray.astype(np.float64)
    nan[3, 5] = np.nan
    with pytest.raises(ValueError, match="image: value nan at row 3, column 5 is not finite"):
        fss.simulate(nan, data_range=255)
    with pytest.raises(ValueError, match="too narrow|narrow|width"):
        fss.simulate(gray[:, :100])


def test_limit_is_a_runtime_error(gray):
    with pytest.raises(RuntimeError, match="memory"):
        fss.simulate(gray, max_memory=1000)
