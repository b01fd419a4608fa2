"""Hostile values at every argument of every function: each call either
returns results without a NaN (finite images; inf only as a float of a dict, where the
model's number is infinite) or raises a ValueError, TypeError or MemoryError (a
RuntimeError only where the argument is a file or the memory limit) with a
short one-line message; never a crash, an "Internal error", nor an
array's repr in the message. The module's C++ conversion of the values is
fuzzed too (tests/fuzz/fuzz_python_arguments.cpp); this covers the glue
between Python objects and it."""

import decimal
import fractions
import math
import pathlib

import numpy as np
import pytest

import fss

NAN, INF = float("nan"), float("inf")
IMAGE = np.full((3, 64), 100, dtype=np.uint8)
GAINS = [1.0, 0.0, 1.0, 1.0]

HOSTILE_SCALARS = [
    NAN, INF, -INF, 1e308, -1e308, 5e-324, 0, -0.0, -1, 2**31, -2**31 - 1, 2**63, 2**64,
    -2**64, 10**400, True, False, None, "", "1", "nan", "x\0y", b"1", 1j, decimal.Decimal("nan"),
    fractions.Fraction(1, 3), np.float32("nan"), np.float64(-np.inf), np.float16(2), np.int8(-1),
    np.uint64(2**64 - 1), np.bool_(True), np.complex128(1), np.datetime64("2020-01-01"),
    np.array(1.5), np.array(np.nan), np.array([]), np.array([1.0, 2.0]), np.zeros((2, 2)),
    [1.0], (), {}, object(), pathlib.Path("x"),
]

HOSTILE_ARRAYS = [
    np.zeros(()), np.zeros((0,)), np.zeros((0, 64)), np.zeros((3, 0)), np.zeros((3, 64, 2)),
    np.zeros((3, 64, 4)), np.zeros((1, 1, 1, 1)), np.full((3, 64), np.nan), np.full((3, 64), -np.inf),
    np.full((3, 64), 1e308), np.full((3, 64), -1e308), np.full((3, 64), 5e-324),
    np.full((3, 64), np.iinfo(np.uint64).max, dtype=np.uint64),
    np.full((3, 64), np.iinfo(np.int64).min, dtype=np.int64),
    np.zeros((3, 64), dtype=np.complex64), np.zeros((3, 64), dtype=object),
    np.zeros((3, 64), dtype="datetime64[s]"), np.zeros((3, 64), dtype="U2"),
    np.zeros((3, 64), dtype=[("a", "f8"), ("b", "i4")]),
    np.full((3, 64), 100, dtype=">f8"), np.full((3, 64), 100, dtype=np.float16),
    np.full((3, 64), 100, dtype=np.longdouble), np.ones((3, 64), dtype=bool),
    np.full((3, 128), 100, dtype=np.int16)[:, ::2], np.asfortranarray(np.full((3, 64, 3), 7.0)),
    np.full((64, 3), 100.0).T, np.broadcast_to(np.float32(9), (3, 64)),
    np.frombuffer(b"\0" + bytes(8 * 192), dtype=np.float64, offset=1).reshape(3, 64),
    np.full((3, 64), 100, dtype=np.uint8)[::-1, ::-1],
    [[1.0] * 64] * 3, [[1.0, 2.0], [3.0]], "image",
]

# function -> (call taking the keywords, the valid keywords it is given)
FUNCTIONS = {
    "simulate": (lambda **k: fss.simulate(**k), {
        "image": IMAGE, "data_range": 255, "code": GAINS, "mode": "numerical", "velocity": None,
        "snr": 100.0,
        "dt": 1.0, "seed": 0, "trials": 1, "noise": "poisson", "restore_velocity": None,
        "threads": 1, "rmse_margin": None, "max_memory": 0, "read_noise": 0.0,
        "dark_current": 0.0, "full_well": None, "adc_bits": 0, "adc_gain": None,
        "velocity_distribution": None}),
    "analyze_code": (lambda **k: fss.analyze_code(**k), {
        "code": GAINS, "velocity": None, "dt": 1.0, "snr": 100.0, "mode": "numerical", "grid": 0,
        "velocity_distribution": None}),
    "generate_code": (lambda **k: fss.generate_code(**k), {
        "family": "sinc", "length": 8, "velocity": 1.0, "dt": 1.0, "seed": 0, "analog": False}),
    "optimize_code": (lambda **k: fss.optimize_code(**k), {
        "length": 4, "velocity": 1.0, "dt": 1.0, "snr": 100.0, "mode": "numerical",
        "binary": False, "min_light": 0.0, "restarts": 0, "iterations": 3, "seed": 0,
        "grid_points": 16, "velocity_distribution": None}),
    "transfer_function": (lambda **k: fss.transfer_function(**k), {
        "code": GAINS, "xi": [0.0, 1.0], "velocity": 1.0, "dt": 1.0}),
    "read_code": (lambda **k: fss.read_code(**k), {"code": "raskar"}),
    "read_png": (lambda **k: fss.read_png(**k), {"path": "/nonexistent/fss.png"}),
}

# Arguments that name files, and the limit: a RuntimeError is their proper end.
RUNTIME_ARGUMENTS = {("simulate", "code"), ("analyze_code", "code"),
                     ("transfer_function", "code"), ("read_code", "code"), ("read_png", "path"),
                     ("simulate", "max_memory"), ("simulate", "velocity_distribution"),
                     ("analyze_code", "velocity_distribution"),
                     ("optimize_code", "velocity_distribution")}
# Slow with some valid values (a huge grid, many iterations): not given those.
SKIPPED = {("analyze_code", "grid"), ("optimize_code", "restarts"),
           ("optimize_code", "iterations"), ("optimize_code", "grid_points"),
           ("optimize_code", "length"), ("generate_code", "length"), ("simulate", "trials"),
           ("simulate", "threads")}


def all_finite(value):
    """True when every number in a result is finite."""
    if isinstance(value, dict):
        return all(all_finite(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(all_finite(v) for v in value)
    if isinstance(value, np.ndarray):
        return bool(np.all(np.isfinite(value)))
    if isinstance(value, (float, complex)):
        return math.isfinite(abs(value))
    return True


def no_nan(value):
    """True when no number in a result is NaN (an infinite one is a float: an
    infinite prediction, the PSNR of an exact restoration)."""
    if isinstance(value, dict):
        return all(no_nan(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(no_nan(v) for v in value)
    if isinstance(value, np.ndarray):
        return not bool(np.any(np.isnan(value)))
    if isinstance(value, (float, complex)):
        return not (math.isnan(value.real) or math.isnan(value.imag))
    return True


def check_outcome(name, argument, call, keywords):
    try:
        result = call(**keywords)
    except (ValueError, TypeError, MemoryError, RuntimeError) as error:
        message = str(error)
        if isinstance(error, RuntimeError) and not isinstance(error, MemoryError):
            assert (name, argument) in RUNTIME_ARGUMENTS, message
        assert message and "\n" not in message and len(message) < 300, message
        assert "Internal error" not in message and "array(" not in message, message
        assert "\0" not in message
        return
    if name == "simulate":
        assert all_finite([result.observed, result.restored, result.groundtruth])
        assert no_nan(result.report) and no_nan(result.trial_metrics)
    elif isinstance(result, dict):
        assert no_nan(result), result
    else:
        assert all_finite(result), result


def cases():
    for name, (_, valid) in FUNCTIONS.items():
        for argument in valid:
            values = HOSTILE_ARRAYS if argument in ("image", "xi", "code") else []
            if (name, argument) not in SKIPPED:
                values = values + HOSTILE_SCALARS
            for i, value in enumerate(values):
                yield pytest.param(name, argument, value, id=f"{name}-{argument}-{i}")


@pytest.mark.filterwarnings("ignore::fss.FssimWarning")
@pytest.mark.parametrize("name,argument,value", cases())
def test_hostile_value(name, argument, value):
    call, valid = FUNCTIONS[name]
    keywords = dict(valid)
    keywords[argument] = value
    check_outcome(name, argument, call, keywords)


@pytest.mark.parametrize("name,argument,value", [
    ("analyze_code", "grid", v) for v in (-1, 2**16 + 1, 2**31, 2**63, 1.5, NAN, "8", None)] + [
    ("optimize_code", a, v) for a in ("restarts", "iterations", "grid_points", "length")
    for v in (-1, 2**31, 2**63, 10**400, 1.5, NAN, "8", None, np.array([2, 3]))] + [
    ("generate_code", "length", v) for v in (0, -1, 2**31, 10**400, 2.5, None)] + [
    ("simulate", a, v) for a in ("trials", "threads")
    for v in (-1, 2**31, 2**63, 10**400, 1.5, NAN, "2", None)])
def test_hostile_counts(name, argument, value):
    call, valid = FUNCTIONS[name]
    keywords = dict(valid)
    keywords[argument] = value
    with pytest.raises((ValueError, TypeError)) as error:
        call(**keywords)
    message = str(error.value)
    assert message.startswith(argument) and "\n" not in message and len(message) < 300, message
