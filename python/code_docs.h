// The docstrings of the code tools (code_bindings.cpp), numpydoc, each beginning with its text
// signature ("name(sig)\n--\n\n", which inspect.signature reads).
#pragma once

namespace fss::python {

inline constexpr const char* kAnalyzeDoc =
    R"(analyze_code(code, *, velocity=None, dt=1.0, snr=100.0, mode='numerical', grid=0, velocity_distribution=None, read_noise=0.0, dark_current=0.0, adc_bits=0, adc_gain=None, full_well=None, restoration='inverse', regularization=None, prior=None)
--

Figures of merit of a code without an image, as ``fssim code analyze``.

The stationary, image-independent figure of merit (docs/method.md §6): the SNR at level 100,
snr / sqrt(Q M) for the paper's inverse filter, with the sums of the gains, min |K| on the band,
Q, M and the ratio to the snapshot's SNR.

Parameters
----------
code : str, path or sequence of float
    A built-in code name (``builtin_codes()``), a code file, or the gains.
velocity : float, optional
    Pixels per time slot; None is 1. Refused together with `velocity_distribution`.
dt : float, default 1.0
    Time slot length, > 0.
snr : float, default 100.0
    SNR of a level-100 landscape seen through one slot.
mode : {'numerical', 'analog'}, default 'numerical'
grid : int, default 0
    M on the N-point DFT grid (the simulator's N = 2 (W - B) gives its own M); 0: an 8192-node
    midpoint rule. At most 65536; the inverse filter only.
velocity_distribution : str or path, optional
    A distribution of velocities (docs/method.md §13): 'uniform:LO:HI', 'normal:MEAN:SD'
    (truncated at MEAN +/- 4 SD), 'normal:MEAN:SD:LO:HI', or the path of a file of
    'velocity weight' lines. The figure of merit is then the expected error over it, each
    velocity restored at itself. Needs |v| dt < 2 over the support.
read_noise : float, default 0.0
    Sensor read noise, electrons RMS per readout (docs/method.md §10).
dark_current : float, default 0.0
    Sensor dark current, electrons per unit slot.
adc_bits : int, default 0
    ADC resolution, 1 to 32 bits; 0: no ADC.
adc_gain : float, optional
    ADC gain, electrons per count (default 1); needs `adc_bits`.
full_well : float, optional
    Refused: the figure of merit is linear in the charge (``simulate(full_well=...)`` shows
    saturation).
restoration : {'inverse', 'wiener', 'tikhonov'}, default 'inverse'
    The restoration the figure of merit assumes (docs/method.md §12).
regularization : float or 'optimal', optional
    Tikhonov only: lambda in [1e-8, 100], or 'optimal' (the default): the lambda minimising the
    figure.
prior : str, optional
    Wiener only: 'power-law[:GAMMA[:C]]', the prior C |xi|^-GAMMA of a level-100 landscape
    (default 'power-law:2:180').

Returns
-------
dict
    The setting (length, mode, velocity, dt, snr, grid), the names of
    ``fssim code analyze --json``'s "analysis" section (sum, square_sum, normalized_l1, k0,
    min_abs, min_abs_xi, invertible, q, m, noise_figure, snr_level100, snapshot_snr_level100,
    ratio_to_snapshot, snr_level100_bound), and warnings (list of str). Numbers are floats:
    m and noise_figure are inf for a code that is not invertible, snr_level100_bound is inf
    where there is no bound. With a sensor also sensor (its parameters), readouts,
    readout_variance_electrons2, effective_q and effective_noise_figure; with a Wiener or
    Tikhonov restoration also restoration (method, prior, gamma, C; Tikhonov: lambda, None
    where the error is infinite, and lambda_optimal), restoration_error and (Tikhonov)
    snapshot_regularization. Under a distribution velocity is None, and the dict also holds
    velocity_distribution (spec, description, low, high; mean and sd, or points),
    kernel_velocity, restoration_error, worst_velocity, worst_snr_level100 and quadrature.

Raises
------
ValueError
    A value out of range, a keyword the restoration does not take, full_well, a DFT grid with
    another restoration than the inverse filter, a code the mode cannot use, a distribution
    that does not parse or is given with `velocity`; one line naming the keyword.
TypeError
    A keyword of the wrong type.
RuntimeError
    A code or velocity file that cannot be read.

Warns
-----
FssimWarning
    With an ADC, when the mean level-100 readout passes the top of its range (the figure of
    merit counts its rounding, not its clipping), as fssim warns.

Examples
--------
>>> a = fss.analyze_code('raskar', velocity=0.5)
>>> a['invertible'], a['snr_level100'] > 0
(True, True)
>>> w = fss.analyze_code('mip', restoration='wiener', prior='power-law:2')
>>> w['restoration']['method'], w['restoration_error'] > 0
('wiener', True)
)";

inline constexpr const char* kOptimizeDoc =
    R"(optimize_code(*, length, velocity=None, velocity_distribution=None, dt=1.0, snr=100.0, mode='numerical', binary=False, min_light=0.0, restarts=24, iterations=300, seed=0, grid_points=2048, read_noise=0.0, dark_current=0.0, adc_bits=0, adc_gain=None, full_well=None, restoration='inverse', regularization=None, prior=None)
--

The code of a length that maximizes the SNR at level 100, as ``fssim code optimize``.

Parameters
----------
length : int
    Number of gains L.
velocity : float, optional
    Pixels per time slot, 0 < |velocity| dt < 2. Give it or `velocity_distribution`.
velocity_distribution : str or path, optional
    A distribution of velocities, as analyze_code's: the search maximizes the SNR of the
    expected error over it. Refused with `velocity`.
dt : float, default 1.0
snr : float, default 100.0
    Scales the reported SNR only, unless a sensor keyword adds readout noise.
mode : {'numerical', 'analog'}, default 'numerical'
    Any real gains, or gains in [0, 1].
binary : bool, default False
    Gains in {0, 1} (the Agrawal-Raskar search space).
min_light : float, default 0.0
    Light budget of analog or binary codes: sum of gains >= this (slots).
restarts : int, default 24
    Random starting codes, at most 10000.
iterations : int, default 300
    Per start: quasi-Newton iterations or moves of the binary search, at most 100000.
seed : int, default 0
    Seed of the random starts.
grid_points : int, default 2048
    Frequencies of the search's objective (the result is analysed as analyze_code does).
read_noise, dark_current, adc_bits, adc_gain, full_well, restoration, regularization, prior
    As analyze_code's: the sensor and the restoration the figure of merit assumes.

Returns
-------
dict
    gains (float64 array), analysis (as analyze_code returns it; its warnings empty, as
    fssim code optimize warns nothing), starts, best_start, iterations, evaluations.

Raises
------
ValueError
    A value out of range, neither or both of `velocity` and `velocity_distribution`, a light
    budget for numerical gains, a sensor whose readout noise passes double precision; one line
    naming the keyword.
TypeError
    A keyword of the wrong type.
RuntimeError
    A velocity file that cannot be read.

Examples
--------
>>> r = fss.optimize_code(length=16, velocity=1.0, restarts=4)
>>> r['gains'].shape, r['analysis']['snr_level100'] > 0  # doctest: +SKIP
((16,), True)
)";

inline constexpr const char* kGenerateDoc =
    R"(generate_code(family, *, length, velocity=None, dt=None, seed=None, analog=None)
--

The gains of a generated code, as ``fssim code generate``.

Parameters
----------
family : {'sinc', 'mip', 'random', 'snapshot', 'accumulation'}
    The paper's constructions for a velocity (sinc, mip), random gains, the snapshot
    (1, 0, ..., 0) or the accumulation (all ones).
length : int
    Number of gains L.
velocity : float, optional
    sinc and mip only: the velocity the code is designed for (default 1), 0 < |v| dt < 2.
dt : float, optional
    sinc and mip only: the time slot length (default 1).
seed : int, optional
    random only: the seed of the gains (default 0).
analog : bool, optional
    random only: gains on [0, 1) instead of [-1, 1) (default False).

Returns
-------
numpy.ndarray
    The gains, float64, shape (length,).

Raises
------
ValueError
    An unknown family, a value out of range, or a keyword the family does not use (as fssim
    refuses the option); one line naming the keyword.
TypeError
    A keyword of the wrong type.

Examples
--------
>>> fss.generate_code('snapshot', length=4)
array([1., 0., 0., 0.])
)";

inline constexpr const char* kTransferDoc =
    R"(transfer_function(code, xi, *, velocity=1.0, dt=1.0)
--

K(xi), the transfer function of a code at frequencies xi (radians per pixel).

K(xi) = dt sinc_h(theta) sum_k alpha_k exp(-i theta (k + 1/2)), theta = xi velocity dt
(docs/method.md §1).

Parameters
----------
code : str, path or sequence of float
    A built-in code name, a code file, or the gains.
xi : float or array_like of float
velocity : float, default 1.0
dt : float, default 1.0

Returns
-------
complex or numpy.ndarray
    A complex for a number, else a complex128 array of xi's shape.

Raises
------
ValueError
    A value that is not finite, a complex xi, a K that leaves the range of doubles.
TypeError
    A keyword of the wrong type.

Examples
--------
>>> fss.transfer_function('raskar', 0.0)
(26+0j)
)";

inline constexpr const char* kReadCodeDoc =
    R"(read_code(code)
--

The gains of a built-in code or a code file.

Parameters
----------
code : str or path
    A built-in name (``builtin_codes()``) or the path of a code file (docs/designing-codes.md).

Returns
-------
numpy.ndarray
    The gains, float64.

Raises
------
ValueError
    A code that is neither a built-in name nor a readable code file, malformed gains.
RuntimeError
    A code file that cannot be read.

Examples
--------
>>> fss.read_code('snapshot')[:3]  # doctest: +SKIP
array([1., 0., 0.])
)";

inline constexpr const char* kBuiltinCodesDoc =
    R"(builtin_codes()
--

The names of the built-in codes.

Returns
-------
list of str
    'snapshot', 'accumulation', 'raskar', 'random', 'mip', 'sinc'.

Examples
--------
>>> 'raskar' in fss.builtin_codes()
True
)";

}  // namespace fss::python
