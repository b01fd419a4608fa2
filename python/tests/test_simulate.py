"""fss.simulate against fssim: the same inputs and seed give the same numbers
to the last bit (the PNG pixels of the images, every value of report.json),
and the shapes, dtypes and conventions of the module."""

import warnings

import numpy as np
import pytest

import fss
from conftest import png8_samples, read_png8, read_report, run_fssim

# (name, fssim options, fss.simulate keywords, input)
CASES = [
    ("default", [], {}, "camera"),
    ("analog_rgb", ["--mode", "analog", "--velocity", "-1", "--seed", "3"],
     {"mode": "analog", "velocity": -1, "seed": 3}, "astronaut"),
    ("mip_dt", ["--code", "mip", "--velocity", "0.37", "--snr", "200", "--dt", "0.5"],
     {"code": "mip", "velocity": 0.37, "snr": 200, "dt": 0.5}, "camera"),
    ("trials_restore", ["--trials", "3", "--seed", "11", "--restore-velocity", "1.05",
                        "--threads", "1", "--rmse-margin", "40"],
     {"trials": 3, "seed": 11, "restore_velocity": 1.05, "threads": 2, "rmse_margin": 40},
     "camera"),
    ("noise_free_sinc", ["--code", "sinc", "--noise", "none"], {"code": "sinc", "noise": "none"},
     "astronaut"),
    # --rmse-margin auto where the paper's 3B does not fit camera.png (B = 78 at v 1.5)
    ("auto_margin", ["--velocity", "1.5", "--rmse-margin", "auto", "--seed", "4"],
     {"velocity": 1.5, "rmse_margin": "auto", "seed": 4}, "camera"),
    # the sensor (docs/method.md §10)
    ("sensor", ["--read-noise", "6", "--dark-current", "0.5", "--adc-bits", "14", "--adc-gain",
                "2", "--full-well", "30000", "--seed", "5"],
     {"read_noise": 6, "dark_current": 0.5, "adc_bits": 14, "adc_gain": 2, "full_well": 30000,
      "seed": 5}, "camera"),
    # the restorations (docs/method.md §12)
    ("tikhonov_optimal", ["--restoration", "tikhonov", "--trials", "2"],
     {"restoration": "tikhonov", "trials": 2}, "camera"),
    ("tikhonov_lambda", ["--restoration", "tikhonov", "--regularization", "0.003", "--mode",
                         "analog"],
     {"restoration": "tikhonov", "regularization": 0.003, "mode": "analog"}, "astronaut"),
    ("wiener_power_law", ["--restoration", "wiener", "--prior", "power-law:1.5", "--seed", "4"],
     {"restoration": "wiener", "prior": "power-law:1.5", "seed": 4}, "camera"),
    ("wiener_oracle", ["--restoration", "wiener", "--prior", "oracle", "--code", "accumulation"],
     {"restoration": "wiener", "prior": "oracle", "code": "accumulation"}, "camera"),
]


@pytest.mark.parametrize("name,cli_options,keywords,image", CASES, ids=[c[0] for c in CASES])
def test_same_numbers_as_fssim(fssim, tmp_path, request, name, cli_options, keywords, image):
    path = request.getfixturevalue(image)
    run_fssim(fssim, "--input", path, "--outdir", tmp_path, "--no-plots", *cli_options)
    cli = read_report(tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fss.simulate(read_png8(path), **keywords)
    # fssim's warnings, each an fss.FssimWarning with the same text
    assert [str(w.message) for w in caught] == result.warnings == cli["warnings"]
    assert all(w.category is fss.FssimWarning for w in caught)

    for output in ("observed", "restored", "groundtruth"):
        written = read_png8(tmp_path / f"{output}.png")
        np.testing.assert_array_equal(png8_samples(getattr(result, output)), written,
                                      err_msg=output)
    # Every value of report.json, bit for bit, but the input's path.
    assert result.report["input"].pop("path") == ""
    assert cli["input"].pop("path") == str(path)
    if name == "trials_restore":  # the thread count is not recorded: the results are the same
        assert result.parameters["trials"] == 3
    assert result.report == cli
    for section in ("metrics", "prediction", "geometry", "trials", "parameters", "code",
                    "kernel", "warnings"):
        assert getattr(result, section) == cli[section], section


def test_code_as_gains_equals_code_file(fssim, tmp_path, camera):
    gains = [0.5, 1, 0.25, 1, 0.75]
    code_file = tmp_path / "short.txt"
    code_file.write_text("0.5 1 0.25\n1; 0.75\n")
    run_fssim(fssim, "--input", camera, "--outdir", tmp_path / "out", "--no-plots",
              "--code", code_file, "--mode", "analog")
    cli = read_report(tmp_path / "out")
    for code in (gains, np.array(gains), tuple(gains), str(code_file), code_file):
        result = fss.simulate(read_png8(camera), code=code, mode="analog")
        assert result.metrics == cli["metrics"]
        assert result.code["gains"] == gains
        np.testing.assert_array_equal(png8_samples(result.restored),
                                      read_png8(tmp_path / "out" / "restored.png"))


def test_shapes_and_dtypes(camera, astronaut):
    gray = read_png8(camera)
    rgb = read_png8(astronaut)
    result = fss.simulate(gray, noise="none")
    width = result.geometry["output_width"]
    first = result.geometry["output_first_input_column"]
    for image in (result.observed, result.restored, result.groundtruth):
        assert image.shape == (512, width) and image.dtype == np.float64
    np.testing.assert_array_equal(result.groundtruth, gray[:, first:first + width])
    assert fss.simulate(gray[:, :, np.newaxis], noise="none").restored.shape == (512, width)
    colour = fss.simulate(rgb, noise="none")
    assert colour.restored.shape == (rgb.shape[0], width, 3)
    assert colour.report["input"]["channels"] == 3
    np.testing.assert_array_equal(colour.groundtruth, rgb[:, first:first + width, :])
    # Not rounded nor clamped: the noise-free restoration has fractions and
    # overshoots.
    assert np.any(result.restored != np.round(result.restored))


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16, np.int16, np.int64, np.float32, np.float64,
                                   ">f8", np.float16])
def test_every_dtype_with_data_range_255_is_gray_levels(camera, dtype):
    gray = read_png8(camera)
    reference = fss.simulate(gray, noise="none", code="snapshot")
    result = fss.simulate(gray.astype(dtype), data_range=255, noise="none", code="snapshot")
    np.testing.assert_array_equal(result.restored, reference.restored)
    assert result.metrics == reference.metrics


def test_strided_and_non_contiguous_input(camera):
    gray = read_png8(camera)
    reference = fss.simulate(np.ascontiguousarray(gray[::2, ::-1]), noise="none")
    result = fss.simulate(gray[::2, ::-1], noise="none")
    np.testing.assert_array_equal(result.restored, reference.restored)


def test_seed_and_version(camera):
    gray = read_png8(camera)
    a = fss.simulate(gray, seed=2**64 - 1)
    b = fss.simulate(gray, seed=2**64 - 1)
    np.testing.assert_array_equal(a.restored, b.restored)
    assert a.parameters["seed"] == 2**64 - 1
    assert a.report["fssim_version"] == fss.__version__
    assert a.report["schema_version"] == fss.REPORT_SCHEMA_VERSION == 1


def test_fssim_version_is_what_version_prints(fssim, tmp_path, camera):
    version = run_fssim(fssim, "--version").strip()
    assert version == "fssim " + fss.__version__
    run_fssim(fssim, "--input", camera, "--outdir", tmp_path, "--no-plots")
    assert read_report(tmp_path)["fssim_version"] == fss.__version__


def test_not_invertible_gives_inf(fssim, tmp_path, camera):
    with pytest.warns(fss.FssimWarning, match="not invertible"):
        result = fss.simulate(read_png8(camera), code="accumulation", noise="none")
    assert result.prediction["finite"] is False
    # JSON has no infinity: report.json holds null where the module gives inf.
    run_fssim(fssim, "--input", camera, "--outdir", tmp_path, "--no-plots", "--code",
              "accumulation", "--noise", "none")
    cli = read_report(tmp_path)["prediction"]
    for key in ("rmse", "noise", "sigma", "rmse_stationary", "m"):
        assert cli[key] is None and result.prediction[key] == float("inf"), key
    assert isinstance(result.prediction["rmse"], float)
    assert result.prediction["rmse_noise_free"] == cli["rmse_noise_free"]
    assert result.warnings


def test_sensor_keywords(camera):
    image = read_png8(camera)
    plain = fss.simulate(image)
    assert "sensor" not in plain.report and "exact" not in plain.prediction
    result = fss.simulate(image, read_noise=10, dark_current=1)
    assert result.report["sensor"] == {
        "read_noise_electrons": 10.0, "dark_current_electrons_per_slot": 1.0,
        "full_well_electrons": None, "adc_bits": 0, "adc_gain_electrons_per_count": 1.0}
    assert result.prediction["exact"] is True
    assert result.prediction["rmse"] > plain.prediction["rmse"]
    with pytest.raises(ValueError, match="read_noise = -1: must be finite and >= 0"):
        fss.simulate(image, read_noise=-1)
