"""The restorations of fss.simulate (docs/method.md §12) and its SSIM (§5): SSIM against
scikit-image's structural_similarity on the double-precision restoration, the keywords'
rules, and what report['restoration'] records."""

import numpy as np
import pytest

import fss

skimage_metrics = pytest.importorskip("skimage.metrics")

RESTORATIONS = [
    {},
    {"restoration": "tikhonov", "regularization": 1e-3},
    {"restoration": "tikhonov"},
    {"restoration": "wiener"},
    {"restoration": "wiener", "prior": "oracle"},
]


def skimage_ssim(result):
    """scikit-image's SSIM over the RMSE window widened by the window's radius (5)."""
    first, end = result.geometry["rmse_columns"]
    truth = np.asarray(result.groundtruth, dtype=np.float64)
    restored = result.restored
    extra = {} if truth.ndim == 2 else {"channel_axis": 2}
    return skimage_metrics.structural_similarity(
        truth[:, first - 5:end + 5], restored[:, first - 5:end + 5], gaussian_weights=True,
        sigma=1.5, use_sample_covariance=False, data_range=255, **extra)


@pytest.mark.parametrize("keywords", RESTORATIONS)
def test_ssim_matches_scikit_image(camera_array, keywords):
    result = fss.simulate(camera_array, seed=2, **keywords)
    assert result.metrics["ssim"] == pytest.approx(skimage_ssim(result), abs=1e-8)


def test_ssim_matches_scikit_image_in_colour(astronaut_array):
    result = fss.simulate(astronaut_array, mode="analog", rmse_margin=20)
    assert result.metrics["ssim"] == pytest.approx(skimage_ssim(result), abs=1e-8)


def test_ssim_is_null_with_a_warning_when_no_pixel_is_left(camera_array):
    with pytest.warns(fss.FssimWarning, match="SSIM is null"):
        result = fss.simulate(camera_array, rmse_margin=3)
    assert result.metrics["ssim"] is None
    assert any("SSIM is null" in w for w in result.warnings)


def test_trials_give_the_ssim_mean_and_sd(camera_array):
    result = fss.simulate(camera_array, trials=3, noise="aggregated")
    assert 0 < result.trials["ssim_sd"] < 0.01
    assert abs(result.trials["ssim_mean"] - result.metrics["ssim"]) < 0.01


def test_report_records_the_restoration(camera_array):
    assert "restoration" not in fss.simulate(camera_array).report
    tikhonov = fss.simulate(camera_array, restoration="tikhonov").report["restoration"]
    assert tikhonov["regularization_optimal"] is True
    assert 1e-8 <= tikhonov["regularization"] <= 1e2
    wiener = fss.simulate(camera_array, restoration="wiener").report["restoration"]
    assert wiener["prior"] == "power-law" and wiener["prior_exponent"] == 2
    assert wiener["prior_level"] > 0 and wiener["noise_variance"] > 0
    result = fss.simulate(camera_array, restoration="wiener")
    assert result.prediction["snr_level100"] is None
    assert result.prediction["finite"] is True


def test_a_code_that_is_not_invertible_gets_a_finite_prediction(camera_array):
    with pytest.warns(fss.FssimWarning, match="not invertible"):
        inverse = fss.simulate(camera_array, code="accumulation")
    assert inverse.prediction["finite"] is False
    assert inverse.prediction["rmse"] == float("inf")
    for keywords in RESTORATIONS[1:]:
        with pytest.warns(fss.FssimWarning, match="restoration damps the frequencies"):
            result = fss.simulate(camera_array, code="accumulation", **keywords)
        assert result.prediction["finite"] is True
        assert np.isfinite(result.prediction["rmse"])


@pytest.mark.parametrize("keywords, message", [
    ({"restoration": "lucy"}, "restoration: 'lucy' is not 'inverse', 'tikhonov' or 'wiener'"),
    ({"regularization": 0.1}, "regularization: only restoration='tikhonov'"),
    ({"restoration": "wiener", "regularization": "optimal"}, "regularization: only"),
    ({"restoration": "tikhonov", "regularization": "best"}, "regularization: a string must be"),
    ({"restoration": "tikhonov", "regularization": 0.0}, "regularization = 0: must lie in"),
    ({"restoration": "tikhonov", "regularization": float("nan")}, "regularization"),
    ({"prior": "oracle"}, "prior: only restoration='wiener'"),
    ({"restoration": "wiener", "prior": "power-law:2:100"}, "prior: 'power-law:2:100' gives a level"),
    ({"restoration": "wiener", "prior": "gauss"}, "prior: prior 'gauss': unknown prior"),
])
def test_bad_keywords_are_refused(camera_array, keywords, message):
    with pytest.raises(ValueError) as error:
        fss.simulate(camera_array, **keywords)
    assert message in str(error.value)
    assert "\n" not in str(error.value)
