"""SimulationResult.trial_metrics: each trial's metrics as float64 arrays, trial t
the run of seed + t, whose statistics are report.json's trials section; and a
readable repr."""

import numpy as np
import pytest

import fss

GAINS = [1.0, 0.0, 1.0, 1.0]
KEYS = {"rmse", "psnr", "rmse_ci", "psnr_ci", "mse", "ssim"}


def gray_levels(seed, shape=(16, 96)):
    return np.random.default_rng(seed).integers(0, 256, shape).astype(np.uint8)


@pytest.mark.parametrize("seed", [0, 7, 2**64 - 3])
def test_trial_t_is_the_run_of_seed_plus_t(seed):
    image = gray_levels(1)
    result = fss.simulate(image, code=GAINS, seed=seed, trials=3)
    metrics = result.trial_metrics
    assert set(metrics) == KEYS
    for name, values in metrics.items():
        assert values.dtype == np.float64 and values.shape == (3,), name
    for t in range(3):
        alone = fss.simulate(image, code=GAINS, seed=seed + t).metrics
        for name in KEYS - {"mse"}:
            assert metrics[name][t] == alone[name], (name, t)
    np.testing.assert_array_equal(metrics["mse"], metrics["rmse"] ** 2)
    assert metrics["rmse"][0] == result.metrics["rmse"]


def test_the_trials_statistics_are_those_of_the_arrays():
    result = fss.simulate(gray_levels(2), code=GAINS, seed=3, trials=6)
    m, t = result.trial_metrics, result.trials
    for name in ("rmse", "rmse_ci", "ssim"):
        assert t[f"{name}_mean"] == pytest.approx(np.mean(m[name]), rel=1e-12)
        assert t[f"{name}_sd"] == pytest.approx(np.std(m[name], ddof=1), rel=1e-6)
    assert t["n"] == 6


def test_without_ssim_there_is_no_ssim_column():
    with pytest.warns(fss.FssimWarning, match="SSIM is null"):
        result = fss.simulate(gray_levels(3), code=GAINS, rmse_margin=3, trials=2)
    assert result.metrics["ssim"] is None
    assert set(result.trial_metrics) == KEYS - {"ssim"}


def test_under_a_velocity_distribution_one_value_a_trial():
    result = fss.simulate(gray_levels(4), code=GAINS, trials=5,
                          velocity_distribution="uniform:0.5:1.5")
    assert result.trial_velocities.shape == (5,)
    assert all(values.shape == (5,) for values in result.trial_metrics.values())
    assert result.trials["mse_mean"] == pytest.approx(np.mean(result.trial_metrics["mse"]),
                                                      rel=1e-12)


def test_the_repr_is_one_readable_line():
    result = fss.simulate(gray_levels(5), code=GAINS, velocity=0.5, trials=2)
    text = repr(result)
    assert "\n" not in text and len(text) < 200, text
    assert text.startswith("<fss.SimulationResult code 'array', velocity 0.5, snr 100, 2 trials: ")
    assert f"rmse {result.metrics['rmse']:.4g}" in text
    assert f"restored {result.restored.shape[0]} x {result.restored.shape[1]}" in text
    assert text.endswith("0 warnings>")


def test_a_result_pickles_and_comes_back_from_a_process(camera_array):
    """A result crosses process boundaries (multiprocessing, concurrent.futures): pickled and
    unpickled, every field is the same."""
    import pickle
    from concurrent.futures import ProcessPoolExecutor
    image = camera_array[:16]
    result = fss.simulate(image, trials=3, seed=5)
    back = pickle.loads(pickle.dumps(result))
    for name in ("observed", "restored", "groundtruth", "trial_velocities"):
        np.testing.assert_array_equal(getattr(back, name), getattr(result, name))
    for name in ("report", "metrics", "prediction", "geometry", "trials", "parameters", "code",
                 "kernel", "warnings"):
        assert getattr(back, name) == getattr(result, name), name
    assert {k: list(v) for k, v in back.trial_metrics.items()} == \
        {k: list(v) for k, v in result.trial_metrics.items()}
    assert repr(back) == repr(result)
    with ProcessPoolExecutor(max_workers=1) as pool:
        remote = pool.submit(fss.simulate, image, trials=3, seed=5).result()
    assert remote.metrics == result.metrics
    np.testing.assert_array_equal(remote.restored, result.restored)
