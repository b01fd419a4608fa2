"""fssim, the flutter shutter camera simulator, on numpy arrays.

The functions of the compiled module ``fss._fss``, over the library of the
``fssim`` executable and its fast path (docs/python.md documents them):

Simulation
    simulate, SimulationResult, simulate_to_folder
Image files
    read_png, read_tiff, read_image, write_png, write_tiff
Codes
    builtin_codes, read_code, generate_code, analyze_code, optimize_code,
    transfer_function
Campaigns
    run_campaign, read_campaign
Warnings
    FssimWarning: every warning fssim prints, warned with this category

Conventions: any integer or float scalar where a number is expected; images
of any numeric dtype with an explicit scale (``data_range=``; uint8 and
uint16 need none); results and metrics in gray levels on the 0..255 scale;
inf and nan as floats; errors naming the Python parameter.
"""
import inspect as _inspect

from . import _fss

__version__ = _fss.__version__
REPORT_SCHEMA_VERSION = _fss.REPORT_SCHEMA_VERSION

# The public API, in the order of docs/python.md: functions, then classes.
_FUNCTIONS = (
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
)
_CLASSES = ("SimulationResult", "FssimWarning")


def _wrapper_source(name, signature):
    """The source of `def name(<signature>): return __fss_compiled(<the same arguments>)`,
    each default the name of an entry of the returned namespace (the compiled function's own
    default object, so that help() prints it as the compiled signature does)."""
    parameters, arguments, defaults = [], [], {}
    star_written = False
    positional_only = False
    for index, p in enumerate(signature.parameters.values()):
        text = p.name
        if p.default is not p.empty:
            key = "__fss_default_%d" % index
            defaults[key] = p.default
            text += "=" + key
        if p.kind is p.POSITIONAL_ONLY:
            positional_only = True
        elif positional_only:
            parameters.append("/")
            positional_only = False
        if p.kind is p.VAR_POSITIONAL:
            text, star_written = "*" + p.name, True
            arguments.append("*" + p.name)
        elif p.kind is p.VAR_KEYWORD:
            text = "**" + p.name
            arguments.append("**" + p.name)
        elif p.kind is p.KEYWORD_ONLY:
            if not star_written:
                parameters.append("*")
                star_written = True
            arguments.append("%s=%s" % (p.name, p.name))
        else:
            arguments.append(p.name)
        parameters.append(text)
    if positional_only:
        parameters.append("/")
    source = "def %s(%s):\n    return __fss_compiled(%s)\n" % (
        name, ", ".join(parameters), ", ".join(arguments))
    return source, defaults


def _wrap(compiled):
    """A Python function calling `compiled` (a function of fss._fss) with the same signature,
    name and docstring, in module fss: help() then shows its signature and numpydoc text, and
    a wrong keyword is Python's own one-line TypeError. One frame between the caller and the
    compiled code, which warns with stacklevel 2. Without a text signature (a docstring not
    beginning with "name(...)\\n--\\n\\n") it takes *args, **kwargs."""
    name = compiled.__name__
    try:
        signature = _inspect.signature(compiled)
    except (TypeError, ValueError):
        signature = None
    if signature is None:
        def wrapper(*args, **kwargs):
            return compiled(*args, **kwargs)
    else:
        source, namespace = _wrapper_source(name, signature)
        namespace["__fss_compiled"] = compiled
        exec(compile(source, "<fss.%s>" % name, "exec"), namespace)
        wrapper = namespace[name]
        wrapper.__signature__ = signature
    wrapper.__name__ = name
    wrapper.__qualname__ = name
    wrapper.__module__ = __name__
    wrapper.__doc__ = compiled.__doc__
    return wrapper


def _export():
    for name in _FUNCTIONS:
        globals()[name] = _wrap(getattr(_fss, name))
    for name in _CLASSES:
        cls = globals()[name] = getattr(_fss, name)
        cls.__module__ = __name__
    return list(_FUNCTIONS + _CLASSES) + ["REPORT_SCHEMA_VERSION"]


__all__ = _export()
