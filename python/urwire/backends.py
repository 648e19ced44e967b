"""Which decoder runs: the C extension urwire._ccore (the generated C parser and the C command's
JSON writer) where it is built, else pure Python, which needs nothing.

URWIRE_BACKEND=python keeps to pure Python even where the extension is built (the tests run both
ways); URWIRE_BACKEND=c insists on the extension and fails to import without it (extension.py).
`backend()` says which one runs.

What the extension does: the canonical JSON Lines of a primary/secondary stream
(`primary_json_lines`, what `urwire decode` prints for a raw stream); the records of robot
states (decode_message, and so decode_stream, Framer and every tool over them: decoding.py),
framed in C, each sub-package a copy of the record its bytes gave before (one handed out in a
state that was dropped since, when nothing holds any part of it) or made in C; the
records of real-time packets (realtime.py) and the values of RTDE data packages (typed_records.py),
made in C from what their struct unpacks; and the dataset's columns of the primary/secondary
interface, of raw streams and captures (data/dataset_c.py, data/dataset_c_capture.py).
"""
from __future__ import annotations

from typing import Iterable, Iterator

from .arguments import VersionLike, bytes_of, parse_version
from .canonical import has_error, to_json_line
from .extension import CCORE
from .framer import Framer

_CCORE = CCORE


def ccore():
    """The extension module urwire._ccore where it decodes, else None."""
    return _CCORE


def backend() -> str:
    """'c' when the C extension decodes, 'python' when pure Python does."""
    return "python" if _CCORE is None else "c"


class JsonLines:
    """The canonical JSON Lines (bytes, each line ending in a newline) of a primary/secondary
    stream fed in chunks of any size; `errors` says whether a record so far held an error.
    Under the C backend the C parser frames, decodes and writes; else the Framer and
    to_json_line do. Both give the same bytes."""

    def __init__(self, version_hint: VersionLike = None):
        hint = parse_version(version_hint)
        if _CCORE is not None:
            self._c = _CCORE.PrimaryJsonLines(None if hint is None else "%d.%d.%d" % hint)
        else:
            self._c = None
            self._framer = Framer(hint)
            self._errors = False

    @property
    def errors(self) -> bool:
        return self._c.errors if self._c is not None else self._errors

    def feed(self, data) -> bytes:
        if self._c is not None:
            return self._c.feed(bytes_of(data, "JsonLines.feed"))
        return self._lines(self._framer.feed(data))

    def close(self) -> bytes:
        if self._c is not None:
            return self._c.close()
        return self._lines(self._framer.close())

    def _lines(self, records: list) -> bytes:
        self._errors = self._errors or any(has_error(r) for r in records)
        return "".join(to_json_line(r) + "\n" for r in records).encode()


def primary_json_lines(chunks: Iterable, version_hint: VersionLike = None) -> Iterator[bytes]:
    """The JSON Lines of a primary/secondary stream given as chunks, a piece per chunk."""
    lines = JsonLines(version_hint)
    for chunk in chunks:
        yield lines.feed(chunk)
    yield lines.close()
