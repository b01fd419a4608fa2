"""fssim, the flutter shutter camera simulator, on numpy arrays.

The functions are those of the compiled module ``fss._fss``, over the library of
the ``fssim`` executable and its fast path; docs/python.md documents them.
"""
from ._fss import *  # noqa: F401,F403
from ._fss import REPORT_SCHEMA_VERSION, __version__  # noqa: F401
