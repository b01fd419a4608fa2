"""numpy conventions of fss.simulate (docs/python.md): any Python or numpy real
scalar where a number is expected, integral floats for integer parameters; an
explicit scale for images that are not uint8 or uint16 (data_range=), the
numbers of the gray-level image to the last bit; short errors in Python words
that never echo an array; inf and nan as floats."""

import shutil

import numpy as np
import pytest

import fss
from conftest import read_png8

# A short code (B = 4 at velocity 1) and small images wide enough for it.
GAINS = [1.0, 0.0, 1.0, 1.0]
SEEDS = [0, 1, 2, 3, 4]


def gray_levels(seed, shape=(16, 96)):
    return np.random.default_rng(seed).integers(0, 256, shape).astype(np.uint8)


def assert_same_run(a, b):
    for output in ("observed", "restored", "groundtruth"):
        np.testing.assert_array_equal(getattr(a, output), getattr(b, output), err_msg=output)
    assert a.report == b.report


# ---------------------------------------------------------------------------
# Scalars


@pytest.mark.parametrize("keywords", [
    {"seed": np.int64(3), "trials": np.uint8(2), "threads": np.int32(1), "snr": np.float32(50)},
    {"seed": 3.0, "trials": 2.0, "threads": 1.0, "snr": 50},
    {"seed": np.float64(3.0), "trials": np.array(2), "threads": np.array(1.0),
     "snr": np.array(50.0)},
    {"seed": np.uint64(3), "trials": np.int8(2), "threads": np.int64(1), "snr": np.int16(50)},
], ids=["numpy_scalars", "integral_floats", "numpy_floats_and_0d_arrays", "numpy_integers"])
def test_numpy_scalars_and_integral_floats_are_numbers(keywords):
    image = gray_levels(0)
    reference = fss.simulate(image, code=GAINS, seed=3, trials=2, threads=1, snr=50.0)
    assert_same_run(fss.simulate(image, code=GAINS, **keywords), reference)


@pytest.mark.parametrize("argument", ["seed", "trials", "threads", "rmse_margin", "adc_bits",
                                      "max_memory"])
@pytest.mark.parametrize("value", [3.5, np.float32(3.5), np.array(3.5)])
def test_a_fraction_is_refused_naming_the_parameter(argument, value):
    with pytest.raises(ValueError) as error:
        fss.simulate(gray_levels(0), code=GAINS, **{argument: value})
    assert str(error.value) == f"{argument} = 3.5: must be an integer"


@pytest.mark.parametrize("argument", ["seed", "snr", "velocity", "data_range", "trials"])
@pytest.mark.parametrize("value", [True, np.bool_(False), 1j, "3", np.array([3.0])])
def test_bool_complex_text_and_arrays_are_not_numbers(argument, value):
    with pytest.raises(TypeError) as error:
        fss.simulate(gray_levels(0), code=GAINS, **{argument: value})
    message = str(error.value)
    assert message.startswith(f"{argument}: expected ") and len(message) < 100, message


# ---------------------------------------------------------------------------
# Images and data_range


@pytest.mark.parametrize("dtype", [np.float64, np.float32, np.int64, np.int16, np.uint32, bool])
def test_an_image_that_is_not_uint8_or_uint16_needs_data_range(dtype):
    image = gray_levels(0).astype(dtype)
    with pytest.raises(ValueError) as error:
        fss.simulate(image, code=GAINS)
    assert str(error.value) == (
        f"image: dtype {np.dtype(dtype)} needs data_range= (255 for gray levels 0..255, "
        "1 for floats on [0, 1])")


def test_a_list_image_needs_data_range_and_is_then_gray_levels():
    image = gray_levels(1)
    with pytest.raises(ValueError, match=r"^image: dtype int64 needs data_range="):
        fss.simulate(image.tolist(), code=GAINS)
    assert_same_run(fss.simulate(image.tolist(), data_range=255, code=GAINS),
                    fss.simulate(image, code=GAINS))


@pytest.mark.parametrize("seed", SEEDS)
def test_floats_on_0_1_with_data_range_1_are_the_gray_levels_to_the_bit(seed):
    # k / 255 in float64, for every k in 0..255 and a random image of them (gray and RGB).
    every_level = np.arange(256, dtype=np.uint8).reshape(1, 256).repeat(12, axis=0)
    for image in (gray_levels(seed), gray_levels(seed, (12, 64, 3)), every_level):
        keywords = {"code": GAINS, "seed": seed, "trials": 2}
        assert_same_run(fss.simulate(image / 255.0, data_range=1, **keywords),
                        fss.simulate(image, **keywords))


@pytest.mark.parametrize("seed", SEEDS)
def test_uint16_is_divided_by_257_as_fssim_reads_a_16_bit_png(seed):
    image = gray_levels(seed)
    keywords = {"code": GAINS, "seed": seed}
    reference = fss.simulate(image, **keywords)
    assert_same_run(fss.simulate(image.astype(np.uint16) * 257, **keywords), reference)
    assert_same_run(fss.simulate(image.astype(np.uint16) * 257, data_range=65535, **keywords),
                    reference)
    swapped = (image.astype(np.uint16) * 257).astype(">u2")  # converted to float64 first
    assert_same_run(fss.simulate(swapped, **keywords), reference)
    # any 16-bit value v is the gray level v / 257 to the bit
    values = np.random.default_rng(seed).integers(0, 65536, (16, 96)).astype(np.uint16)
    noise_free = {"code": GAINS, "noise": "none"}
    assert_same_run(fss.simulate(values, **noise_free),
                    fss.simulate(values / 257.0, data_range=255, **noise_free))


def test_data_range_scales_every_value():
    image = gray_levels(2)
    reference = fss.simulate(image, code=GAINS)
    # 2 v on a range of 510 is v; uint8 with data_range 255 is as without
    assert_same_run(fss.simulate(image.astype(np.int64) * 2, data_range=510, code=GAINS),
                    reference)
    assert_same_run(fss.simulate(image, data_range=255.0, code=GAINS), reference)


@pytest.mark.parametrize("value", [0, -1, float("nan"), float("inf"), -0.0])
def test_data_range_must_be_a_positive_finite_number(value):
    with pytest.raises(ValueError, match=r"^data_range = \S+: must be a finite number > 0"):
        fss.simulate(gray_levels(0), data_range=value, code=GAINS)


def test_a_gray_level_beyond_doubles_is_refused():
    image = np.full((16, 96), 1e308)
    with pytest.raises(ValueError, match=r"^image: value 1e\+308 at row 0, column 0 has no finite "
                                         r"gray level"):
        fss.simulate(image, data_range=1, code=GAINS)


def test_read_png_then_simulate_needs_no_scale(camera):
    image = fss.read_png(camera)
    assert image.dtype == np.uint8
    assert_same_run(fss.simulate(image), fss.simulate(read_png8(camera)))


# ---------------------------------------------------------------------------
# Messages never echo an array


@pytest.mark.parametrize("call", [
    lambda big: fss.simulate(big),
    lambda big: fss.simulate(big.reshape(1000, 1000).tolist()),
    lambda big: fss.simulate(big.tolist()),
    lambda big: fss.simulate(big.reshape(1000, 1000), data_range=big),
    lambda big: fss.simulate(gray_levels(0), code=GAINS, seed=big),
    lambda big: fss.simulate(gray_levels(0), code=GAINS, snr=big.tolist()),
    lambda big: fss.simulate(gray_levels(0), code=big.tolist()),
    lambda big: fss.simulate(gray_levels(0), code=GAINS, mode=big),
], ids=["array", "list_2d", "list_1d", "data_range", "seed", "snr", "code", "mode"])
def test_messages_never_echo_an_array(call):
    big = np.arange(10**6, dtype=np.int64) + 123456
    with pytest.raises((ValueError, TypeError)) as error:
        call(big)
    message = str(error.value)
    assert len(message) < 300 and "\n" not in message, message
    assert "123457" not in message and "123458" not in message, message


# ---------------------------------------------------------------------------
# inf and nan are floats


def test_an_infinite_prediction_is_a_float_and_a_column_of_them_is_a_float_array():
    image = gray_levels(3)
    with pytest.warns(fss.FssimWarning):
        infinite = fss.simulate(image, code=[1, 1], velocity=2)  # K(pi / 2) = 0
    assert infinite.prediction["finite"] is False
    assert infinite.prediction["rmse"] == float("inf")
    assert type(infinite.prediction["rmse"]) is float
    column = np.array([fss.simulate(image, code=[1, 1], velocity=v).prediction["rmse"]
                       for v in (0.25, 0.5, 0.75)] + [infinite.prediction["rmse"]])
    assert column.dtype == np.float64
    assert np.isinf(np.round(column, 2)[-1]) and np.all(np.isfinite(column[:-1]))


def test_none_only_where_a_value_does_not_apply(camera):
    wiener = fss.simulate(gray_levels(4, (16, 128)), code=GAINS, restoration="wiener")
    assert wiener.prediction["snr_level100"] is None  # needs a prior: not given by a run
    with pytest.warns(fss.FssimWarning, match="SSIM is null"):
        narrow = fss.simulate(gray_levels(4), code=GAINS, rmse_margin=3)
    assert narrow.metrics["ssim"] is None  # no pixel 5 columns inside the window
    distribution = fss.simulate(gray_levels(4), code=GAINS, velocity_distribution="uniform:1:2")
    assert distribution.parameters["velocity"] is None


# ---------------------------------------------------------------------------
# Errors speak Python


def test_the_narrow_image_advice_speaks_python():
    with pytest.raises(ValueError) as error:
        fss.simulate(gray_levels(0, (16, 28)), code=GAINS)
    message = str(error.value)
    assert message.endswith("choose a margin below 8 with rmse_margin, or rmse_margin='auto'"), \
        message
    with pytest.raises(ValueError) as error:
        fss.simulate(gray_levels(0, (16, 20)), code=GAINS, rmse_margin="auto")
    assert str(error.value).endswith("(5B + 1), which no rmse_margin can change"), str(error.value)


def test_the_analog_advice_speaks_python():
    with pytest.raises(ValueError) as error:
        fss.simulate(gray_levels(0), code=[1.0, 2.0, 1.0], mode="analog")
    assert str(error.value).endswith("analog gains must lie in [0, 1] (use mode='numerical')")


def test_noise_names_every_model():
    with pytest.raises(ValueError) as error:
        fss.simulate(gray_levels(0), code=GAINS, noise="gaussian")
    assert str(error.value) == "noise: 'gaussian' is not 'poisson', 'aggregated' or 'none'"


def test_the_outdir_advice_speaks_python(tmp_path, camera):
    source = tmp_path / "observed.png"
    shutil.copyfile(camera, source)
    with pytest.raises(RuntimeError) as error:
        fss.simulate_to_folder(source, tmp_path, plots=False)
    assert str(error.value).endswith("': choose another outdir"), str(error.value)
    assert source.read_bytes() == camera.read_bytes()


@pytest.mark.parametrize("name", ["--data.png", "--code.txt", "my --raw-file.png", "--mode numerical"])
def test_names_in_messages_are_kept_as_given(tmp_path, name):
    """Only fssim's own options become Python words; a file named like one stays as it is."""
    with pytest.raises(RuntimeError) as caught:
        fss.read_png(tmp_path / name)
    assert name in str(caught.value)
    with pytest.raises((ValueError, RuntimeError)) as caught:
        fss.simulate(np.zeros((8, 64), np.uint8), code=str(tmp_path / name))
    assert name in str(caught.value)
