"""The public API of fss: __all__, the shipped stub (fss/__init__.pyi) and the compiled module
name the same things; each function's signature is the stub's; help() shows the signature and
a numpydoc docstring; the Python wrappers keep the compiled functions' behaviour."""

import ast
import inspect
import pathlib
import pydoc
import re
import warnings

import numpy as np
import pytest

import fss
import fss._fss

STUB = pathlib.Path(fss.__file__).with_suffix(".pyi")


def _stub_tree():
    assert STUB.is_file(), "the stub is not shipped next to fss/__init__.py: %s" % STUB
    return ast.parse(STUB.read_text())


def _stub_definitions():
    """The stub's public top-level names: name -> list of ast nodes (several for an overload)."""
    definitions = {}
    for node in _stub_tree().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            name = node.name
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            name = node.target.id
        else:
            continue
        if not name.startswith("_"):
            definitions.setdefault(name, []).append(node)
    return definitions


def _stub_all():
    for node in _stub_tree().body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return ast.literal_eval(node.value)
    raise AssertionError("the stub has no __all__")


STUB_NAMES = _stub_definitions()
FUNCTIONS = sorted(n for n, nodes in STUB_NAMES.items() if isinstance(nodes[0], ast.FunctionDef))
COMPILED_PUBLIC = {n for n in dir(fss._fss) if not n.startswith("_")}


def test_all_is_the_stubs_names_and_the_compiled_modules():
    assert len(fss.__all__) == len(set(fss.__all__))
    assert set(fss.__all__) == set(STUB_NAMES)
    assert fss.__all__ == _stub_all()
    assert set(fss.__all__) == COMPILED_PUBLIC
    namespace = {}
    exec("from fss import *", namespace)
    assert set(namespace) - {"__builtins__"} == set(fss.__all__)


def test_versions():
    assert fss.__version__ == fss._fss.__version__ and fss.__version__
    assert isinstance(fss.REPORT_SCHEMA_VERSION, int) and fss.REPORT_SCHEMA_VERSION >= 1


def _stub_parameters(function):
    """(name, kind, default) of a stub function's parameters; the default as a Python value."""
    a = function.args
    result = []
    positional = a.posonlyargs + a.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(a.defaults)) + [
        ast.literal_eval(d) for d in a.defaults]
    for i, arg in enumerate(positional):
        kind = (inspect.Parameter.POSITIONAL_ONLY if i < len(a.posonlyargs)
                else inspect.Parameter.POSITIONAL_OR_KEYWORD)
        result.append((arg.arg, kind, defaults[i]))
    if a.vararg:
        result.append((a.vararg.arg, inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.empty))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        value = inspect.Parameter.empty if default is None else ast.literal_eval(default)
        result.append((arg.arg, inspect.Parameter.KEYWORD_ONLY, value))
    if a.kwarg:
        result.append((a.kwarg.arg, inspect.Parameter.VAR_KEYWORD, inspect.Parameter.empty))
    return result


def _parameters(signature):
    return [(p.name, p.kind, p.default) for p in signature.parameters.values()]


@pytest.mark.parametrize("name", FUNCTIONS)
def test_signature_is_the_stubs(name):
    function = getattr(fss, name)
    signature = inspect.signature(function)
    # The wrapper's signature is the compiled function's own text signature.
    assert _parameters(signature) == _parameters(inspect.signature(getattr(fss._fss, name)))
    for node in STUB_NAMES[name]:  # every overload
        expected = _stub_parameters(node)
        got = _parameters(signature)
        assert got == expected, "%s: module %s, stub %s" % (name, signature, expected)
        for (_, _, default), (_, _, stub_default) in zip(got, expected):
            assert type(default) is type(stub_default)


@pytest.mark.parametrize("name", FUNCTIONS)
def test_wrapper_is_a_function_of_fss(name):
    function = getattr(fss, name)
    compiled = getattr(fss._fss, name)
    assert inspect.isfunction(function)
    assert function.__module__ == "fss"
    assert function.__name__ == function.__qualname__ == name
    assert function.__doc__ == compiled.__doc__
    assert not hasattr(function, "__wrapped__")


def _sections(doc):
    """The numpydoc sections of a docstring: title -> body, in order."""
    lines = inspect.cleandoc(doc).splitlines()
    sections, title = {}, "summary"
    sections[title] = []
    for i, line in enumerate(lines):
        if i + 1 < len(lines) and line.strip() and re.fullmatch(r"-{3,}", lines[i + 1].strip()) \
                and len(lines[i + 1].strip()) == len(line.strip()):
            title = line.strip()
            sections[title] = []
        elif not re.fullmatch(r"-{3,}", line.strip()):
            sections[title].append(line)
    return sections


def _documented_parameters(body):
    """Names of a numpydoc Parameters section's entries ("a, b : type" lines at column 0)."""
    names = set()
    for line in body:
        if line and not line[0].isspace():
            names.update(n.strip().lstrip("*") for n in line.split(" : ")[0].split(","))
    return names


@pytest.mark.parametrize("name", FUNCTIONS)
def test_docstring_is_numpydoc(name):
    function = getattr(fss, name)
    doc = function.__doc__
    assert doc and not doc.startswith(name + "("), "%s: the text signature was not parsed" % name
    sections = _sections(doc)
    titles = [t for t in sections if t != "summary"]
    assert sections["summary"] and sections["summary"][0].strip(), name
    parameters = inspect.signature(function).parameters
    # A function without parameters (builtin_codes) has nothing to document or refuse.
    required = (["Parameters", "Raises"] if parameters else []) + ["Returns", "Examples"]
    for title in required:
        assert title in titles, "%s: no %s section" % (name, title)
    order = ["Parameters", "Returns", "Raises", "Warns", "See Also", "Notes", "Examples"]
    present = [t for t in order if t in titles]
    assert present == sorted(present, key=order.index) and [
        t for t in titles if t in order] == present, "%s: sections %s" % (name, titles)
    if parameters:
        assert _documented_parameters(sections["Parameters"]) == set(parameters), name
    assert ">>> " in "\n".join(sections["Examples"]), name


@pytest.mark.parametrize("name", FUNCTIONS)
def test_help_shows_the_signature(name):
    text = pydoc.render_doc(getattr(fss, name), renderer=pydoc.plaintext)
    signature = str(inspect.signature(getattr(fss, name)))
    assert name + signature in text
    assert "Parameters" in text or not inspect.signature(getattr(fss, name)).parameters
    assert "PyCapsule" not in text and "builtins" not in text


def test_help_of_the_module_and_the_result():
    text = pydoc.render_doc(fss, renderer=pydoc.plaintext)
    assert "PyCapsule" not in text
    assert "simulate(image, *, data_range=None" in text
    result_text = pydoc.render_doc(fss.SimulationResult, renderer=pydoc.plaintext)
    assert "PyCapsule" not in result_text


def test_classes_are_of_fss():
    assert fss.SimulationResult.__module__ == "fss"
    assert fss.FssimWarning.__module__ == "fss"
    assert issubclass(fss.FssimWarning, UserWarning)
    assert fss.SimulationResult is fss._fss.SimulationResult
    assert fss.FssimWarning is fss._fss.FssimWarning


def test_result_attributes_are_the_stubs():
    (node,) = STUB_NAMES["SimulationResult"]
    stub = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | {
        n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
    public = {n for n in dir(fss.SimulationResult) if not n.startswith("_")}
    assert public == stub


def test_wrong_keyword_is_one_short_line():
    image = np.zeros((8, 8), np.uint8)
    with pytest.raises(TypeError) as error:
        fss.simulate(image, sed=3)
    message = str(error.value)
    assert "sed" in message and "\n" not in message and len(message) < 200
    with pytest.raises(TypeError):
        fss.simulate(image, "raskar")  # keywords only after the image


def test_wrapper_passes_every_argument(camera):
    image = fss.read_png(camera)[:16]
    options = dict(code="mip", velocity=0.5, snr=50, seed=4, trials=2, rmse_margin="auto")
    wrapped = fss.simulate(image, **options)
    direct = fss._fss.simulate(image, **options)
    assert wrapped.report == direct.report
    np.testing.assert_array_equal(wrapped.restored, direct.restored)
    assert fss.transfer_function("raskar", 0.3, dt=0.5) == fss._fss.transfer_function(
        "raskar", 0.3, dt=0.5)


def test_warnings_point_at_the_caller(camera):
    # The accumulation's kernel is not invertible (a warning of fssim).
    image = fss.read_png(camera)[:8, :400]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fss.simulate(image, code="accumulation", rmse_margin="auto")
    ours = [w for w in caught if issubclass(w.category, fss.FssimWarning)]
    assert ours and len(ours) == len(result.warnings)
    assert all(w.filename == __file__ for w in ours), [w.filename for w in ours]
    with warnings.catch_warnings():
        warnings.simplefilter("error", fss.FssimWarning)
        with pytest.raises(fss.FssimWarning):
            fss.simulate(image, code="accumulation", rmse_margin="auto")


def test_wrapper_of_other_signatures():
    # Positional-only parameters and defaults: divmod(x, y, /), print(*args, sep=' ', ...).
    wrapped = fss._wrap(divmod)
    assert str(inspect.signature(wrapped)) == "(x, y, /)" and wrapped(7, 2) == (3, 1)
    with pytest.raises(TypeError):
        wrapped(x=7, y=2)
    wrapped = fss._wrap(print)
    assert str(inspect.signature(wrapped)) == str(inspect.signature(print))
    # Without a text signature (min has none): *args, **kwargs, passed through.
    wrapped = fss._wrap(min)
    assert str(inspect.signature(wrapped)) == "(*args, **kwargs)"
    assert wrapped(3, 1, 2) == 1 and wrapped([4, 5], key=lambda v: -v) == 5
    assert wrapped.__name__ == "min" and wrapped.__module__ == "fss"
