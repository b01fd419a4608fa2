"""Velocity distributions in fss.simulate, fss.simulate_to_folder, fss.analyze_code and
fss.optimize_code (docs/method.md §13): the keyword's forms, its refusals (one line, the
bindings' error types), the result's trial velocities and MSE statistics against fssim's
report.json for the same run, the trials' mean MSE against the prediction, and the design
functions against `fssim code analyze | optimize`."""

import json
import os
import pathlib
import struct
import zlib

import numpy as np
import pytest

import fss
from conftest import read_report, run_fssim

SHORT_CODE = "1 0 1 1 0 0 1 1\n"  # L = 8, invertible over [0.5, 1.5]


def write_png8(path, array):
    """An 8-bit gray PNG of `array` (uint8, H x W), rows unfiltered."""
    height, width = array.shape
    raw = b"".join(b"\x00" + array[y].tobytes() for y in range(height))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) +
            chunk(b"IEND", b""))
    pathlib.Path(path).write_bytes(data)


@pytest.fixture
def crop(camera_array):
    """A 24 x 128 crop of camera.png: cheap, wide enough for the short code at |v| <= 1.5."""
    return np.ascontiguousarray(camera_array[260:284, 160:288])


@pytest.fixture
def files(tmp_path, crop):
    """The crop as a PNG, the short code and a file of two velocities, in tmp_path."""
    write_png8(tmp_path / "crop.png", crop)
    (tmp_path / "short.txt").write_text(SHORT_CODE)
    (tmp_path / "v.txt").write_text("# velocity weight\n0.8 1\n1.2 3\n")
    return tmp_path


def test_each_trial_draws_its_velocity_from_the_distribution(crop, files):
    code = str(files / "short.txt")
    result = fss.simulate(crop, code=code, velocity_distribution="uniform:0.6:1.4", trials=40,
                          seed=2)
    velocities = result.trial_velocities
    assert velocities.dtype == np.float64 and velocities.shape == (40,)
    assert np.all((velocities >= 0.6) & (velocities <= 1.4))
    assert len(np.unique(velocities)) == 40
    # The trials' MSE statistics and E[MSE] are in the result's sections.
    trials, prediction = result.trials, result.prediction
    assert trials["mse_mean"] > 0 and trials["mse_sd"] > 0
    assert prediction["mse"] == pytest.approx(prediction["rmse"] ** 2, rel=1e-12)
    # Jensen: the mean RMSE is below sqrt(mean MSE).
    assert trials["rmse_mean"] < np.sqrt(trials["mse_mean"])
    # A file of velocities (str, bytes, os.PathLike) gives its velocities only.
    for spec in (str(files / "v.txt"), os.fsencode(files / "v.txt"), files / "v.txt"):
        discrete = fss.simulate(crop, code=code, velocity_distribution=spec, trials=12, seed=2)
        assert set(discrete.trial_velocities) <= {0.8, 1.2}
    # Without a distribution: no trial velocities, no MSE statistics.
    plain = fss.simulate(crop, code=code, trials=2)
    assert plain.trial_velocities.shape == (0,)
    assert plain.trials.get("mse_mean") is None
    assert plain.prediction.get("mse") is None


def test_the_velocities_depend_on_the_seed_and_trial_only(crop, files):
    code = str(files / "short.txt")
    one = fss.simulate(crop, code=code, velocity_distribution="normal:1:0.1", trials=6, seed=9,
                       threads=1)
    two = fss.simulate(crop, code=code, velocity_distribution="normal:1:0.1", trials=6, seed=9,
                       threads=3)
    assert np.array_equal(one.trial_velocities, two.trial_velocities)
    assert one.trials == two.trials and one.prediction == two.prediction
    other = fss.simulate(crop, code=code, velocity_distribution="normal:1:0.1", trials=6, seed=10)
    assert not np.array_equal(one.trial_velocities, other.trial_velocities)


@pytest.mark.parametrize("keywords,cli", [
    ({"velocity_distribution": "uniform:0.6:1.4", "trials": 5, "seed": 4},
     ["--velocity-distribution", "uniform:0.6:1.4", "--trials", "5", "--seed", "4"]),
    ({"velocity_distribution": "normal:1:0.15", "trials": 3, "restore_velocity": 1.05,
      "restoration": "tikhonov", "regularization": 0.01, "snr": 60},
     ["--velocity-distribution", "normal:1:0.15", "--trials", "3", "--restore-velocity", "1.05",
      "--restoration", "tikhonov", "--regularization", "0.01", "--snr", "60"]),
    ({"velocity_distribution": "FILE", "trials": 4, "mode": "analog"},
     ["--velocity-distribution", "FILE", "--trials", "4", "--mode", "analog"]),
], ids=["uniform", "normal_tikhonov_restore", "file_analog"])
def test_results_are_fssims_report(fssim, tmp_path, files, crop, keywords, cli):
    velocity_file = str(files / "v.txt")
    keywords = {k: (velocity_file if v == "FILE" else v) for k, v in keywords.items()}
    cli = [velocity_file if a == "FILE" else a for a in cli]
    code = str(files / "short.txt")
    run_fssim(fssim, "--input", files / "crop.png", "--code", code, "--no-plots", *cli,
              "--outdir", tmp_path / "cli")
    report = read_report(tmp_path / "cli")
    result = fss.simulate(crop, code=code, **keywords)
    for section in ("trials", "prediction", "metrics", "geometry", "kernel", "warnings"):
        assert result.report[section] == report[section], section
    assert result.trials["mse_mean"] == report["trials"]["mse_mean"]
    assert result.prediction["mse"] == report["prediction"]["mse"]
    assert list(result.trial_velocities) == report["trials"]["velocities"]
    # simulate_to_folder writes fssim's files and returns its report.json.
    folder = fss.simulate_to_folder(files / "crop.png", tmp_path / "py", code=code, plots=False,
                                    **keywords)
    assert folder == read_report(tmp_path / "py")
    for name in sorted(p.name for p in (tmp_path / "cli").iterdir()):
        if name != "report.json":  # it names the input and output as given
            assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes()
    assert folder["trials"] == report["trials"] and folder["prediction"] == report["prediction"]


@pytest.mark.parametrize("keywords,error,message", [
    ({"velocity": 1, "velocity_distribution": "uniform:0.5:1.5"}, ValueError,
     "velocity_distribution: refused with velocity = 1 "),
    ({"velocity": 0.8, "velocity_distribution": "normal:1:0.2"}, ValueError,
     "velocity_distribution: refused with velocity = 0.8 "),
    ({"velocity_distribution": "uniform:1.5:0.5"}, ValueError,
     "velocity_distribution: velocity distribution 'uniform:1.5:0.5'"),
    ({"velocity_distribution": "normal:1"}, ValueError, "velocity_distribution: "),
    ({"velocity_distribution": "nothing.txt"}, ValueError,
     "velocity_distribution 'nothing.txt' is neither"),
    ({"velocity_distribution": 1.5}, TypeError, "velocity_distribution: expected a str"),
    ({"velocity_distribution": "uniform:0.5:1.5", "restoration": "wiener"}, ValueError, ""),
    ({"velocity_distribution": "uniform:0.5:1.5", "restoration": "tikhonov"}, ValueError, ""),
])
def test_refusals(crop, files, keywords, error, message):
    for call in (lambda: fss.simulate(crop, code=str(files / "short.txt"), **keywords),
                 lambda: fss.simulate_to_folder(files / "crop.png", files / "out",
                                                code=str(files / "short.txt"), **keywords)):
        with pytest.raises(error) as raised:
            call()
        text = str(raised.value)
        assert "\n" not in text and message in text, text
    assert not (files / "out").exists()


def test_a_velocity_file_that_does_not_parse_is_a_runtime_error(crop, files):
    (files / "bad.txt").write_text("0.5 1\n0.7 two\n")
    with pytest.raises(RuntimeError, match=r"bad\.txt', line 2"):
        fss.simulate(crop, code=str(files / "short.txt"), velocity_distribution=files / "bad.txt")
    with pytest.raises(ValueError, match="NUL"):
        fss.simulate(crop, velocity_distribution="v\0.txt")


@pytest.mark.parametrize("seed,spec", [(1, "normal:1:0.1"), (2, "uniform:0.8:1.0"),
                                       (3, "normal:0.8:0.1")])
def test_the_mean_mse_agrees_with_the_prediction(crop, files, seed, spec):
    """Over 300 trials the mean of the trials' MSE is within 3 standard errors of E[MSE]; a
    prediction 25 % off is not (the trials' MSE varies with the velocity: its sd is 0.4 to 0.8
    times its mean here)."""
    result = fss.simulate(crop, code=str(files / "short.txt"), velocity_distribution=spec,
                          trials=300, seed=seed, snr=30)
    trials, mse = result.trials, result.prediction["mse"]
    standard_error = trials["mse_sd"] / np.sqrt(300)
    z = (trials["mse_mean"] - mse) / standard_error
    assert abs(z) < 3, (z, trials, result.prediction)
    assert abs(trials["mse_mean"] - 1.25 * mse) / standard_error > 3


def code_gains(path):
    """The gains of a code file: '#' comments, ';' after each gain."""
    gains = []
    for line in pathlib.Path(path).read_text().splitlines():
        gains += [float(t) for t in line.split("#")[0].replace(";", " ").split()]
    return gains


@pytest.mark.parametrize("code,spec", [("raskar", "uniform:0.8:1.2"), ("mip", "normal:1:0.1"),
                                       ("sinc", "FILE")])
def test_analyze_under_a_distribution_is_fssims(fssim, files, code, spec):
    spec = str(files / "v.txt") if spec == "FILE" else spec
    run_fssim(fssim, "code", "analyze", code, "--velocity-distribution", spec, "--json",
              files / "a.json")
    expected = json.loads((files / "a.json").read_text())
    analysis = fss.analyze_code(code, velocity_distribution=spec)
    assert {k: analysis[k] for k in expected["analysis"]} == expected["analysis"]
    assert analysis["velocity_distribution"] == expected["parameters"]["velocity_distribution"]
    assert analysis["velocity"] is None
    assert analysis["quadrature"]["converged"] is True
    assert 0 < analysis["worst_snr_level100"] <= analysis["snr_level100"]
    # A distribution of one velocity is that velocity's analysis.
    point = fss.analyze_code(code, velocity_distribution="uniform:0.9:0.9")
    single = fss.analyze_code(code, velocity=0.9)
    assert point["snr_level100"] == single["snr_level100"] and point["m"] == single["m"]


def test_optimize_under_a_distribution_is_fssims(fssim, files):
    run_fssim(fssim, "code", "optimize", "--length", "8", "--velocity-distribution",
              "uniform:0.8:1.2", "--restarts", "2", "--iterations", "20", "--seed", "4", "-o",
              files / "opt.txt")
    result = fss.optimize_code(length=8, velocity_distribution="uniform:0.8:1.2", restarts=2,
                               iterations=20, seed=4)
    assert result["gains"].tolist() == code_gains(files / "opt.txt")
    analysis = fss.analyze_code(result["gains"].tolist(), velocity_distribution="uniform:0.8:1.2")
    assert result["analysis"] == analysis
    # At least as good under the distribution as the code optimized for its centre.
    centre = fss.optimize_code(length=8, velocity=1, restarts=2, iterations=20, seed=4)
    at_centre = fss.analyze_code(centre["gains"].tolist(), velocity_distribution="uniform:0.8:1.2")
    assert analysis["snr_level100"] >= at_centre["snr_level100"]


@pytest.mark.parametrize("call,error,message", [
    (lambda: fss.analyze_code("raskar", velocity=1, velocity_distribution="uniform:0.8:1.2"),
     ValueError, "velocity_distribution: refused with velocity = 1 "),
    (lambda: fss.analyze_code("raskar", velocity_distribution="uniform:0.5:2.5"), ValueError,
     "|v| dt < 2"),
    (lambda: fss.analyze_code("raskar", velocity_distribution="normal:1"), ValueError,
     "velocity_distribution: "),
    (lambda: fss.analyze_code("raskar", velocity_distribution=2), TypeError,
     "velocity_distribution: expected a str"),
    (lambda: fss.optimize_code(length=8), ValueError,
     "velocity: give a velocity or a velocity_distribution"),
    (lambda: fss.optimize_code(length=8, velocity=1, velocity_distribution="uniform:0.8:1.2"),
     ValueError, "velocity_distribution: refused with velocity = 1 "),
    (lambda: fss.optimize_code(length=8, velocity_distribution="missing.txt"), ValueError,
     "velocity_distribution 'missing.txt' is neither"),
])
def test_design_refusals(call, error, message):
    with pytest.raises(error) as raised:
        call()
    assert "\n" not in str(raised.value) and message in str(raised.value), str(raised.value)


def test_simulate_to_folder_never_overwrites_the_velocity_file(files, tmp_path):
    """The file of a discrete distribution is an input, as fssim keeps it: a run whose output
    has its name is refused and the file stays as it was."""
    out = tmp_path / "out"
    out.mkdir()
    text = "0.9 1\n1.0 1\n"
    (out / "code.txt").write_text(text)
    with pytest.raises(RuntimeError, match="refusing to overwrite the input"):
        fss.simulate_to_folder(files / "crop.png", out, code=files / "short.txt",
                               velocity_distribution=out / "code.txt", plots=False)
    assert (out / "code.txt").read_text() == text
    assert sorted(p.name for p in out.iterdir()) == ["code.txt"]
