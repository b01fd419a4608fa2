"""fss.run_campaign and fss.read_campaign against `fssim campaign`: the same spec writes the same
bytes; the columns as numpy arrays equal what read_campaign reads back; a run resumes; settings
that cannot run raise after writing, or warn with skip_unrunnable."""

import json
import subprocess
import warnings

import numpy as np
import pytest

import fss
from conftest import run_fssim

FILES = ("results.csv", "results.jsonl", "trials.csv", "trials.jsonl", "campaign.json")


@pytest.fixture(scope="module")
def crop(tmp_path_factory, camera_array):
    """A 48 x 280 crop of camera.png, written with fss.write_png."""
    path = tmp_path_factory.mktemp("images") / "crop.png"
    fss.write_png(path, camera_array[200:248, 100:380])
    return path


@pytest.fixture(scope="module")
def fssim_version(fssim):
    return subprocess.run([fssim, "--version"], capture_output=True, text=True,
                          check=True).stdout.split(" ", 1)[1].strip()


def spec_of(crop, **fields):
    """2 codes x 2 velocities x 3 trials, numpy values where a user may have them."""
    spec = {"input": [crop], "code": ["raskar", "mip"], "velocity": np.array([0.25, 0.5]),
            "trials": np.int64(3), "seed": 1, "rmse_margin": 40}
    spec.update(fields)
    return spec


def spec_file(spec, path):
    """The spec as a campaign file for fssim."""
    plain = {k: (v.tolist() if isinstance(v, (np.ndarray, np.generic)) else v)
             for k, v in spec.items()}
    plain["input"] = [str(p) for p in plain["input"]]
    path.write_text(json.dumps(plain))
    return path


def assert_same_files(python_dir, cli_dir, fssim_version):
    for name in FILES:
        if (cli_dir / name).exists() or (python_dir / name).exists():
            # the module and fssim of one build have one version; an fssim built at another
            # commit differs only there
            text = (python_dir / name).read_text().replace(fss.__version__, fssim_version)
            assert text == (cli_dir / name).read_text(), name


def assert_same_columns(a, b):
    assert list(a) == list(b)
    for name in a:
        assert a[name].dtype == b[name].dtype, name
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_same_bytes_as_fssim(fssim, fssim_version, crop, tmp_path):
    spec = spec_of(crop, per_trial=True)
    columns = fss.run_campaign(spec, tmp_path / "py", threads=1)
    run_fssim(fssim, "campaign", "-f", spec_file(spec, tmp_path / "spec.json"), "-o",
              tmp_path / "cli", "--no-progress")
    assert_same_files(tmp_path / "py", tmp_path / "cli", fssim_version)
    # the columns as numpy arrays, as read_campaign reads them back
    assert_same_columns(columns, fss.read_campaign(tmp_path / "py"))
    assert_same_columns(columns, fss.read_campaign(tmp_path / "cli" / "results.csv"))
    assert len(columns["code"]) == 4 and columns["code"].dtype.kind == "U"
    assert columns["code"].tolist() == ["raskar", "raskar", "mip", "mip"]
    assert columns["velocity"].tolist() == [0.25, 0.5, 0.25, 0.5]
    assert columns["trials"].dtype == np.int64 and columns["trials"].tolist() == [3] * 4
    assert columns["seed"].dtype == np.uint64
    assert columns["rmse_mean"].dtype == np.float64 and np.all(columns["rmse_mean"] > 0)
    assert np.all(np.isnan(columns["full_well"])) and columns["invertible"].tolist() == [1.0] * 4
    trials = fss.read_campaign(tmp_path / "py", trials=True)
    assert trials["trial"].tolist() == [0, 1, 2] * 4
    assert np.all(trials["trial_seed"] == np.repeat(columns["seed"], 3) + trials["trial"])
    for i in range(4):  # each setting's mean over its trials
        assert trials["rmse"][3 * i:3 * i + 3].mean() == pytest.approx(columns["rmse_mean"][i])
    # a campaign file gives the same campaign: the directory resumes it
    assert_same_columns(fss.run_campaign(tmp_path / "spec.json", tmp_path / "py"), columns)


def test_resume(crop, tmp_path):
    out = tmp_path / "out"
    columns = fss.run_campaign(spec_of(crop), out)
    results = (out / "results.csv").read_bytes()
    # an interrupted run: the last setting missing from the journal, no result files yet
    journal = (out / "journal.jsonl").read_text().splitlines(keepends=True)
    (out / "journal.jsonl").write_text("".join(journal[:-1]))
    for name in ("results.csv", "results.jsonl", "campaign.json"):
        (out / name).unlink()
    assert_same_columns(fss.run_campaign(spec_of(crop), out), columns)
    assert (out / "results.csv").read_bytes() == results
    assert (out / "journal.jsonl").read_text() == "".join(journal)
    with pytest.raises(ValueError, match="holds another campaign"):
        fss.run_campaign(spec_of(crop, seed=2), out)


def test_settings_that_cannot_run(fssim, crop, tmp_path):
    spec = spec_of(crop, velocity=[0.5, 6], code=["raskar"])  # B = 312 > the crop's width
    with warnings.catch_warnings():
        warnings.simplefilter("error", fss.FssimWarning)  # the error comes first, never a warning
        with pytest.raises(RuntimeError, match=r"^1 setting cannot run .*read_campaign.*"
                                               r"skip_unrunnable=True$"):
            fss.run_campaign(spec, tmp_path / "py")
    columns = fss.read_campaign(tmp_path / "py")  # written before the error
    assert columns["status"].tolist() == ["ok", "too-narrow"]
    assert np.isnan(columns["rmse_mean"][1]) and columns["rmse_mean"][0] > 0
    assert np.isnan(columns["invertible"][1])
    # the warning lists what fssim lists on stderr
    cli = subprocess.run([fssim, "campaign", "-f", spec_file(spec, tmp_path / "spec.json"), "-o",
                          tmp_path / "cli", "--no-progress"], capture_output=True, text=True)
    assert cli.returncode == 1
    listed = [line.split("fssim: campaign: ", 1)[1].strip()
              for line in cli.stderr.splitlines() if line.startswith("fssim: campaign: ")]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        skipped = fss.run_campaign(spec, tmp_path / "py", skip_unrunnable=True)
    assert len(caught) == 1 and len(listed) >= 3 and caught[0].category is fss.FssimWarning
    message = str(caught[0].message)
    assert "\n" not in message and all(line in message for line in listed)
    assert_same_columns(skipped, columns)


@pytest.mark.parametrize("fields,error,message", [
    ({"trials": 0}, ValueError, r"^trials = 0: must be >= 1"),
    ({"velocity": "1:x"}, ValueError, r"^velocity"),
    ({"colour": 1}, ValueError, r"^spec: .*colour"),
    ({"snr": [float("nan")]}, ValueError, r"^spec: "),
    ({"trials": object()}, TypeError, r"^spec: a value of type object"),
    ({"input": ["/nonexistent/x.png"]}, ValueError, r"nonexistent"),
])
def test_spec_errors_name_the_field(crop, tmp_path, fields, error, message):
    with pytest.raises(error, match=message) as caught:
        fss.run_campaign(spec_of(crop, **fields), tmp_path / "out")
    assert "--" not in str(caught.value) and "\n" not in str(caught.value)
    assert not (tmp_path / "out").exists()


def test_argument_errors(crop, tmp_path):
    with pytest.raises(TypeError, match="spec"):
        fss.run_campaign(3, tmp_path / "out")
    with pytest.raises(ValueError, match=r"^threads = -1"):
        fss.run_campaign(spec_of(crop), tmp_path / "out", threads=-1)
    fss.run_campaign(spec_of(crop, code=["raskar"], velocity=0.5), tmp_path / "out")
    with pytest.raises(RuntimeError, match="no trials.csv: run it with per_trial=True"):
        fss.read_campaign(tmp_path / "out", trials=True)
    with pytest.raises(ValueError, match="is not a trials.csv"):
        fss.read_campaign(tmp_path / "out" / "results.csv", trials=True)
    with pytest.raises(RuntimeError, match="missing"):
        fss.read_campaign(tmp_path / "missing")
    bad = tmp_path / "bad.csv"
    bad.write_text("code,trials\nraskar,three\n")
    with pytest.raises(RuntimeError, match=r"bad\.csv: column trials, row 1: 'three' is not an"):
        fss.read_campaign(bad)
    bad.write_text("a,b,c\n")
    with pytest.raises(RuntimeError, match=r"bad\.csv: column 'a' is not one of results.csv"):
        fss.read_campaign(bad)
    bad.write_text("code,code\nraskar,mip\n")
    with pytest.raises(RuntimeError, match=r"bad\.csv: column 'code' appears twice"):
        fss.read_campaign(bad)
    with pytest.raises(RuntimeError, match=r"is not one of results.csv"):
        fss.read_campaign(tmp_path / "out" / "results.jsonl")
