"""The gallery of python/examples/: each script runs in a fresh folder, exits 0 and writes its
figure (or says it skipped it when matplotlib is missing)."""

import importlib.util
import os
import pathlib
import subprocess
import sys

import pytest

import fss
from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "python" / "examples"
SCRIPTS = sorted(p.name for p in EXAMPLES.glob("*.py"))
SKIPPED = "matplotlib not available: figure skipped"


def _has_matplotlib():
    return importlib.util.find_spec("matplotlib") is not None


def example_environment(*first):
    """The test's environment, its PYTHONPATH made absolute (the examples run elsewhere) and
    led by `first` and the folder of the fss this test imports."""
    env = dict(os.environ)
    paths = [str(p) for p in first] + [str(pathlib.Path(fss.__file__).parents[1])]
    paths += [os.path.abspath(p) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    env["PYTHONPATH"] = os.pathsep.join(paths)
    return env


def run_example(name, cwd, env=None):
    """Runs one example as a user would, in `cwd`, writing into cwd/out (the timeout is a
    guard against a hang, not a measure of speed: bench/ measures speed)."""
    result = subprocess.run([sys.executable, str(EXAMPLES / name), "out"], cwd=cwd,
                            env=env or example_environment(), capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    return result


def test_the_gallery_is_there():
    assert set(SCRIPTS) >= {"rmse_vs_velocity.py", "design_code.py", "campaign_readback.py"}


@pytest.mark.parametrize("name", SCRIPTS)
def test_example_runs_and_writes_its_figure(name, tmp_path):
    result = run_example(name, tmp_path)
    figure = tmp_path / "out" / (pathlib.Path(name).stem + ".png")
    if _has_matplotlib():
        assert figure.is_file() and figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert SKIPPED not in result.stdout
    else:
        assert SKIPPED in result.stdout.splitlines() and not figure.exists()
    assert "Warning" not in result.stderr, result.stderr


def test_an_example_without_matplotlib_skips_the_figure(tmp_path):
    # A matplotlib that cannot be imported, first on the path.
    blocker = tmp_path / "blocker"
    blocker.mkdir()
    (blocker / "matplotlib.py").write_text("raise ImportError('blocked by the test')\n")
    result = run_example("design_code.py", tmp_path, example_environment(blocker))
    assert SKIPPED in result.stdout.splitlines()
    assert not (tmp_path / "out" / "design_code.png").exists()
    assert "raskar" in result.stdout  # the numbers are still computed
