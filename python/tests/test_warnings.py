"""Every warning fssim prints for a run is an fss.FssimWarning (a UserWarning) of
fss.simulate and fss.simulate_to_folder, with fssim's text, one warnings.warn
each, and still in the result's warnings; a filter "error" makes it an
exception."""

import subprocess
import warnings

import numpy as np
import pytest

import fss
from conftest import read_png8


def fssim_warnings(fssim, *args):
    """The texts fssim prints after "fssim: warning: " on stderr for a run."""
    result = subprocess.run([fssim, *map(str, args)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    prefix = "fssim: warning: "
    return [line[len(prefix):] for line in result.stderr.splitlines() if line.startswith(prefix)]


def warned(call):
    """(the call's result, the texts of the FssimWarnings it warned)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call()
    assert all(issubclass(w.category, fss.FssimWarning) for w in caught), caught
    return result, [str(w.message) for w in caught]


@pytest.fixture()
def pair_code(tmp_path):
    """Two open slots: at velocity 2, K(xi) = 1 + exp(-2 i xi) vanishes at pi / 2."""
    path = tmp_path / "pair.txt"
    path.write_text("1 1\n")
    return path


def test_the_category_is_a_user_warning_of_the_package():
    assert issubclass(fss.FssimWarning, UserWarning)
    assert fss.FssimWarning is fss._fss.FssimWarning
    assert fss.FssimWarning.__module__ == "fss"


def test_a_non_invertible_run_warns_what_fssim_prints(fssim, tmp_path, camera, pair_code):
    expected = fssim_warnings(fssim, "--input", camera, "--outdir", tmp_path / "cli", "--no-plots",
                              "--code", pair_code, "--velocity", "2")
    assert len(expected) == 2 and "is not invertible at velocity 2" in expected[0]
    result, texts = warned(lambda: fss.simulate(read_png8(camera), code=pair_code, velocity=2))
    assert texts == expected == result.warnings
    report, texts = warned(lambda: fss.simulate_to_folder(camera, tmp_path / "py", plots=False,
                                                          code=pair_code, velocity=2))
    assert texts == expected == report["warnings"]


def test_pytest_warns_and_the_filter_error(camera):
    image = read_png8(camera)
    with pytest.warns(fss.FssimWarning, match="is not invertible at velocity 2"):
        fss.simulate(image, code=[1, 1], velocity=2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", fss.FssimWarning)
        with pytest.raises(fss.FssimWarning, match="is not invertible at velocity 2"):
            fss.simulate(image, code=[1, 1], velocity=2)
        fss.simulate(image, code=[1, 1], velocity=0.5)  # invertible: no warning, no error


def test_an_automatic_margin_below_3b_warns(fssim, tmp_path, camera):
    # B = 78 at velocity 1.5: camera.png is narrower than 9 B + 1
    expected = fssim_warnings(fssim, "--input", camera, "--outdir", tmp_path, "--no-plots",
                              "--velocity", "1.5", "--rmse-margin", "auto")
    assert len(expected) == 1 and expected[0].startswith("RMSE margin auto: ")
    _, texts = warned(lambda: fss.simulate(read_png8(camera), velocity=1.5, rmse_margin="auto"))
    assert texts == expected


def test_a_default_run_warns_nothing():
    image = np.random.default_rng(0).integers(0, 256, (16, 96)).astype(np.uint8)
    result, texts = warned(lambda: fss.simulate(image, code=[1, 0, 1, 1]))
    assert texts == [] and result.warnings == []


def test_the_warning_points_at_the_caller(camera):
    with pytest.warns(fss.FssimWarning) as caught:
        fss.simulate(read_png8(camera), code=[1, 1], velocity=2)
    assert {w.filename for w in caught} == {__file__}
