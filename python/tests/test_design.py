"""fss.analyze_code and fss.optimize_code with every option of `fssim code analyze | optimize`
(the sensor, the restoration, the velocity distribution): each keyword changes the result as the
option does, to the last digit; refusals name the Python keyword; warnings are warned."""

import json
import math
import subprocess
import warnings

import pytest

import fss
from conftest import run_fssim
from test_codes import parse_code_text

# (fssim options, fss keywords); the code is the first of each
ANALYSES = [
    (["raskar", "--read-noise", "5", "--dark-current", "0.5", "--adc-bits", "12", "--adc-gain",
      "2"], {"read_noise": 5, "dark_current": 0.5, "adc_bits": 12, "adc_gain": 2}),
    (["snapshot", "--mode", "analog", "--read-noise", "40", "--snr", "30"],
     {"mode": "analog", "read_noise": 40.0, "snr": 30}),
    (["mip", "--restoration", "wiener", "--prior", "power-law:1.5:100"],
     {"restoration": "wiener", "prior": "power-law:1.5:100"}),
    (["sinc", "--restoration", "tikhonov", "--regularization", "0.001", "--velocity", "0.7"],
     {"restoration": "tikhonov", "regularization": 1e-3, "velocity": 0.7}),
    (["raskar", "--restoration", "tikhonov"], {"restoration": "tikhonov"}),
    (["raskar", "--restoration", "tikhonov", "--regularization", "optimal"],
     {"restoration": "tikhonov", "regularization": "optimal"}),
    # POINTS: a file of two velocities (an exact sum, cheaper than a quadrature)
    (["raskar", "--velocity-distribution", "POINTS", "--restoration", "wiener", "--read-noise",
      "3"], {"velocity_distribution": "POINTS", "restoration": "wiener", "read_noise": 3}),
    (["sinc", "--velocity", "2"], {"velocity": 2}),  # not invertible: m and the bound infinite
    (["accumulation", "--restoration", "tikhonov", "--velocity", "1"],
     {"restoration": "tikhonov", "velocity": 1}),
]


def same_number(python, json_value):
    """A Python float equals the JSON number; JSON's null stands for inf or nan."""
    if json_value is None:
        return python is None or (isinstance(python, float) and not math.isfinite(python))
    if isinstance(json_value, dict):
        return json_value.keys() <= python.keys() and all(
            same_number(python[k], v) for k, v in json_value.items())
    if isinstance(json_value, list):
        return len(python) == len(json_value) and all(map(same_number, python, json_value))
    return python == json_value and type(python) is type(json_value)


@pytest.mark.parametrize("options,keywords", ANALYSES, ids=range(len(ANALYSES)))
def test_analyze_equals_fssim(fssim, tmp_path, options, keywords):
    points = tmp_path / "points.txt"
    points.write_text("0.8 0.25\n1.1 0.75\n")
    options = [str(points) if o == "POINTS" else o for o in options]
    keywords = {k: points if v == "POINTS" else v for k, v in keywords.items()}
    expected = json.loads(run_fssim(fssim, "code", "analyze", *options, "--json", "-"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fss.FssimWarning)  # the ADC's: test_adc_warning_as_fssim
        analysis = fss.analyze_code(options[0], **keywords)
    for name, value in expected["analysis"].items():
        assert same_number(analysis[name], value), name
    parameters = expected["parameters"]
    for name in ("sensor", "restoration", "velocity_distribution"):
        assert (name in analysis) == (name in parameters), name
        if name in parameters:
            assert same_number(analysis[name], parameters[name]), name
    # every keyword changes the figure: the same call without it differs
    plain = fss.analyze_code(options[0], velocity=keywords.get("velocity"))
    if keywords.keys() - {"velocity"}:
        assert plain["snr_level100"] != analysis["snr_level100"]


def test_every_number_is_a_float():
    analysis = fss.analyze_code("sinc", velocity=2)
    assert analysis["m"] == math.inf and analysis["noise_figure"] == math.inf
    assert analysis["snr_level100_bound"] == 0.0 and not analysis["invertible"]
    assert fss.analyze_code("raskar", velocity=0)["snr_level100_bound"] == math.inf  # no bound
    assert analysis["warnings"] == []
    tikhonov = fss.analyze_code([1.0, -1.0], restoration="tikhonov")  # sum 0: E infinite
    assert tikhonov["restoration"]["lambda"] is None  # no lambda: the error is infinite
    assert tikhonov["restoration_error"] == math.inf


def test_adc_warning_as_fssim(fssim):
    command = [fssim, "code", "analyze", "raskar", "--adc-bits", "10", "--read-noise", "5"]
    stderr = subprocess.run(command, capture_output=True, text=True, check=True).stderr
    assert stderr.startswith("fssim: warning: ")
    with pytest.warns(fss.FssimWarning) as caught:
        analysis = fss.analyze_code("raskar", adc_bits=10, read_noise=5)
    assert [str(w.message) for w in caught] == [stderr.strip()[len("fssim: warning: "):]]
    assert analysis["warnings"] == [str(caught[0].message)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fss.analyze_code("raskar", adc_bits=16, read_noise=5)  # in range: no warning
        with pytest.raises(fss.FssimWarning):
            fss.analyze_code("raskar", adc_bits=10)


@pytest.mark.parametrize("options,keywords", [
    (["--read-noise", "20", "--mode", "analog", "--snr", "40"],
     {"read_noise": 20, "mode": "analog", "snr": 40}),
    (["--restoration", "wiener", "--prior", "power-law:1"],
     {"restoration": "wiener", "prior": "power-law:1"}),
], ids=["sensor", "wiener"])
def test_optimize_equals_fssim(fssim, tmp_path, options, keywords):
    run_fssim(fssim, "code", "optimize", "--length", "8", "--velocity", "1", "--restarts", "2",
              "--iterations", "20", "--seed", "4", *options, "-o", tmp_path / "opt.txt")
    expected = parse_code_text((tmp_path / "opt.txt").read_text())
    result = fss.optimize_code(length=8, velocity=1, restarts=2, iterations=20, seed=4, **keywords)
    assert result["gains"].tolist() == expected
    plain = fss.optimize_code(length=8, velocity=1, restarts=2, iterations=20, seed=4,
                              mode=keywords.get("mode", "numerical"))
    assert plain["analysis"]["snr_level100"] != result["analysis"]["snr_level100"]
    assert result["analysis"] == fss.analyze_code(result["gains"], **keywords)


@pytest.mark.parametrize("call,message", [
    (lambda: fss.analyze_code("raskar", full_well=1000), r"^full_well = 1000: code design"),
    (lambda: fss.optimize_code(length=4, velocity=1, full_well=10), r"^full_well = 10: "),
    (lambda: fss.analyze_code("raskar", adc_gain=2), r"^adc_gain: needs adc_bits"),
    (lambda: fss.analyze_code("raskar", adc_bits=40), r"^adc_bits = 40"),
    (lambda: fss.analyze_code("raskar", read_noise=-1), r"^read_noise = -1"),
    (lambda: fss.optimize_code(length=4, velocity=1, dark_current=-2), r"^dark_current = -2"),
    (lambda: fss.analyze_code("raskar", adc_bits=8, adc_gain=0), r"^adc_gain = 0"),
    (lambda: fss.analyze_code("raskar", restoration="magic"), r"^restoration: 'magic' is not"),
    (lambda: fss.analyze_code("raskar", prior="power-law"), r"^prior = 'power-law': only resto"),
    (lambda: fss.analyze_code("raskar", restoration="wiener", prior="oracle"),
     r"^prior = 'oracle': code design has no image"),
    (lambda: fss.analyze_code("raskar", restoration="wiener", prior="power-law:9"),
     r"^prior 'power-law:9': GAMMA"),
    (lambda: fss.analyze_code("raskar", regularization=0.1),
     r"^regularization: only restoration='tikhonov'"),
    (lambda: fss.optimize_code(length=4, velocity=1, restoration="wiener",
                               regularization="optimal"), r"^regularization: only"),
    (lambda: fss.analyze_code("raskar", restoration="tikhonov", regularization=1e3),
     r"^regularization = 1000: must be a number in \[1e-08, 100\] or 'optimal'"),
    (lambda: fss.analyze_code("raskar", restoration="tikhonov", regularization="best"),
     r"^regularization = 'best': expected a number or 'optimal'"),
    (lambda: fss.analyze_code("raskar", restoration="wiener", grid=920), r"^grid = 920: the DFT"),
    (lambda: fss.optimize_code(length=8, velocity=1, snr=1e-90, read_noise=1e90),
     r"readout noise .* raise snr"),
], ids=range(17))
def test_refusals_name_the_keyword(call, message):
    with pytest.raises(ValueError, match=message) as error:
        call()
    assert "--" not in str(error.value) and "\n" not in str(error.value)


def test_keyword_types():
    with pytest.raises(TypeError, match="read_noise"):
        fss.analyze_code("raskar", read_noise="5")
    with pytest.raises(TypeError, match="prior"):
        fss.analyze_code("raskar", restoration="wiener", prior=2)
    with pytest.raises(TypeError, match="restoration"):
        fss.optimize_code(length=4, velocity=1, restoration=None)
