"""Canonical JSON of decoded records (docs/canonical-json.md): the form every target prints.

Most of a line's cost is its floats: each text is worked out once and then looked up while the
value recurs. Each class is written by a function made for it on first use.
"""
from __future__ import annotations

import ctypes
import json
import marshal
import math
import struct
from typing import Any, Callable, Optional

from .envelope import Enveloped
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
    """The digits of the shortest %.{p}g (p = 1..9) that reads back as the same float32 (read as
    a double, then rounded to float32), laid out as repr() lays out a double."""
    if type(x) is float:
        text = _F32_TEXTS.get(x)
        if text is None:
            if x - x != 0.0 or x == 0.0:
                return _f32_shortest(x)  # NaN, the infinities and the zeros: not kept
            text = _f32_digits(x)
            if "e" in text or "." not in text:  # most texts are laid out as repr() already
                text = _as_repr(text)
            if len(_F32_TEXTS) >= _TEXTS_KEPT:
                _F32_TEXTS.clear()
            _F32_TEXTS[x] = text
        return text
    if isinstance(x, int):
        return str(int(x))  # a switch field that decoded an integer case
    return _f32_shortest(x)  # a float subclass: a NaN that keeps its bits


def _f32_shortest(x: float) -> str:
    """f32_text, worked out.

    %.{p}g reads back as x when the p-digit decimal nearest x lies within half a float32 ulp of
    it. Scaled by 10**(p - 1 - E) (E: x's decimal exponent), that is: the distance from x to the
    nearest integer is below the scaled half-ulp. Double arithmetic gives both to within 1e-7
    for p <= 9, so a margin of _CLOSE decides every case but the near-ties, which take the exact
    test. Apart from powers of two the decimals that read back lie symmetrically around x, so
    once p digits fail, fewer fail too: 7 digits are tried first, then fewer while they read
    back, or 8. Only the chosen p is formatted."""
    if x - x != 0.0:
        return _nonfinite(x)
    if x == 0.0:
        return "-0.0" if math.copysign(1.0, x) < 0 else "0.0"
    return _as_repr(_f32_digits(x))


def _as_repr(text: str) -> str:
    """A %g text laid out as repr() lays out a double: fixed notation, with at least one decimal,
    from 1e-4 up to 1e16, where %g also goes to an exponent at as many places as it has digits
    ("3e+01" is "30.0", "31" is "31.0"). Both write the exponent alike below 1e-4 and from 1e16."""
    if "e" not in text:
        return text if "." in text else text + ".0"
    mantissa, _, exponent = text.partition("e")
    places = int(exponent)
    if places < -4 or places >= 16:
        return text
    # %g goes to an exponent below 1e-4, as repr() does, or at 10**p and above for p digits:
    # here, then, the digits are followed by zeros up to the point.
    sign = "-" if mantissa[0] == "-" else ""
    digits = mantissa.lstrip("-").replace(".", "")
    return sign + digits + "0" * (places + 1 - len(digits)) + ".0"


def _f32_digits(x: float) -> str:
    """The shortest %.{p}g of a finite x other than zero (f32_text before _as_repr)."""
    m, e = _frexp(x)
    row = _DECADES.get(e)
    if row is None or m == 0.5 or m == -0.5:
        return _f32_upwards(x)
    boundary, scale, half_ulp, scale_above, half_ulp_above = row
    if -boundary < x < boundary:
        v, w = x * scale, half_ulp
    else:
        v, w = x * scale_above, half_ulp_above
    d = v - ((v + _TO_INTEGER) - _TO_INTEGER)  # _fits(v, w) written out: most values end here
    if not -w + _CLOSE < d < w - _CLOSE:
        if -w - _CLOSE <= d <= w + _CLOSE:
            return _f32_upwards(x)
        v, w = v * 10.0, w * 10.0
        d = v - ((v + _TO_INTEGER) - _TO_INTEGER)
        if -w + _CLOSE < d < w - _CLOSE:
            return "%.8g" % x
        return "%.9g" % x if d < -w - _CLOSE or d > w + _CLOSE else _f32_upwards(x)
    p = 7
    while p > 1:
        v, w = v / 10.0, w / 10.0
        fits = _fits(v, w)
        if fits is None:
            return _f32_upwards(x)
        if not fits:
            break
        p -= 1
    return "%.*g" % (p, x)


_TO_INTEGER = 6755399441055744.0  # 1.5 * 2**52: (v + it) - it rounds v to an integer
_CLOSE = 1e-6


def _fits(v: float, w: float) -> Optional[bool]:
    """Whether the integer nearest v lies within w of it; None when too close to call."""
    d = v - ((v + _TO_INTEGER) - _TO_INTEGER)
    if -w + _CLOSE < d < w - _CLOSE:
        return True
    if d < -w - _CLOSE or d > w + _CLOSE:
        return False
    return None


def _decades() -> dict:
    """For each binary exponent e (math.frexp) of a normal float32 below the top binade: the power
    of ten inside its binade, and below and above that boundary the scale that leaves 7 digits
    before the point, with the float32 half-ulp 2**(e - 25) so scaled. No float32 lies between
    a power of ten and the double nearest it, so comparing with the double is exact."""
    rows = {}
    for e in range(-125, 128):
        decade = math.floor(math.log10(2.0 ** (e - 1)))
        while float(f"1e{decade}") > 2.0 ** (e - 1):
            decade -= 1
        while float(f"1e{decade + 1}") <= 2.0 ** (e - 1):
            decade += 1
        scale, scale_above = float(f"1e{6 - decade}"), float(f"1e{5 - decade}")
        half_ulp = 2.0 ** (e - 25)
        rows[e] = (float(f"1e{decade + 1}"), scale, half_ulp * scale, scale_above, half_ulp * scale_above)
    return rows


_DECADES = _decades()


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


def shown_text(s: str) -> str:
    """Text as it is shown: invalid UTF-8 bytes, kept as surrogates for lossless encoding, are
    each printed as U+FFFD."""
    if s.isascii():
        return s
    return s.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def _text(s: str) -> str:
    return _encode_text(shown_text(s))


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
# then costs a call per object, not a dispatch per member. The items of a group (the joints)
# are written inside their parent's writer, without a call per item.
#
# A robot sends its configuration, kinematics, calibration and tool settings unchanged in every
# state. So the writer of a message or sub-package keeps its last text with the exact values it
# was made from, and gives that text again while they recur. The values are compared as marshal
# writes them: a float by its bits (0.0 and -0.0 differ), a number with its type (1 and 1.0
# differ), an enum as its code. Format 2 has no references between objects, so equal values
# always give equal bytes. Building that key costs about a fifth of writing the text.

# How a value @ of each kind is written: a piece of an f-string. An f-string joins its parts
# without the tuple and the format parsing that a %-format takes.
_KINDS = {
    "int": "{@:d}",
    "enum": "{@:d}",
    "bool": '{"true" if @ else "false"}',
    "bool|text": '{text(@) if @.__class__ is str else "true" if @ else "false"}',   # a text says what went wrong
    "f32": "{f32(@)}",
    "f64": "{f64(@)}",
    "int|f32": "{f32(@)}",
    "int|f64": "{f64(@)}",
    "text": "{text(@)}",
    "hex": '"{@.hex()}"',
    "texts": '[{", ".join(map(text, @))}]',
    "values": '[{", ".join(map(value, @))}]',
    "items": '[{", ".join(map(write, @))}]',
    "list:int": '[{", ".join(map(int_text, @))}]',
    "list:bool": '[{", ".join(map(bool_text, @))}]',
    "list:f32": '[{", ".join(map(f32, @))}]',
    "list:f64": '[{", ".join(map(f64, @))}]',
    "joined": "[{@}]",  # a group's items, already written and joined into the local @
}
_EXTRA = '{o.extra and extra_text(o.extra) or ""}'
_QUOTES = "'" * 3


def _bool_text(v: Any) -> str:
    return "true" if v else "false"


def _extra_text(extra: bytes) -> str:
    return ', "extra": "%s"' % extra.hex()


def _literal(text: str) -> str:
    """Text as the literal part of an f-string."""
    return text.replace("{", "{{").replace("}", "}}")


def _fstring(members: list, before: str = "", after: str = "", tail: str = "") -> str:
    """Source of one f-string of (name, kind, value source) members, between the texts `before`
    and `after`, with the f-string piece `tail` last."""
    pieces = ", ".join(_literal(f'"{name}": ') + _KINDS[kind].replace("@", value) for name, kind, value in members)
    source = _literal(before) + pieces + tail + _literal(after)
    assert "'" not in source and "\\" not in source, source  # member and type names are identifiers
    return "f" + _QUOTES + source + _QUOTES


def _inline_items(cls: type) -> dict:
    """The group members whose items are written inside cls's writer -> their item class: items
    with no optional member and no records of their own."""
    return {name: item for name, item in getattr(cls, "ITEMS", {}).items()
            if all(not optional and kind not in ("items", "values") for _, kind, optional in item.JSON)}


def _text_source(cls: type, function: str) -> str:
    """`def <function>(o)`, the text of one record: the members in order, an optional one only
    when it is set; a message or sub-package (a class with a TYPE) starts with its type and
    ends with its extra bytes, an item of a group has neither."""
    typed = getattr(cls, "TYPE", None)
    head = f'"type": "{typed}"' if typed else ""
    inline = _inline_items(cls)
    lines = [f"def {function}(o):"]

    def member(name: str, kind: str, value: str, indent: str) -> tuple:
        """(name, kind, value source) of a member; a group's items are joined into a local first."""
        item = inline.get(name) if kind == "items" else None
        if item is None:
            return name, kind, value
        each = _fstring([(n, k, f"i.{n}") for n, k, _ in item.JSON], "{", "}")
        lines.append(f'{indent}joined_{name} = ", ".join([{each} for i in {value}])')
        return name, "joined", f"joined_{name}"

    if not any(optional for _, _, optional in cls.JSON):
        members = [member(name, kind, f"o.{name}", "    ") for name, kind, _ in cls.JSON]
        opening = "{" + head + (", " if head and members else "")
        lines.append(f"    return {_fstring(members, opening, '}', _EXTRA if typed else '')}")
        return "\n".join(lines) + "\n"
    lines.append(f"    parts = [{head!r}]" if typed else "    parts = []")
    run: list = []
    for name, kind, optional in [*cls.JSON, ("", "", True)]:
        if not optional:
            run.append(member(name, kind, f"o.{name}", "    "))
            continue
        if run:
            lines.append(f"    parts.append({_fstring(run)})")
            run = []
        if name:
            lines += [f"    v = o.{name}", "    if v is not None:"]
            lines.append(f"        parts.append({_fstring([member(name, kind, 'v', '        ')])})")
    if typed:
        lines += ["    if o.extra:", "        parts.append(extra_text(o.extra)[2:])"]
    lines.append('    return "{" + ", ".join(parts) + "}"')
    return "\n".join(lines) + "\n"


def _key_source(cls: type) -> Optional[str]:
    """Source of a tuple of every value that cls's text depends on, as marshal can write it;
    None when a member holds records that marshal cannot (global variable values)."""
    inline = _inline_items(cls)

    def value(kind: str, source: str, optional: bool, item: Optional[type] = None) -> Optional[str]:
        if kind == "enum":
            code = f"int({source})"
        elif kind == "items":
            if item is None:
                return None
            code = "[(" + "".join(value(k, f"i.{n}", False) + ", " for n, k, _ in item.JSON) + f") for i in {source}]"
        elif kind == "values":
            return None
        else:
            return source
        return f"(None if {source} is None else {code})" if optional else code

    values = [value(kind, f"o.{name}", optional, inline.get(name)) for name, kind, optional in cls.JSON]
    if None in values:
        return None
    return "(" + "".join(v + ", " for v in values) + "o.extra)"


def _writer_source(cls: type) -> str:
    """`def write_<class>(o)`: its text, kept with its key for a message or sub-package."""
    name = cls.__name__
    key = _key_source(cls) if getattr(cls, "TYPE", None) else None
    if key is None:
        return _text_source(cls, f"write_{name}")
    return _text_source(cls, f"text_{name}") + f"""
def write_{name}(o):
    global last
    try:
        key = dumps({key}, 2)
    except ValueError:  # a float32 NaN that keeps its bits: marshal writes exact floats only
        return text_{name}(o)
    kept = last
    if key == kept[0]:
        return kept[1]
    text = text_{name}(o)
    last = (key, text)
    return text
"""


def _names() -> dict:
    """What the writers' code calls."""
    return dict(f32=f32_text, f64=f64_text, text=_text, value=_value, int_text="%d".__mod__,
                bool_text=_bool_text, extra_text=_extra_text, write=_write, dumps=marshal.dumps,
                last=(None, None))


def _compile(cls: type) -> Callable[[Any], str]:
    names = _names()
    exec(_writer_source(cls), names)
    _WRITER_SPACES.append(names)
    return names[f"write_{cls.__name__}"]


_WRITER_SPACES: list = []  # the globals of each writer made: where a writer keeps its last text


def forget_texts() -> None:
    """Drop every text kept so far, of floats and of records: the next lines are worked out
    anew. The texts never depend on it; benchmarks and tests use it."""
    _F32_TEXTS.clear()
    _F64_TEXTS.clear()
    for names in _WRITER_SPACES:
        names["last"] = (None, None)


def member_text(kind: str, value: Any) -> str:
    """The canonical JSON of one member's value, given its kind in a class's JSON table."""
    write = _MEMBER_WRITERS.get(kind)
    if write is None:
        source = "f" + _QUOTES + _KINDS[kind].replace("@", "v") + _QUOTES
        write = _MEMBER_WRITERS[kind] = eval("lambda v: " + source, _names())
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


def _enveloped(obj: Enveloped) -> str:
    """The envelope's keys first, then the record's own; a record of no conversation (a fault of
    the capture file) as it is."""
    inner = _write(obj.record)
    if obj.interface is None:
        return inner
    return envelope_head(obj) + inner[1:]


def envelope_head(obj: Enveloped) -> str:
    """The start of an enveloped record's JSON: "{" and the envelope's keys, the record's own to follow."""
    return '{"interface": %s, "direction": %s, "conversation": %s, ' % (
        _text(obj.interface), _text(obj.direction), _text(obj.conversation))


_RUNTIME_WRITERS = ((Enveloped, _enveloped), (StreamError, _stream_error), (UnknownMessage, _unknown_message),
                    (UnknownPackage, _unknown_package), (MalformedPackage, _malformed_package),
                    (UnknownSubtype, _subtype), (MalformedSubtype, _subtype))


class _Writers(dict):
    """class -> its writer, found or made on the first record of the class."""

    def __missing__(self, cls: type) -> Callable[[Any], str]:
        writer = next((w for base, w in _RUNTIME_WRITERS if issubclass(cls, base)), None)
        if writer is None and hasattr(cls, "canonical_json"):   # records of the other interfaces
            writer = cls.canonical_json
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


def fails(record: Any) -> bool:
    """Whether a record makes a command exit 1, the same rule for every interface: its JSON is
    {"type": "error", ...} or carries an "error" text, at its top (a message of any interface kept
    whole with one, such as an RTDE data package of a recipe never set up) or in a part. An
    "error" that is a decoded bool (a dashboard reply that says an error) is the robot's word, not
    a fault of decoding."""
    inner = record.record if isinstance(record, Enveloped) else record
    noted = getattr(inner, "notes", None)
    return (has_error(inner) or isinstance(getattr(inner, "error", None), str)
            or isinstance(noted, dict) and isinstance(noted.get("error"), str))


def has_error(record: Any) -> bool:
    """True when the record is a stream fault or holds a part that could not be decoded."""
    if isinstance(record, Enveloped):
        return has_error(record.record)
    if getattr(record, "IS_ERROR", False):     # a record that is an error of its interface
        return True
    if isinstance(record, (StreamError, MalformedSubtype)):
        return True
    if isinstance(record, UnknownMessage):
        return record.error is not None
    if hasattr(record, "packages"):
        return record.error is not None or any(isinstance(p, MalformedPackage) for p in record.packages)
    return False
