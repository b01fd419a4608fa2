// The docstrings of the campaign functions (campaign_bindings.cpp), numpydoc, each beginning with
// its text signature ("name(sig)\n--\n\n", which inspect.signature reads).
#pragma once

namespace fss::python {

inline constexpr const char* kRunCampaignDoc =
    R"(run_campaign(spec, outdir, *, threads=0, skip_unrunnable=False, per_trial=None, max_memory=0)
--

Runs a campaign (images x codes x settings) into a directory, as ``fssim campaign``.

Every setting of the product is simulated and written as one row of outdir/results.csv and
results.jsonl (with per_trial, also one row per trial in trials.csv and trials.jsonl), the very
bytes ``fssim campaign -f SPEC -o OUTDIR`` writes (docs/campaign.md). Each setting's seed
derives from the campaign seed and the setting itself. Every finished setting is journalled:
a run interrupted (Ctrl-C, a crash) resumes when called again with the same spec and outdir.

Parameters
----------
spec : dict or str or os.PathLike
    The fields of a campaign file (docs/campaign.md): 'input' (images: files, directories,
    globs), 'code', 'mode', 'velocity' or 'velocity_distribution', 'restore_velocity', 'snr',
    'dt', 'trials', 'seed', 'noise', 'rmse_margin', 'per_trial', 'read_noise',
    'dark_current', 'full_well', 'adc_bits', 'adc_gain', 'restoration', 'regularization',
    'prior'. Lists as lists, numpy arrays or strings ('0.25:1:x2'); paths as str or
    os.PathLike. Or the path of a campaign file. Relative paths are from the current
    directory.
outdir : str or os.PathLike
    The campaign directory (created; the same campaign resumes there, another is refused).
threads : int, default 0
    Threads (0: all). Settings of images of at most 4 Mi samples run side by side, one
    thread each; larger images run one setting at a time on every thread. Never changes a
    result.
skip_unrunnable : bool, default False
    Settings that cannot run (an image too narrow for the blur, a value out of range) are rows
    with their status either way; False raises a RuntimeError once every row is written.
per_trial : bool, optional
    Also one row per trial (trials.csv, read by ``read_campaign(outdir, trials=True)``); None:
    the spec's 'per_trial'.
max_memory : int, default 0
    Bytes each simulation may use; 0: no limit.

Returns
-------
dict of numpy.ndarray
    results.csv's columns, one entry per setting in the product's order: float64 for numbers
    (NaN where a setting has no value), and for the booleans invertible and predicted_exact
    (1.0, 0.0, NaN where the setting did not run); int64 for trials and adc_bits; uint64 for
    seed; str for text (image, code, mode, status, message, ...).

Raises
------
ValueError
    A spec field that does not parse or is out of range, an outdir holding another campaign
    or over an input; one line naming the field or keyword.
RuntimeError
    An image, code or spec file that cannot be read, a directory that cannot be written, or
    settings that cannot run (after every result is written) unless skip_unrunnable.
TypeError
    A keyword of the wrong type.
KeyboardInterrupt
    Ctrl-C, at the end of the running setting (call again to resume).

Warns
-----
FssimWarning
    One warning listing the settings that did not run and why, as fssim lists them on stderr.

See Also
--------
read_campaign : the columns of a campaign directory.

Examples
--------
>>> spec = {'input': 'data/camera.png', 'code': ['raskar', 'mip'],
...         'velocity': [0.25, 0.5], 'trials': 3}
>>> r = fss.run_campaign(spec, 'out/campaign')  # doctest: +SKIP
>>> r['rmse_mean'] / r['predicted_rmse']  # doctest: +SKIP
)";

inline constexpr const char* kReadCampaignDoc =
    R"(read_campaign(path, *, trials=False)
--

The rows of a campaign's results as numpy columns.

Parameters
----------
path : str or os.PathLike
    A campaign directory (its results.csv, or trials.csv with `trials`), or a results.csv or
    trials.csv file.
trials : bool, default False
    Read the directory's trials.csv (a campaign run with per_trial): one row per trial.

Returns
-------
dict of numpy.ndarray
    The file's columns in its order, as run_campaign returns them: float64 for numbers and
    booleans (NaN where empty), int64 for trials, adc_bits and trial, uint64 for seed and
    trial_seed, str for text and any column the results schema does not name.

Raises
------
RuntimeError
    A file that is missing, too large, empty or malformed (one line naming it, and the column
    and row of a cell that is not its column's type); a directory without trials.csv.
ValueError
    trials=True with a file that is not a trials.csv.
TypeError
    A keyword of the wrong type.

Examples
--------
>>> r = fss.read_campaign('out/campaign')  # doctest: +SKIP
>>> ok = r['status'] == 'ok'  # doctest: +SKIP
>>> r['code'][ok], r['rmse_mean'][ok]  # doctest: +SKIP
)";

}  // namespace fss::python
