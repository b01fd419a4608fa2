"""The checks of every argument: paths and names without NUL bytes, every
float argument finite and in the range fssim accepts, adc_gain only with
adc_bits, and messages that name the Python argument ("read_noise = nan: ..."),
not fssim's option nor the library's field."""

import math
import os
import pathlib

import numpy as np
import pytest

import fss
from conftest import SOURCE_DIR

NAN, INF = float("nan"), float("inf")
# A short code (B = 4 at velocity 1) and an image wide enough for it.
GAINS = [1.0, 0.0, 1.0, 1.0]
IMAGE = np.full((3, 64), 100, dtype=np.uint8)


# ---------------------------------------------------------------------------
# NUL bytes in paths and names


def test_read_png_refuses_a_nul_in_the_path(camera, tmp_path):
    copy = tmp_path / "a.png"
    copy.write_bytes(camera.read_bytes())
    for path in (str(copy) + "\0junk", os.fsencode(copy) + b"\0junk",
                 pathlib.Path(str(copy) + "\0junk")):
        with pytest.raises(ValueError) as error:
            fss.read_png(path)
        assert str(error.value).startswith("path: ") and "NUL" in str(error.value)
        assert "\0" not in str(error.value)


@pytest.mark.parametrize("call", [
    lambda code: fss.read_code(code),
    lambda code: fss.simulate(IMAGE, code=code),
    lambda code: fss.analyze_code(code),
    lambda code: fss.transfer_function(code, 0.5),
], ids=["read_code", "simulate", "analyze_code", "transfer_function"])
@pytest.mark.parametrize("name", ["raskar\0junk", str(SOURCE_DIR / "codes" / "raskar.txt") + "\0x"])
def test_code_names_refuse_a_nul(call, name):
    with pytest.raises(ValueError) as error:
        call(name)
    assert str(error.value).startswith("code: ") and "NUL" in str(error.value)
    assert "\0" not in str(error.value)


@pytest.mark.parametrize("call,argument", [
    (lambda text: fss.simulate(IMAGE, code=GAINS, mode=text), "mode"),
    (lambda text: fss.simulate(IMAGE, code=GAINS, noise=text), "noise"),
    (lambda text: fss.generate_code(text, length=4), "family"),
    (lambda text: fss.optimize_code(length=4, velocity=1, mode=text), "mode"),
])
def test_choices_with_a_nul_are_refused_and_escaped(call, argument):
    with pytest.raises(ValueError) as error:
        call("numerical\0x")
    message = str(error.value)
    assert message.startswith(argument + ": ") and "\0" not in message and "\\x00" in message


# ---------------------------------------------------------------------------
# Float arguments: finite and in range, named as the keyword


SIMULATE_FLOATS = [
    ({"velocity": NAN}, "velocity = nan: must be a finite number"),
    ({"velocity": -INF}, "velocity = -inf: must be a finite number"),
    ({"restore_velocity": INF}, "restore_velocity = inf: must be a finite number"),
    ({"snr": NAN}, "snr = nan: must be finite and > 0"),
    ({"snr": 1e-200}, "snr = 1e-200: must lie in [1e-100, 1e100]"),
    ({"dt": INF}, "dt = inf: must be finite and > 0"),
    ({"dt": 1e101}, "dt = 1e+101: must lie in [1e-100, 1e100]"),
    ({"read_noise": NAN}, "read_noise = nan: must be finite and >= 0"),
    ({"read_noise": -1}, "read_noise = -1: must be finite and >= 0"),
    ({"dark_current": INF}, "dark_current = inf: must be finite and >= 0"),
    ({"full_well": NAN}, "full_well = nan: must be finite and > 0"),
    ({"full_well": 0}, "full_well = 0: must be finite and > 0"),
    ({"adc_bits": 12, "adc_gain": NAN}, "adc_gain = nan: must be finite and > 0"),
    ({"adc_bits": 12, "adc_gain": -INF}, "adc_gain = -inf: must be finite and > 0"),
    ({"adc_bits": 33}, "adc_bits = 33: must lie in [1, 32] (or 0 for no ADC)"),
    ({"rmse_margin": -2}, "rmse_margin = -2: must be >= 0"),
    ({"threads": -1}, "threads = -1: must be >= 0 (0: all)"),
    ({"trials": 2**40}, "trials = 1099511627776: must be an integer in [1, 2147483647]"),
    ({"noise": "aggregated", "full_well": 1000},
     "noise = aggregated: must be poisson or none with a full well or an ADC"),
]


@pytest.mark.parametrize("keywords,message", SIMULATE_FLOATS,
                         ids=[m.split(" =")[0] + str(i) for i, (_, m) in enumerate(SIMULATE_FLOATS)])
def test_simulate_checks_every_number(keywords, message):
    with pytest.raises(ValueError) as error:
        fss.simulate(IMAGE, code=GAINS, **keywords)
    assert str(error.value).startswith(message)


TRANSFER = [
    ({"velocity": NAN}, "velocity = nan: must be a finite number"),
    ({"velocity": INF}, "velocity = inf: must be a finite number"),
    ({"dt": NAN}, "dt = nan: must be finite and > 0"),
    ({"dt": 0.0}, "dt = 0: must be finite and > 0"),
    ({"dt": 1e-300}, "dt = 1e-300: must lie in [1e-100, 1e100]"),
    ({"xi": NAN}, "xi: value nan is not finite"),
    ({"xi": [0.0, 1.0, -INF]}, "xi: value -inf at index 2 is not finite"),
    ({"xi": 1e300, "velocity": 1e100}, "xi = 1e+300: K(xi) of code 'raskar' is not finite"),
]


@pytest.mark.parametrize("keywords,message", TRANSFER)
def test_transfer_function_checks_every_number(keywords, message):
    keywords = dict(keywords)
    xi = keywords.pop("xi", 0.5)
    with pytest.raises(ValueError) as error:
        fss.transfer_function("raskar", xi, **keywords)
    assert str(error.value).startswith(message)


def test_transfer_function_results_are_finite():
    values = fss.transfer_function("raskar", np.array([-1e6, -3.0, 0.0, 2.5, 1e6]), velocity=-7.5,
                                   dt=1e-3)
    assert np.all(np.isfinite(values))


@pytest.mark.parametrize("call,message", [
    (lambda: fss.analyze_code("raskar", velocity=NAN), "velocity = nan: must be a finite number"),
    (lambda: fss.analyze_code("raskar", dt=INF), "dt = inf: must be finite and > 0"),
    (lambda: fss.analyze_code("raskar", dt=1e-200), "dt = 1e-200: must lie in [1e-100, 1e100]"),
    (lambda: fss.analyze_code("raskar", snr=NAN), "snr = nan: must be finite and > 0"),
    (lambda: fss.analyze_code("raskar", snr=1e101), "snr = 1e+101: must lie in [1e-100, 1e100]"),
    (lambda: fss.analyze_code("raskar", grid=-1), "grid"),
    (lambda: fss.generate_code("sinc", length=8, velocity=NAN),
     "velocity = nan: must be a finite number"),
    (lambda: fss.generate_code("random", length=8, dt=NAN), "dt = nan: must be finite and > 0"),
    (lambda: fss.generate_code("mip", length=8, dt=1e300),
     "dt = 1e+300: must lie in [1e-100, 1e100]"),
    (lambda: fss.generate_code("sinc", length=8, velocity=3),
     "velocity = 3 with dt = 1: the sinc code needs 0 < |velocity| dt < 2"),
    (lambda: fss.optimize_code(length=8, velocity=NAN), "velocity = nan: must be a finite number"),
    (lambda: fss.optimize_code(length=8, velocity=1, dt=-INF), "dt = -inf: must be finite and > 0"),
    (lambda: fss.optimize_code(length=8, velocity=1, snr=NAN), "snr = nan: must be finite and > 0"),
    (lambda: fss.optimize_code(length=8, velocity=1, mode="analog", min_light=NAN),
     "min_light = nan: must lie in [0, length = 8]"),
    (lambda: fss.optimize_code(length=8, velocity=1, iterations=0),
     "iterations = 0: must lie in [1, 100000]"),
    (lambda: fss.optimize_code(length=8, velocity=1, grid_points=2),
     "grid_points = 2: must lie in [16, 65536]"),
], ids=lambda value: None if callable(value) else value.split(":")[0])
def test_code_functions_check_every_number(call, message):
    with pytest.raises(ValueError) as error:
        call()
    assert str(error.value).startswith(message)


def test_design_results_are_never_nan():
    # At the ends of the ranges a figure may be infinite (a float, never None), never NaN.
    analysis = fss.analyze_code("raskar", velocity=1e-90, dt=1e-100, snr=1e100)
    for key, value in analysis.items():
        if isinstance(value, float):
            assert not math.isnan(value), key
        assert value is not None or key in ("velocity", "velocity_distribution"), key
    assert np.all(np.isfinite(fss.generate_code("sinc", length=8, velocity=1e-10, dt=1e10)))


# ---------------------------------------------------------------------------
# adc_gain needs adc_bits


@pytest.mark.filterwarnings("ignore::fss.FssimWarning")  # a flat image near the ADC's 0
def test_adc_gain_needs_adc_bits():
    for keywords in ({"adc_gain": 2.0}, {"adc_gain": 1.0}, {"adc_gain": 2.0, "adc_bits": 0}):
        with pytest.raises(ValueError) as error:
            fss.simulate(IMAGE, code=GAINS, **keywords)
        assert str(error.value) == "adc_gain: needs adc_bits (without an ADC there are no counts)"
    with_adc = fss.simulate(IMAGE, code=GAINS, adc_bits=12, adc_gain=2.0)
    assert with_adc.report["sensor"]["adc_gain_electrons_per_count"] == 2.0
    default_gain = fss.simulate(IMAGE, code=GAINS, adc_bits=12)
    assert default_gain.report["sensor"]["adc_gain_electrons_per_count"] == 1.0


# ---------------------------------------------------------------------------
# The restore velocity's blur is named as its own


def test_restore_velocity_too_wide_is_named():
    for value in (1e308, 100.0):
        with pytest.raises(ValueError) as error:
            fss.simulate(IMAGE, code=GAINS, restore_velocity=value)
        assert str(error.value).startswith("restore_velocity = "), str(error.value)
        assert "more than the image width 64" in str(error.value)
