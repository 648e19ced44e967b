"""The optional C extension urwire._ccore, as URWIRE_BACKEND picks it: the module, or None for
pure Python. Its own module so that the decoder (decoding.py) and the stream writers
(backends.py) both ask it without importing each other.

URWIRE_BACKEND=python keeps to pure Python even where the extension is built (the tests run both
ways); URWIRE_BACKEND=c insists on the extension and fails to import without it.
"""
from __future__ import annotations

import os

_CHOICES = ("c", "python")
_CHOICE = os.environ.get("URWIRE_BACKEND", "").strip().lower()
if _CHOICE and _CHOICE not in _CHOICES:
    raise ImportError(f"URWIRE_BACKEND={_CHOICE!r}: expected one of {', '.join(_CHOICES)}")

CCORE = None
if _CHOICE != "python":
    try:
        from . import _ccore as CCORE
    except ImportError:
        if _CHOICE == "c":
            raise ImportError("URWIRE_BACKEND=c, but the C extension urwire._ccore is not built "
                              "(make python-ext, or pip install . with a C compiler)") from None
