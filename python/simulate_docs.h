// The docstrings of fss.simulate, fss.simulate_to_folder and fss.SimulationResult
// (simulate_bindings.cpp), numpydoc, each function's beginning with its text signature
// ("name(sig)\n--\n\n", which inspect.signature reads).
#pragma once

#include <string>

namespace fss::python {

// The numpydoc Parameters entries the simulations share (fss.simulate, fss.simulate_to_folder).
inline constexpr const char* kSimulationParameters =
    R"(code : str, path or sequence of float, default 'raskar'
    A built-in code name (fss.builtin_codes()), a code file, or the gains.
mode : {'numerical', 'analog'}, default 'numerical'
velocity : float, optional
    The velocity in pixels per time slot (any sign); None is 1. Refused together with
    `velocity_distribution`.
snr : float, default 100
    The SNR of a constant landscape at level 100 seen through one unit slot (docs/method.md
    §3).
dt : float, default 1
    The time slot length.
seed : int, default 0
    Trial t draws its noise (and, under a distribution, its velocity) from seed + t.
trials : int, default 1
noise : {'poisson', 'aggregated', 'none'}, default 'poisson'
restore_velocity : float, optional
    The velocity the restoration assumes; None: the true one (each trial's under a
    distribution).
threads : int, default 0
    0: all hardware threads; never changes a result.
rmse_margin : int or 'auto', optional
    Columns left out at each side for the RMSE; None: 3 B; 'auto': 3 B where the image is
    wide enough (W >= 9 B + 1), else the largest margin leaving a window of B columns (with
    a FssimWarning when below 3 B).
max_memory : int, default 0
    Bytes; refuses, before allocating, a run estimated to need more (0: no limit).
read_noise, dark_current : float, default 0
    The sensor (docs/method.md §10): electrons RMS per readout, electrons per slot.
full_well : float, optional
    Electrons; None: none.
adc_bits : int, default 0
    0: no ADC.
adc_gain : float, optional
    Electrons per count (default 1); only with `adc_bits`.
restoration : {'inverse', 'tikhonov', 'wiener'}, default 'inverse'
    docs/method.md §12; ``report['restoration']`` says what was applied.
regularization : float or 'optimal', optional
    Tikhonov's lambda in [1e-8, 1e2]; None or 'optimal': the lambda minimising the run's exact
    expected error. `restoration` 'tikhonov' only.
prior : str, optional
    Wiener's prior: 'power-law', 'power-law:GAMMA' or 'oracle' (None: 'power-law:2').
    `restoration` 'wiener' only.
velocity_distribution : str or path, optional
    A distribution of velocities (docs/method.md §13): 'uniform:LO:HI', 'normal:MEAN:SD'
    (truncated at MEAN +/- 4 SD and renormalised), 'normal:MEAN:SD:LO:HI' (truncated), or the
    path of a file of "velocity weight" lines (a discrete distribution, weights normalised).
    Each trial draws its velocity from it, from `seed` and its index only (never from
    `threads`); the restoration uses the drawn velocity unless `restore_velocity` is given;
    the geometry is that of the support's largest |velocity|, the same for every trial. A
    restoration the library does not allow under a distribution is a ValueError. Refused with
    `velocity`.
)";

inline constexpr const char* kSimulationRaises = R"(
Raises
------
ValueError
    A usage error (an option out of range, an integer argument given 3.5, a code the mode
    cannot use, an image too narrow for the code's blur, a velocity distribution that does not
    parse or is given with `velocity`); one line naming the keyword.
TypeError
    An argument of the wrong type (bool, complex or str where a number is expected).
RuntimeError
    A file that cannot be read (a velocity file that does not parse included), the memory
    limit `max_memory`.
MemoryError
    A failed allocation.

Warns
-----
FssimWarning
    Each warning fssim prints for the same run (a code not invertible at the velocity, a
    margin below 3 B, saturated readouts, ...), one warnings.warn each; they are also in the
    result's ``warnings``. ``warnings.simplefilter('error', fss.FssimWarning)`` makes them
    errors.
)";

inline std::string simulate_doc() {
  return std::string(
             R"(simulate(image, *, data_range=None, code='raskar', mode='numerical', velocity=None, snr=100.0, dt=1.0, seed=0, trials=1, noise='poisson', restore_velocity=None, threads=0, rmse_margin=None, max_memory=0, read_noise=0.0, dark_current=0.0, full_well=None, adc_bits=0, adc_gain=None, restoration='inverse', regularization=None, prior=None, velocity_distribution=None)
--

Simulate a flutter shutter run on `image`, as ``fssim --input`` does.

The same image, options and seed give fssim's numbers to the last bit, whatever `threads`.
Every number is checked as fssim checks its option (a ValueError naming the keyword); any
Python or numpy integer or float is taken where a number is expected (integer keywords take
3.0, not 3.5).

Parameters
----------
image : array_like
    H x W (gray) or H x W x 3 (RGB), any real dtype and memory layout; never modified.
data_range : float, optional
    The value of gray level 255: each value becomes value x 255 / data_range (255: the values
    as they are; 1: floats on [0, 1]). None: 255 for uint8 and 65535 for uint16 (v / 257, as
    fssim reads a 16-bit PNG, so ``simulate(read_png(p))`` is ``fssim --input p``); any other
    dtype (floats, other integers, bool, lists) needs it.
)") + kSimulationParameters +
         R"(
Returns
-------
SimulationResult
    The observed, restored and ground truth crops (float64 gray levels, 0..255 scale), the
    sections of report.json as dicts (infinite or NaN numbers as float('inf') or
    float('nan'); None only where a value does not apply) and each trial's metrics as
    float64 arrays (``trial_metrics``). Under a velocity distribution, ``trial_velocities``
    holds each trial's velocity and ``prediction['mse']`` the exact E[MSE] over the
    distribution, which ``trials['mse_mean']`` estimates.
)" + kSimulationRaises +
         R"(
See Also
--------
simulate_to_folder : the same run from an image file, writing fssim's output folder.
read_image : an image file as an array for `image`.

Examples
--------
>>> import numpy as np
>>> import fss
>>> image = np.tile(np.arange(0, 256, 4, dtype=np.uint8), (64, 8))  # 64 x 512 gray levels
>>> r = fss.simulate(image, code='raskar', velocity=1.0, snr=100, seed=0, trials=4)
>>> r.restored.shape
(64, 356)
>>> r.trial_metrics['rmse'].shape
(4,)

A float image on [0, 1] states its scale:

>>> r1 = fss.simulate(image / 255.0, data_range=1, seed=0, trials=4)
>>> bool(r1.metrics['rmse'] == r.metrics['rmse'])
True
)";
}

inline std::string simulate_to_folder_doc() {
  return std::string(
             R"(simulate_to_folder(input, outdir, *, code='raskar', mode='numerical', velocity=None, snr=100.0, dt=1.0, seed=0, trials=1, noise='poisson', restore_velocity=None, threads=0, rmse_margin=None, max_memory=0, read_noise=0.0, dark_current=0.0, full_well=None, adc_bits=0, adc_gain=None, restoration='inverse', regularization=None, prior=None, velocity_distribution=None, plots=True, sheet=False, report=False, save_float=False, png_depth='8')
--

Run ``fssim --input INPUT --outdir OUTDIR`` from Python.

Reads the image file as fssim does (a 16-bit sample v is the gray level v / 257, a float TIFF
sample is a gray level as it is; there is no `data_range`), simulates and writes the same
files, byte for byte, all of them or none. `max_memory` refuses a run from the file's header,
before decoding.

Parameters
----------
input : str, bytes or os.PathLike
    A PNG or TIFF file.
outdir : str, bytes or os.PathLike
    The output folder, created if missing.
)") + kSimulationParameters +
         R"(plots, sheet, report, save_float : bool
    As fssim's --no-plots (negated), --sheet, --report and --save-float.
png_depth : {'8', '16', 'auto', 8, 16}, default '8'
    Bits a sample of observed, restored, groundtruth and residual.png ('auto': 16 for a
    16-bit or float input).

Returns
-------
dict
    report.json as a dict (the keys of SimulationResult.report), its infinite or NaN numbers
    as floats.
)" + kSimulationRaises +
         R"(
Examples
--------
>>> report = fss.simulate_to_folder('input.png', 'out', code='raskar', seed=1)  # doctest: +SKIP
>>> sorted(report)  # doctest: +SKIP
['code', 'fssim_version', 'geometry', 'input', 'kernel', 'metrics', 'parameters', ...]
)";
}

inline constexpr const char* kSimulationResultDoc =
    R"(What fss.simulate returns: the images as float64 arrays and report.json's sections as dicts.

The dicts hold report.json's content (docs/report-schema.md) with infinite or NaN numbers as
float('inf') or float('nan'), None only where a value does not apply. Every image is on the
0..255 gray-level scale, neither rounded nor clamped, H x Wo (gray) or H x Wo x 3 (RGB): the
output crop, input columns [geometry['output_first_input_column'], + Wo).

Attributes
----------
observed : numpy.ndarray
    The first trial's observation divided by K(0).
restored : numpy.ndarray
    The first trial's restoration.
groundtruth : numpy.ndarray
    The input on the same crop.
metrics : dict
    The first trial's errors against the ground truth, in gray levels: 'rmse' (over the RMSE
    window), 'psnr' (20 log10(255 / rmse), dB), 'rmse_ci' and 'psnr_ci' (contrast-invariant),
    'ssim' (None when no pixel is far enough from the window's edges).
prediction : dict
    The predicted error (docs/method.md §6, §6b): 'finite' (False for a code not invertible
    under the inverse filter; then 'rmse', 'noise', 'sigma', 'rmse_stationary' and 'm' are
    inf), 'rmse' (the exact expected RMSE), 'rmse_noise_free', 'noise', 'sigma', 'rmse_stationary', 'snr_level100' (None for a
    restoration other than the inverse filter), 'window_mean', 'q', 'm'; 'exact' with a
    sensor; under a velocity distribution 'mse', 'mse_error_estimate', 'mse_evaluations',
    'mse_infinite_reason'.
trials : dict
    Over all trials: 'n', 'rmse_mean', 'rmse_sd', 'rmse_ci_mean', 'rmse_ci_sd', 'ssim_mean',
    'ssim_sd' (sample standard deviations, 0 for one trial); under a velocity distribution
    'mse_mean', 'mse_sd', 'velocities'.
trial_metrics : dict of numpy.ndarray
    Each trial's metrics, trial t (noise from seed + t) at index t, float64 arrays of length
    `trials`: 'rmse', 'psnr', 'rmse_ci', 'psnr_ci', 'mse' (rmse squared), and 'ssim' when every
    trial has one.
trial_velocities : numpy.ndarray
    Each trial's velocity under a velocity distribution (float64; empty without one).
geometry : dict
    'blur_length' (B), 'observed_width', 'mirror_width', 'output_width' (Wo),
    'output_first_input_column' (the input column of the crop's first column),
    'rmse_columns' and 'rmse_ci_columns' (the windows [first, end), output columns).
parameters : dict
    The run's options: 'code', 'code_length', 'mode', 'velocity' (None under a distribution),
    'restore_velocity', 'dt', 'snr', 'seed', 'noise', 'trials'; 'velocity_distribution'
    under one.
code : dict
    'name', 'gains', 'sum', 'square_sum', 'normalized_l1'.
kernel : dict
    The transfer function at the restore velocity: 'k0' (K(0)), 'min_abs' and 'min_abs_xi'
    (min |K| and where), 'invertible', 'observed_divisor', 'zero_bins'.
warnings : list of str
    The warnings fssim prints for the run (each also warned as an FssimWarning).
report : dict
    All of report.json: the sections above and 'schema_version', 'fssim_version', 'input';
    'sensor' with a sensor, 'restoration' for a restoration other than the inverse filter.
)";

}  // namespace fss::python
