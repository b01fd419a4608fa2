# Types of the package fss (python/fss/__init__.py over the compiled fss._fss).
# Every public name of fss is here, with the signature of the compiled function
# (python/tests/test_api.py checks both against the module); docs/python.md
# documents them.
import os
from typing import Any, Literal, Sequence, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str
REPORT_SCHEMA_VERSION: int

__all__ = [
    "simulate",
    "simulate_to_folder",
    "read_png",
    "read_tiff",
    "read_image",
    "write_png",
    "write_tiff",
    "builtin_codes",
    "read_code",
    "generate_code",
    "analyze_code",
    "optimize_code",
    "transfer_function",
    "run_campaign",
    "read_campaign",
    "SimulationResult",
    "FssimWarning",
    "REPORT_SCHEMA_VERSION",
]

# A number: any Python or numpy integer or float scalar (or a 0-d array).
_Real = float | int | np.integer[Any] | np.floating[Any]
# An integer: integral floats (3.0) are taken too.
_Int = int | np.integer[Any]
_Path = str | bytes | os.PathLike[str] | os.PathLike[bytes]
# A built-in code name, a code file, or the gains.
_Code = str | os.PathLike[str] | Sequence[float] | NDArray[Any]
_Mode = Literal["numerical", "analog"]
_Noise = Literal["poisson", "aggregated", "none"]
_Restoration = Literal["inverse", "tikhonov", "wiener"]
# Tikhonov's lambda, or the word "optimal".
_Regularization = _Real | Literal["optimal"]
# "power-law", "power-law:GAMMA" or "oracle" (a simulation); "power-law[:GAMMA[:C]]" (design).
_Prior = str
# "uniform:LO:HI", "normal:MEAN:SD", "normal:MEAN:SD:LO:HI", or a file of "velocity weight" lines.
_Distribution = str | os.PathLike[str]
_Family = Literal["sinc", "mip", "random", "snapshot", "accumulation"]
_Image = NDArray[np.uint8] | NDArray[np.uint16]
# A campaign's columns: float64 for numbers, int64 for counts, str for text.
_Columns = dict[str, NDArray[Any]]

class FssimWarning(UserWarning):
    """Every warning fssim prints, warned with this category."""

class SimulationResult:
    """What fss.simulate returns."""

    @property
    def observed(self) -> NDArray[np.float64]: ...
    @property
    def restored(self) -> NDArray[np.float64]: ...
    @property
    def groundtruth(self) -> NDArray[np.float64]: ...
    @property
    def report(self) -> dict[str, Any]: ...
    @property
    def metrics(self) -> dict[str, Any]: ...
    @property
    def prediction(self) -> dict[str, Any]: ...
    @property
    def geometry(self) -> dict[str, Any]: ...
    @property
    def trials(self) -> dict[str, Any]: ...
    @property
    def parameters(self) -> dict[str, Any]: ...
    @property
    def code(self) -> dict[str, Any]: ...
    @property
    def kernel(self) -> dict[str, Any]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def trial_velocities(self) -> NDArray[np.float64]: ...
    @property
    def trial_metrics(self) -> dict[str, NDArray[np.float64]]: ...

def simulate(
    image: ArrayLike,
    *,
    data_range: _Real | None = None,
    code: _Code = "raskar",
    mode: _Mode = "numerical",
    velocity: _Real | None = None,
    snr: _Real = 100.0,
    dt: _Real = 1.0,
    seed: _Int = 0,
    trials: _Int = 1,
    noise: _Noise = "poisson",
    restore_velocity: _Real | None = None,
    threads: _Int = 0,
    rmse_margin: _Int | Literal["auto"] | None = None,
    max_memory: _Int = 0,
    read_noise: _Real = 0.0,
    dark_current: _Real = 0.0,
    full_well: _Real | None = None,
    adc_bits: _Int = 0,
    adc_gain: _Real | None = None,
    restoration: _Restoration = "inverse",
    regularization: _Regularization | None = None,
    prior: _Prior | None = None,
    velocity_distribution: _Distribution | None = None,
) -> SimulationResult: ...
def simulate_to_folder(
    input: _Path,
    outdir: _Path,
    *,
    code: _Code = "raskar",
    mode: _Mode = "numerical",
    velocity: _Real | None = None,
    snr: _Real = 100.0,
    dt: _Real = 1.0,
    seed: _Int = 0,
    trials: _Int = 1,
    noise: _Noise = "poisson",
    restore_velocity: _Real | None = None,
    threads: _Int = 0,
    rmse_margin: _Int | Literal["auto"] | None = None,
    max_memory: _Int = 0,
    read_noise: _Real = 0.0,
    dark_current: _Real = 0.0,
    full_well: _Real | None = None,
    adc_bits: _Int = 0,
    adc_gain: _Real | None = None,
    restoration: _Restoration = "inverse",
    regularization: _Regularization | None = None,
    prior: _Prior | None = None,
    velocity_distribution: _Distribution | None = None,
    plots: bool = True,
    sheet: bool = False,
    report: bool = False,
    save_float: bool = False,
    png_depth: Literal["8", "16", "auto", 8, 16] = "8",
) -> dict[str, Any]: ...
def read_png(path: _Path, *, max_memory: _Int = 0) -> _Image: ...
def read_tiff(
    path: _Path, *, max_memory: _Int = 0
) -> NDArray[np.uint8] | NDArray[np.uint16] | NDArray[np.float32]: ...
def read_image(
    path: _Path, *, max_memory: _Int = 0
) -> NDArray[np.uint8] | NDArray[np.uint16] | NDArray[np.float32]: ...
def write_png(
    path: _Path, image: ArrayLike, *, data_range: _Real | None = None, bit_depth: Literal[8, 16] = 8
) -> None: ...
def write_tiff(path: _Path, image: ArrayLike, *, data_range: _Real | None = None) -> None: ...
def builtin_codes() -> list[str]: ...
def read_code(code: _Code) -> NDArray[np.float64]: ...
def generate_code(
    family: _Family,
    *,
    length: _Int,
    velocity: _Real | None = None,
    dt: _Real | None = None,
    seed: _Int | None = None,
    analog: bool | None = None,
) -> NDArray[np.float64]: ...
def analyze_code(
    code: _Code,
    *,
    velocity: _Real | None = None,
    dt: _Real = 1.0,
    snr: _Real = 100.0,
    mode: _Mode = "numerical",
    grid: _Int = 0,
    velocity_distribution: _Distribution | None = None,
    read_noise: _Real = 0.0,
    dark_current: _Real = 0.0,
    adc_bits: _Int = 0,
    adc_gain: _Real | None = None,
    # Refused: the figure of merit is linear in the charge.
    full_well: None = None,
    restoration: _Restoration = "inverse",
    regularization: _Regularization | None = None,
    prior: _Prior | None = None,
) -> dict[str, Any]: ...
def optimize_code(
    *,
    length: _Int,
    velocity: _Real | None = None,
    velocity_distribution: _Distribution | None = None,
    dt: _Real = 1.0,
    snr: _Real = 100.0,
    mode: _Mode = "numerical",
    binary: bool = False,
    min_light: _Real = 0.0,
    restarts: _Int = 24,
    iterations: _Int = 300,
    seed: _Int = 0,
    grid_points: _Int = 2048,
    read_noise: _Real = 0.0,
    dark_current: _Real = 0.0,
    adc_bits: _Int = 0,
    adc_gain: _Real | None = None,
    # Refused: the figure of merit is linear in the charge.
    full_well: None = None,
    restoration: _Restoration = "inverse",
    regularization: _Regularization | None = None,
    prior: _Prior | None = None,
) -> dict[str, Any]: ...
@overload
def transfer_function(
    code: _Code, xi: _Real, *, velocity: _Real = 1.0, dt: _Real = 1.0
) -> complex: ...
@overload
def transfer_function(
    code: _Code, xi: NDArray[Any] | Sequence[float], *, velocity: _Real = 1.0, dt: _Real = 1.0
) -> NDArray[np.complex128]: ...
def run_campaign(
    spec: dict[str, Any] | _Path,
    outdir: _Path,
    *,
    threads: _Int = 0,
    skip_unrunnable: bool = False,
    per_trial: bool | None = None,
    max_memory: _Int = 0,
) -> _Columns: ...
def read_campaign(path: _Path, *, trials: bool = False) -> _Columns: ...
