"""What `urwire export` says when a file cannot be read or written, whatever it writes (tables,
an MCAP file or a dataset): one line on stderr, and exit status 2."""
from __future__ import annotations

import sys
from typing import Union

from ..reading import input_kind

FAILED = 2   # export's exit status when a file cannot be read or written


def export_failed(path: str, exc: Union[OSError, ValueError]) -> int:
    """Say why `path` was not exported: a file that cannot be opened, read or written (OSError,
    naming the file), or bytes that are not a capture or stream (ValueError). Returns FAILED."""
    if isinstance(exc, OSError):
        print(f"urwire export: {exc.filename or path}: {exc.strerror or exc}", file=sys.stderr)
    else:
        print(f"urwire export: cannot read {input_kind(path)} {path}: {exc}", file=sys.stderr)
    return FAILED
