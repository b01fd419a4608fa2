"""fss.simulate_to_folder is `fssim --input ... --outdir ...` from Python: the
same files, byte for byte, through the same library entry point."""

import pathlib
import shutil

import pytest

import fss
from conftest import read_report, run_fssim

CASES = [
    ("default", [], {}),
    ("analog_velocity", ["--mode", "analog", "--velocity", "0.5", "--seed", "3"],
     {"mode": "analog", "velocity": 0.5, "seed": 3}),
    ("sheet_report_16bit", ["--sheet", "--report", "--png-depth", "16", "--trials", "3"],
     {"sheet": True, "report": True, "png_depth": "16", "trials": 3}),
    ("floats_no_plots", ["--save-float", "--no-plots", "--noise", "aggregated"],
     {"save_float": True, "plots": False, "noise": "aggregated"}),
]


@pytest.mark.parametrize("name,cli_options,keywords", CASES, ids=[c[0] for c in CASES])
def test_same_files_as_fssim(fssim, tmp_path, camera, name, cli_options, keywords):
    cli_dir, py_dir = tmp_path / "cli", tmp_path / "py"
    run_fssim(fssim, "--input", camera, "--outdir", cli_dir, *cli_options)
    report = fss.simulate_to_folder(str(camera), py_dir, **keywords)
    cli_files = sorted(p.name for p in cli_dir.iterdir())
    assert sorted(p.name for p in py_dir.iterdir()) == cli_files
    for file in cli_files:
        assert (cli_dir / file).read_bytes() == (py_dir / file).read_bytes(), file
    assert report == read_report(py_dir)


def test_code_file_is_never_overwritten(tmp_path, camera):
    code = tmp_path / "code.txt"
    code.write_text("1 0 1 1\n")
    with pytest.raises(RuntimeError, match="code.txt"):
        fss.simulate_to_folder(camera, tmp_path, code=code)
    assert code.read_text() == "1 0 1 1\n"


def test_failures_leave_the_folder_as_it_was(tmp_path, camera):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    with pytest.raises(ValueError, match="png_depth = '12'"):
        fss.simulate_to_folder(camera, out, png_depth="12")
    with pytest.raises(RuntimeError, match="missing.png"):
        fss.simulate_to_folder(tmp_path / "missing.png", out)
    with pytest.raises(ValueError, match="velocity"):
        fss.simulate_to_folder(camera, out, velocity=float("nan"))
    assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]


def test_max_memory_refuses_from_the_header(tmp_path, camera):
    with pytest.raises(RuntimeError, match="memory limit"):
        fss.simulate_to_folder(camera, tmp_path / "out", max_memory=1 << 20)
    assert not (tmp_path / "out").exists()


def test_paths_may_be_pathlike_and_outputs_go_where_asked(tmp_path, camera):
    copy = tmp_path / "in.png"
    shutil.copy(camera, copy)
    report = fss.simulate_to_folder(pathlib.Path(copy), tmp_path / "run", threads=1)
    assert report["input"]["path"] == str(copy)
    assert (tmp_path / "run" / "restored.png").is_file()
