"""Canonical JSON of decoded records (docs/canonical-json.md): the form every target prints.

Hand-written; copied verbatim into generated/python/urwire/ by `make generate`.
"""
from __future__ import annotations

import ctypes
import json
import math
import struct
from typing import Any

from ._runtime import (GlobalValue, MalformedPackage, MalformedSubtype, StreamError, UnknownMessage,
                       UnknownPackage, UnknownSubtype)

_F32 = struct.Struct(">f")
_encode_text = json.JSONEncoder(ensure_ascii=False).encode


def _as_f32(x: float) -> float:
    """x rounded to float32, as C's (float) cast does; struct refuses values past FLT_MAX
    even when they round to it, so those go through ctypes."""
    try:
        return _F32.unpack(_F32.pack(x))[0]
    except OverflowError:
        return ctypes.c_float(x).value


def f32_text(x: float) -> str:
    """Shortest %.{p}g (p = 1..9) that reads back as the same float32."""
    if x != x or x in (math.inf, -math.inf):
        return _nonfinite(x)
    for p in range(1, 10):
        s = "%.*g" % (p, x)
        if _as_f32(float(s)) == x:
            return s
    return "%.9g" % x


def f64_text(x: float) -> str:
    if x != x or x in (math.inf, -math.inf):
        return _nonfinite(x)
    return repr(x)


def _nonfinite(x: float) -> str:
    return "NaN" if x != x else ("Infinity" if x > 0 else "-Infinity")


def _text(s: str) -> str:
    if not s.isascii():
        # Invalid bytes were kept as surrogates for lossless encoding; print them as U+FFFD.
        s = s.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
    return _encode_text(s)


def _scalar(kind: str, v: Any) -> str:
    if kind == "int":
        return str(int(v))
    if kind == "bool":
        return "true" if v else "false"
    if isinstance(v, int):  # a switch field that decoded an integer case
        return str(int(v))
    return f32_text(v) if kind == "f32" else f64_text(v)


def _value(v: GlobalValue) -> str:
    layout = v.value
    if layout is None:
        body = "null"
    elif isinstance(layout, bool) or (v.type == "BOOL"):
        body = "true" if layout else "false"
    elif isinstance(layout, str):
        body = _text(layout)
    elif isinstance(layout, int):
        body = str(layout)
    elif isinstance(layout, float):
        body = f32_text(layout)
    elif v.type == "MATRIX":
        body = "[" + ", ".join("[" + ", ".join(_value(x) for x in row) + "]" for row in layout) + "]"
    elif v.type == "POSE":
        body = "[" + ", ".join(f32_text(x) for x in layout) + "]"
    else:
        body = "[" + ", ".join(_value(x) for x in layout) + "]"
    return '{"type": ' + _text(v.type) + ', "value": ' + body + "}"


def _field(kind: str, v: Any) -> str:
    if kind == "text":
        return _text(v)
    if kind == "hex":
        return '"' + v.hex() + '"'
    if kind == "texts":
        return "[" + ", ".join(_text(s) for s in v) + "]"
    if kind == "values":
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if kind == "items":
        return "[" + ", ".join(_object(x) for x in v) + "]"
    if kind.startswith("list:"):
        item = kind[5:]
        return "[" + ", ".join(_scalar(item, x) for x in v) + "]"
    return _scalar(kind, v)


def _members(obj: Any) -> list[str]:
    parts = []
    for name, kind, optional in obj.JSON:
        v = getattr(obj, name)
        if optional and v is None:
            continue
        parts.append(f'"{name}": {_field(kind, v)}')
    return parts


def _object(obj: Any) -> str:
    return "{" + ", ".join(_members(obj)) + "}"


def _record(obj: Any) -> str:
    if isinstance(obj, StreamError):
        return '{"type": "error", "offset": %d, "error": %s}' % (obj.offset, _text(obj.error))
    if isinstance(obj, UnknownMessage):
        parts = ['"type": "unknown"', f'"message_type": {obj.message_type}']
        if obj.error is not None:
            parts.append(f'"error": {_text(obj.error)}')
        parts.append(f'"raw": "{obj.raw.hex()}"')
        return "{" + ", ".join(parts) + "}"
    if isinstance(obj, UnknownPackage):
        return '{"type": "unknown", "package_type": %d, "raw": "%s"}' % (obj.package_type, obj.raw.hex())
    if isinstance(obj, MalformedPackage):
        return '{"type": "%s", "error": %s, "raw": "%s"}' % (obj.name, _text(obj.error), obj.raw.hex())
    if isinstance(obj, (UnknownSubtype, MalformedSubtype)):
        unknown = isinstance(obj, UnknownSubtype)
        parts = ['"type": "unknown"', f'"message_type": {obj.message_type}',
                 f'"{obj.subtype_name}": {obj.subtype}'] if unknown else [f'"type": "{obj.name}"']
        parts += [f'"{name}": {int(value)}' for name, value in obj.header]
        if not unknown:
            parts.append(f'"error": {_text(obj.error)}')
        parts.append(f'"raw": "{obj.raw.hex()}"')
        return "{" + ", ".join(parts) + "}"
    if hasattr(obj, "packages"):
        parts = [f'"type": "{obj.TYPE}"', '"packages": [' + ", ".join(_record(p) for p in obj.packages) + "]"]
        if obj.error is not None:
            parts += [f'"error": {_text(obj.error)}', f'"raw": "{obj.raw.hex()}"']
        return "{" + ", ".join(parts) + "}"
    parts = [f'"type": "{obj.TYPE}"'] + _members(obj)
    if obj.extra:
        parts.append(f'"extra": "{obj.extra.hex()}"')
    return "{" + ", ".join(parts) + "}"


def to_json_line(record: Any) -> str:
    """One record as a canonical JSON line (without the newline)."""
    return _record(record)


def to_dict(record: Any) -> dict:
    """One record as plain Python values, exactly as its canonical JSON parses."""
    return json.loads(_record(record))


def has_error(record: Any) -> bool:
    """True when the record is a stream fault or holds a part that could not be decoded."""
    if isinstance(record, (StreamError, MalformedSubtype)):
        return True
    if isinstance(record, UnknownMessage):
        return record.error is not None
    if hasattr(record, "packages"):
        return record.error is not None or any(isinstance(p, MalformedPackage) for p in record.packages)
    return False
