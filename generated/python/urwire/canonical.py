# Copied from codegen/templates/python/runtime/canonical.py: edit it there and run `make generate`.
"""Canonical JSON of decoded records (docs/canonical-json.md): the form every target prints.

Most of a line's cost is its floats: each text is worked out once and then looked up while the
value recurs. Each class is written by a function made for it on first use.
Hand-written; copied verbatim into generated/python/urwire/ by `make generate`.
"""
from __future__ import annotations

import ctypes
import json
import math
import struct
from typing import Any, Callable, Optional

from ._runtime import (GlobalValue, MalformedPackage, MalformedSubtype, StreamError, UnknownMessage,
                       UnknownPackage, UnknownSubtype)

_F32 = struct.Struct(">f")
_f32_pack, _f32_unpack = _F32.pack, _F32.unpack
_frexp = math.frexp
_encode_text = json.JSONEncoder(ensure_ascii=False).encode

# The texts of the floats seen last, by value: a robot sends most of its values again in every
# state (limits, kinematics, a joint at rest), and a look-up costs a tenth of working one out.
# Zeros are left out (0.0 and -0.0 are one key but two texts), and so are NaN and the infinities.
_TEXTS_KEPT = 1 << 13
_F32_TEXTS: dict = {}
_F64_TEXTS: dict = {}


def f32_text(x: float) -> str:
    """Shortest %.{p}g (p = 1..9) that reads back as the same float32 (read as a double, then
    rounded to float32)."""
    if type(x) is float:
        text = _F32_TEXTS.get(x)
        if text is None:
            text = _f32_shortest(x)
            if x - x == 0.0 and x != 0.0:
                if len(_F32_TEXTS) >= _TEXTS_KEPT:
                    _F32_TEXTS.clear()
                _F32_TEXTS[x] = text
        return text
    if isinstance(x, int):
        return str(int(x))  # a switch field that decoded an integer case
    return _f32_shortest(x)  # a float subclass: a NaN that keeps its bits


def _f32_shortest(x: float) -> str:
    """f32_text, worked out.

    Apart from zero and powers of two, the decimals that read back as x lie symmetrically around
    it, and %.{p-1}g is never nearer to x than %.{p}g: once p digits fail, fewer fail too. Most
    float32 values need 7 to 9 digits, so 7 is tried first: if it fails, 8 then 9; if it reads
    back, shorter ones down to the first that fails, starting from the digits %.7g shows when it
    ends in zeros (a value typed in as a short decimal)."""
    if x - x != 0.0:
        return _nonfinite(x)
    if x == 0.0:
        return "-0" if math.copysign(1.0, x) < 0 else "0"
    if abs(_frexp(x)[0]) == 0.5:
        return _f32_upwards(x)
    try:
        text = "%.7g" % x
        if _f32_unpack(_f32_pack(float(text)))[0] != x:
            text = "%.8g" % x
            return text if _f32_unpack(_f32_pack(float(text)))[0] == x else "%.9g" % x
        p = 7 if len(text) > 7 else _significant_digits(text)
        if p < 7:
            text = "%.*g" % (p, x)  # the same number, laid out for p digits
        while p > 1:
            shorter = "%.*g" % (p - 1, x)
            if _f32_unpack(_f32_pack(float(shorter)))[0] != x:
                break
            text, p = shorter, p - 1
        return text
    except OverflowError:  # a text past FLT_MAX, which struct refuses (x is near it)
        return _f32_upwards(x)


def _f32_upwards(x: float) -> str:
    """The shortest %.{p}g that reads back as x, trying p = 1, 2, ... in turn."""
    for p in range(1, 9):
        text = "%.*g" % (p, x)
        if _as_f32(float(text)) == x:
            return text
    return "%.9g" % x


def _as_f32(x: float) -> float:
    """x rounded to float32, as C's (float) cast does; struct refuses values past FLT_MAX
    even when they round to it, so those go through ctypes."""
    try:
        return _f32_unpack(_f32_pack(x))[0]
    except OverflowError:
        return ctypes.c_float(x).value


def _significant_digits(text: str) -> int:
    """How many significant digits a %g text shows ("100" and "1e+02" show one)."""
    return len(text.partition("e")[0].replace(".", "").strip("-0"))


def f64_text(x: float) -> str:
    """Shortest text that reads back as the same double, laid out as repr()."""
    if type(x) is float:
        text = _F64_TEXTS.get(x)
        if text is None:
            if x - x != 0.0:
                return _nonfinite(x)
            text = repr(x)
            if x != 0.0:
                if len(_F64_TEXTS) >= _TEXTS_KEPT:
                    _F64_TEXTS.clear()
                _F64_TEXTS[x] = text
        return text
    if isinstance(x, int):
        return str(int(x))  # a switch field that decoded an integer case
    return f64_text(float(x))


def _nonfinite(x: float) -> str:
    return "NaN" if x != x else ("Infinity" if x > 0 else "-Infinity")


def _text(s: str) -> str:
    if not s.isascii():
        # Invalid bytes were kept as surrogates for lossless encoding; print them as U+FFFD.
        s = s.encode("utf-8", "surrogateescape").decode("utf-8", "replace")
    return _encode_text(s)


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


# ---- one writer per class ----------------------------------------------------------------
# A generated class lists its members as JSON = ((name, kind, optional), ...). Its writer is
# made once, on first use, as straight-line code (the way dataclasses makes __init__): a record
# then costs a call per object, not a dispatch per member.

# How a value {v} of each kind is written: a %-format and the expression it takes.
_KINDS = {
    "int": ("%d", "{v}"),
    "bool": ("%s", '("true" if {v} else "false")'),
    "f32": ("%s", "f32({v})"),
    "f64": ("%s", "f64({v})"),
    "text": ("%s", "text({v})"),
    "hex": ('"%s"', "{v}.hex()"),
    "texts": ("[%s]", '", ".join(map(text, {v}))'),
    "values": ("[%s]", '", ".join(map(value, {v}))'),
    "items": ("[%s]", '", ".join(map(write, {v}))'),
    "list:int": ("[%s]", '", ".join(map(int_text, {v}))'),
    "list:bool": ("[%s]", '", ".join(map(bool_text, {v}))'),
    "list:f32": ("[%s]", '", ".join(map(f32, {v}))'),
    "list:f64": ("[%s]", '", ".join(map(f64, {v}))'),
}
_EXTRA = """(', "extra": "%s"' % o.extra.hex() if o.extra else "")"""


def _bool_text(v: Any) -> str:
    return "true" if v else "false"


def _format(members: list, before: str = "", after: str = "", tail: str = "") -> str:
    """Source of one %-format of (name, kind, value source) members, between `before` and
    `after`, with `tail` (a %s expression) last."""
    text = before + ", ".join(f'"{name}": '.replace("%", "%%") + _KINDS[kind][0] for name, kind, _ in members)
    values = [_KINDS[kind][1].format(v=value) for _, kind, value in members] + ([tail] if tail else [])
    return f"{text + ('%s' if tail else '') + after!r} % ({''.join(v + ', ' for v in values)})"


def _writer_source(cls: type) -> str:
    """`def write_<class>(o)`: the members in order, an optional one only when it is set; a
    message or sub-package (a class with a TYPE) starts with its type and ends with its extra
    bytes, an item of a group has neither."""
    typed = getattr(cls, "TYPE", None)
    head = f'"type": "{typed}"' if typed else ""
    lines = [f"def write_{cls.__name__}(o):"]
    if not any(optional for _, _, optional in cls.JSON):
        members = [(name, kind, f"o.{name}") for name, kind, _ in cls.JSON]
        opening = "{" + head.replace("%", "%%") + (", " if head and members else "")
        lines.append(f"    return {_format(members, opening, '}', _EXTRA if typed else '')}")
        return "\n".join(lines) + "\n"
    lines.append(f"    parts = [{head!r}]" if typed else "    parts = []")
    run: list = []
    for name, kind, optional in [*cls.JSON, ("", "", True)]:
        if not optional:
            run.append((name, kind, f"o.{name}"))
            continue
        if run:
            lines.append(f"    parts.append({_format(run)})")
            run = []
        if name:
            lines += [f"    v = o.{name}", "    if v is not None:", f"        parts.append({_format([(name, kind, 'v')])})"]
    if typed:
        lines += ["    if o.extra:", """        parts.append('"extra": "%s"' % o.extra.hex())"""]
    lines.append('    return "{" + ", ".join(parts) + "}"')
    return "\n".join(lines) + "\n"


def _names() -> dict:
    """What the writers' code calls."""
    return dict(f32=f32_text, f64=f64_text, text=_text, value=_value, int_text="%d".__mod__,
                bool_text=_bool_text, write=_write)


def _compile(cls: type) -> Callable[[Any], str]:
    names = _names()
    exec(_writer_source(cls), names)
    return names[f"write_{cls.__name__}"]


def member_text(kind: str, value: Any) -> str:
    """The canonical JSON of one member's value, given its kind in a class's JSON table."""
    write = _MEMBER_WRITERS.get(kind)
    if write is None:
        fmt, expr = _KINDS[kind]
        write = _MEMBER_WRITERS[kind] = eval(f"lambda v: {fmt!r} % ({expr.format(v='v')},)", _names())
    return write(value)


_MEMBER_WRITERS: dict = {}


# ---- records that the runtime makes: stream faults, unknown and malformed parts -------------

def _stream_error(obj: StreamError) -> str:
    return '{"type": "error", "offset": %d, "error": %s}' % (obj.offset, _text(obj.error))


def _unknown_message(obj: UnknownMessage) -> str:
    parts = ['"type": "unknown"', f'"message_type": {obj.message_type}']
    if obj.error is not None:
        parts.append(f'"error": {_text(obj.error)}')
    parts.append(f'"raw": "{obj.raw.hex()}"')
    return "{" + ", ".join(parts) + "}"


def _unknown_package(obj: UnknownPackage) -> str:
    return '{"type": "unknown", "package_type": %d, "raw": "%s"}' % (obj.package_type, obj.raw.hex())


def _malformed_package(obj: MalformedPackage) -> str:
    return '{"type": "%s", "error": %s, "raw": "%s"}' % (obj.name, _text(obj.error), obj.raw.hex())


def _subtype(obj: Any) -> str:
    unknown = isinstance(obj, UnknownSubtype)
    parts = ['"type": "unknown"', f'"message_type": {obj.message_type}',
             f'"{obj.subtype_name}": {obj.subtype}'] if unknown else [f'"type": "{obj.name}"']
    parts += [f'"{name}": {int(value)}' for name, value in obj.header]
    if not unknown:
        parts.append(f'"error": {_text(obj.error)}')
    parts.append(f'"raw": "{obj.raw.hex()}"')
    return "{" + ", ".join(parts) + "}"


def _packages(obj: Any) -> str:
    """A message made of sub-packages (a robot state)."""
    parts = [f'"type": "{obj.TYPE}"', '"packages": [' + ", ".join(map(_write, obj.packages)) + "]"]
    if obj.error is not None:
        parts += [f'"error": {_text(obj.error)}', f'"raw": "{obj.raw.hex()}"']
    return "{" + ", ".join(parts) + "}"


_RUNTIME_WRITERS = ((StreamError, _stream_error), (UnknownMessage, _unknown_message),
                    (UnknownPackage, _unknown_package), (MalformedPackage, _malformed_package),
                    (UnknownSubtype, _subtype), (MalformedSubtype, _subtype))


class _Writers(dict):
    """class -> its writer, found or made on the first record of the class."""

    def __missing__(self, cls: type) -> Callable[[Any], str]:
        writer = next((w for base, w in _RUNTIME_WRITERS if issubclass(cls, base)), None)
        if writer is None:
            writer = _packages if hasattr(cls, "packages") else _compile(cls)
        self[cls] = writer
        return writer


_WRITERS = _Writers()


def _write(obj: Any) -> str:
    return _WRITERS[type(obj)](obj)


def to_json_line(record: Any) -> str:
    """One record as a canonical JSON line (without the newline)."""
    return _WRITERS[type(record)](record)


def to_dict(record: Any) -> dict:
    """One record as plain Python values, exactly as its canonical JSON parses."""
    return json.loads(to_json_line(record))


def has_error(record: Any) -> bool:
    """True when the record is a stream fault or holds a part that could not be decoded."""
    if isinstance(record, (StreamError, MalformedSubtype)):
        return True
    if isinstance(record, UnknownMessage):
        return record.error is not None
    if hasattr(record, "packages"):
        return record.error is not None or any(isinstance(p, MalformedPackage) for p in record.packages)
    return False
