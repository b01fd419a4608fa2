"""fss.generate_code, analyze_code, optimize_code, read_code and
transfer_function against `fssim code ...` and the closed forms of K."""

import json
import subprocess

import numpy as np
import pytest

import fss
from conftest import SOURCE_DIR, run_fssim


def parse_code_text(text):
    """Gains of the code text format: '#' comments, ';' after each gain."""
    gains = []
    for line in text.splitlines():
        line = line.split("#")[0].replace(";", " ").replace(",", " ")
        gains += [float(token) for token in line.split()]
    return gains


@pytest.mark.parametrize("family,options,keywords", [
    ("sinc", ["--length", "52"], {"length": 52}),
    ("mip", ["--length", "31", "--velocity", "0.7", "--dt", "0.5"],
     {"length": 31, "velocity": 0.7, "dt": 0.5}),
    ("random", ["--length", "20", "--seed", "9"], {"length": 20, "seed": 9}),
    ("random", ["--length", "20", "--seed", "9", "--analog"],
     {"length": 20, "seed": 9, "analog": True}),
    ("snapshot", ["--length", "5"], {"length": 5}),
    ("accumulation", ["--length", "5"], {"length": 5}),
])
def test_generate_equals_fssim(fssim, family, options, keywords):
    expected = parse_code_text(run_fssim(fssim, "code", "generate", family, *options))
    gains = fss.generate_code(family, **keywords)
    assert gains.dtype == np.float64 and gains.shape == (len(expected),)
    assert gains.tolist() == expected


@pytest.mark.parametrize("code,options,keywords", [
    ("raskar", [], {}),
    ("sinc", ["--velocity", "0.7", "--dt", "0.5", "--snr", "30"],
     {"velocity": 0.7, "dt": 0.5, "snr": 30}),
    ("snapshot", ["--mode", "analog", "--grid", "920"], {"mode": "analog", "grid": 920}),
    ("accumulation", [], {}),
])
def test_analyze_equals_fssim(fssim, tmp_path, code, options, keywords):
    run_fssim(fssim, "code", "analyze", code, "--json", tmp_path / "a.json", *options)
    expected = json.loads((tmp_path / "a.json").read_text())
    analysis = fss.analyze_code(code, **keywords)
    for name, value in expected["analysis"].items():
        if value is None:  # JSON's null: a Python float inf (M of a code that is not invertible)
            assert analysis[name] == float("inf"), name
        else:
            assert analysis[name] == value and type(analysis[name]) is type(value), name
    assert analysis["length"] == expected["code"]["length"]
    for name in ("mode", "velocity", "dt", "snr"):
        assert analysis[name] == expected["parameters"][name]


def test_optimize_equals_fssim(fssim, tmp_path):
    run_fssim(fssim, "code", "optimize", "--length", "8", "--velocity", "1", "--restarts", "2",
              "--iterations", "20", "--seed", "4", "-o", tmp_path / "opt.txt")
    expected = parse_code_text((tmp_path / "opt.txt").read_text())
    result = fss.optimize_code(length=8, velocity=1, restarts=2, iterations=20, seed=4)
    assert result["gains"].tolist() == expected
    assert result["analysis"] == fss.analyze_code(result["gains"].tolist())
    assert result["starts"] >= 3 and result["evaluations"] >= result["iterations"]


def test_read_code():
    for name in fss.builtin_codes():
        path = SOURCE_DIR / "codes" / f"{name}.txt"
        expected = parse_code_text(path.read_text())
        assert fss.read_code(name).tolist() == expected
        assert fss.read_code(path).tolist() == expected
        assert fss.read_code(str(path)).tolist() == expected


def test_transfer_function():
    gains = fss.read_code("raskar")
    assert fss.transfer_function("raskar", 0.0) == complex(26, 0)
    assert fss.transfer_function(gains, 0.0, dt=0.5) == complex(13, 0)
    xi = np.linspace(-np.pi, np.pi, 101).reshape(1, 101)
    values = fss.transfer_function("raskar", xi, velocity=0.8, dt=0.5)
    assert values.shape == xi.shape and values.dtype == np.complex128
    # K(xi) = dt sinc_h(theta) sum_k alpha_k exp(-i theta (k + 1/2)), theta = xi v dt
    theta = xi[0] * 0.8 * 0.5
    k = np.arange(len(gains))
    sinc_h = np.where(theta == 0, 1.0, np.sin(theta / 2) / np.where(theta == 0, 1, theta / 2))
    expected = 0.5 * sinc_h * (gains * np.exp(-1j * np.outer(theta, k + 0.5))).sum(axis=1)
    np.testing.assert_allclose(values[0], expected, rtol=1e-12, atol=1e-12)
    # analyze_code's minimum of |K| is |K| at its place.
    analysis = fss.analyze_code("mip")
    assert abs(fss.transfer_function("mip", analysis["min_abs_xi"])) == pytest.approx(
        analysis["min_abs"], rel=1e-12)


@pytest.mark.parametrize("family,keyword,value", [
    ("sinc", "seed", 3), ("mip", "analog", False), ("random", "velocity", 0.5),
    ("random", "dt", 1.0), ("snapshot", "seed", 0), ("accumulation", "velocity", 1.0),
])
def test_generate_refuses_a_keyword_the_family_does_not_use(fssim, family, keyword, value):
    """As fssim refuses the option: never a keyword accepted and ignored."""
    with pytest.raises(ValueError, match=f"^{keyword}: the {family} code does not use it"):
        fss.generate_code(family, length=8, **{keyword: value})
    option = "--" + keyword
    result = subprocess.run([fssim, "code", "generate", family, "--length", "8", option] +
                            ([] if keyword == "analog" else [str(value)]),
                            capture_output=True, text=True)
    assert result.returncode == 2 and "does not use it" in result.stderr


def test_code_errors():
    with pytest.raises(ValueError, match="family: 'fancy' is not one of"):
        fss.generate_code("fancy", length=4)
    with pytest.raises(ValueError, match="length"):
        fss.generate_code("sinc", length=0)
    with pytest.raises(ValueError):
        fss.analyze_code("random", mode="analog")
    with pytest.raises(ValueError):
        fss.optimize_code(length=8, velocity=3)
    with pytest.raises(ValueError, match="xi: dtype complex128"):
        fss.transfer_function("raskar", 1j)
