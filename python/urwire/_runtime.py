"""Decoding helpers shared by the generated layouts: errors, text, bounds checks, values."""
from __future__ import annotations

import struct
from bisect import bisect_right
from dataclasses import dataclass
from typing import Any, Optional, Union

# Any nonzero byte is true; the tuple keeps the byte itself for 2..255 so that encoding
# gives back exactly what was read.
BOOL: tuple = (False, True) + tuple(range(2, 256))


_F32 = struct.Struct(">f")
_U32 = struct.Struct(">I")


class F32NaN(float):
    """A float32 NaN with its exact bits: struct would quiet a signalling NaN on the way."""

    __slots__ = ("bits",)


def f32_nan(buf, at: int) -> F32NaN:
    x = F32NaN("nan")
    (x.bits,) = _U32.unpack_from(buf, at)
    return x


def f32_bits(x: float) -> int:
    """The float32 bits to write for x (exact for NaNs read from the wire)."""
    if type(x) is F32NaN:
        return x.bits
    return _U32.unpack(_F32.pack(x))[0]


def f32_list(values, buf, at: int) -> list:
    return [x if x == x else f32_nan(buf, at + 4 * k) for k, x in enumerate(values)]


class DecodeError(Exception):
    """A field could not be read: carries its path and the byte offset in the message."""

    def __init__(self, path: str, offset: int, problem: str):
        super().__init__(f"{path} at offset {offset}: {problem}")
        self.path = path
        self.offset = offset
        self.problem = problem

    def within(self, prefix: str) -> "DecodeError":
        path = prefix + ("." + self.path if not self.path.startswith("[") else self.path)
        return DecodeError(path, self.offset, self.problem)

    @property
    def text(self) -> str:
        return str(self)


class EncodeError(ValueError):
    """An object cannot be written in the layout of its type."""


def short(path: str, offset: int, need: int, end: int) -> DecodeError:
    return DecodeError(path, offset, f"needs {need} bytes, {max(end - offset, 0)} left")


def short_in_run(run: tuple, pos: int, end: int) -> DecodeError:
    """The first field of a fixed run that does not fit: run holds (path, offset, size)."""
    for path, rel, size in run:
        if pos + rel + size > end:
            return short(path, pos + rel, size, end)
    raise AssertionError("short_in_run called on a run that fits")


def text(raw) -> str:
    """Bytes as text; invalid UTF-8 is kept (surrogateescape) so that encoding is lossless."""
    return bytes(raw).decode("utf-8", "surrogateescape")


def text_bytes(value: str) -> bytes:
    return value.encode("utf-8", "surrogateescape")


def read_prefixed_text(buf, pos: int, end: int, prefix: struct.Struct, path: str) -> tuple[str, int]:
    size = prefix.size
    if pos + size > end:
        raise short(path, pos, size, end)
    (n,) = prefix.unpack_from(buf, pos)
    if n < 0:
        raise DecodeError(path, pos, f"negative length {n}")
    pos += size
    if pos + n > end:
        raise short(path, pos, n, end)
    return text(buf[pos:pos + n]), pos + n


def write_prefixed_text(out: bytearray, value: str, prefix: struct.Struct) -> None:
    raw = text_bytes(value)
    try:
        out += prefix.pack(len(raw))
    except struct.error:
        raise EncodeError(f"text of {len(raw)} bytes does not fit its length prefix") from None
    out += raw


def read_terminated_texts(buf, pos: int, end: int, terminator: int) -> tuple[list[str], int]:
    """Strings each ended by terminator; a trailing unterminated part is left unread (extra)."""
    raw = bytes(buf[pos:end])
    sep = bytes((terminator,))
    last = raw.rfind(sep)
    if last < 0:
        return [], pos
    return [text(p) for p in raw[:last].split(sep)], pos + last + 1


def write_terminated_texts(out: bytearray, values: list[str], terminator: int) -> None:
    for v in values:
        out += text_bytes(v)
        out.append(terminator)


# ---- tables by software version --------------------------------------------------------------

class ByVersion(dict):
    """Software version -> the table in force then, from (low, high, table) triples with
    inclusive bounds (None: open); the newest when none is. Looked up once per version:
    `tables[version]`, or `tables(version)`."""

    def __init__(self, tables: tuple):
        super().__init__()
        self.tables = tables

    def __missing__(self, version: tuple):
        for low, high, table in self.tables:
            if (low is None or version >= low) and (high is None or version <= high):
                break
        else:
            table = self.tables[-1][2]
        self[version] = table
        return table

    def __call__(self, version: tuple):
        return self[version]


# ---- global variable values ---------------------------------------------------------------

@dataclass(slots=True)
class GlobalValue:
    """One typed value of a global variable: its type name and code (per software version)."""

    type: str
    value: Any
    code: int
    columns: Optional[int] = None
    """MATRIX only: the declared column count, which a matrix of no rows cannot show."""


# A value kind: (type name, layout, struct of its fixed part or None, True for a bool scalar)
ValueKind = tuple


_I16 = struct.Struct(">h")
_I16x2 = struct.Struct(">hh")


class ValueCodec:
    """Reads and writes the typed values of one value-type table; `min_size` is the fewest
    bytes any of its values takes, which bounds the items a LIST or MATRIX can hold."""

    def __init__(self, kinds: dict[int, ValueKind], names: dict[str, int], max_depth: int, min_size: int):
        self.kinds = kinds
        self.codes = names
        self.max_depth = max_depth
        self.min_size = min_size

    def check_count(self, items: int, path: str, at: int, pos: int, end: int) -> None:
        """Items that cannot fit in the bytes from pos are refused before any is read."""
        if items * self.min_size > end - pos:
            raise DecodeError(path, at, f"{items} items need more than the {end - pos} bytes left")

    def decode_list(self, buf, pos: int, end: int, terminator: int, path: str) -> tuple[list, int]:
        values = []
        while pos < end:
            item_path = f"{path}[{len(values)}]"
            value, pos = self.decode(buf, pos, end, item_path, 1)
            if pos >= end:
                raise short(item_path, pos, 1, end)
            if buf[pos] != terminator:
                raise DecodeError(item_path, pos, f"expected terminator 0x{terminator:02x}, found 0x{buf[pos]:02x}")
            values.append(value)
            pos += 1
        return values, pos

    def decode(self, buf, pos: int, end: int, path: str, depth: int) -> tuple[GlobalValue, int]:
        if pos >= end:
            raise short(path + ".type", pos, 1, end)
        code = buf[pos]
        if depth > self.max_depth:
            raise DecodeError(path, pos, f"nesting deeper than {self.max_depth}")
        kind = self.kinds.get(code)
        if kind is None:
            raise DecodeError(path + ".type", pos, f"unknown value type {code}")
        name, layout, fixed, _ = kind
        pos += 1
        if layout == "empty":
            return GlobalValue(name, None, code), pos
        if layout == "scalar" or layout == "array":
            if pos + fixed.size > end:
                raise short(path, pos, fixed.size, end)
            items = fixed.unpack_from(buf, pos)
            at = pos
            pos += fixed.size
            if fixed.format.endswith("f"):
                items = f32_list(items, buf, at)
            if layout == "array":
                return GlobalValue(name, list(items), code), pos
            value = BOOL[items[0]] if kind[3] else items[0]
            return GlobalValue(name, value, code), pos
        if layout == "string":
            value, pos = read_prefixed_text(buf, pos, end, fixed, path)
            return GlobalValue(name, value, code), pos
        if layout == "list":
            if pos + fixed.size > end:
                raise short(path, pos, fixed.size, end)
            (count,) = fixed.unpack_from(buf, pos)
            if count < 0:
                raise DecodeError(path, pos, f"negative length {count}")
            self.check_count(count, path, pos, pos + fixed.size, end)
            pos += fixed.size
            items = []
            for i in range(count):
                item, pos = self.decode(buf, pos, end, f"{path}[{i}]", depth + 1)
                items.append(item)
            return GlobalValue(name, items, code), pos
        # matrix: rows and columns are read together
        if pos + fixed.size > end:
            raise short(path, pos, fixed.size, end)
        rows, cols = fixed.unpack_from(buf, pos)
        if rows < 0:
            raise DecodeError(path, pos, f"negative length {rows}")
        if cols < 0:
            raise DecodeError(path, pos + fixed.size // 2, f"negative length {cols}")
        if rows and not cols:
            # Rows of no items would take no bytes at all: any number of them fits in none.
            raise DecodeError(path, pos, f"{rows} rows of 0 columns")
        self.check_count(rows * cols, path, pos, pos + fixed.size, end)
        pos += fixed.size
        matrix = []
        for r in range(rows):
            row = []
            for c in range(cols):
                item, pos = self.decode(buf, pos, end, f"{path}[{r}][{c}]", depth + 1)
                row.append(item)
            matrix.append(row)
        return GlobalValue(name, matrix, code, cols), pos

    def encode_list(self, out: bytearray, values: list, terminator: int) -> None:
        for v in values:
            self.encode(out, v)
            out.append(terminator)

    def encode(self, out: bytearray, v: GlobalValue) -> None:
        kind = self.kinds.get(v.code)
        if kind is None:
            raise EncodeError(f"value type code {v.code} is not in this version's table")
        _, layout, fixed, _ = kind
        out.append(v.code)
        if layout == "empty":
            return
        if layout == "scalar" or layout == "array":
            items = v.value if layout == "array" else [v.value]
            if fixed.format.endswith("f"):
                out += struct.pack(f">{len(items)}I", *map(f32_bits, items))
            else:
                out += fixed.pack(*items)
        elif layout == "string":
            write_prefixed_text(out, v.value, fixed)
        elif layout == "list":
            out += fixed.pack(len(v.value))
            for item in v.value:
                self.encode(out, item)
        else:
            cols = len(v.value[0]) if v.value else (v.columns or 0)
            if any(len(row) != cols for row in v.value):
                raise EncodeError("matrix rows differ in length")
            if v.value and not cols:
                raise EncodeError("matrix rows of 0 columns would not read back: they take no bytes")
            out += fixed.pack(len(v.value), cols)
            for row in v.value:
                for item in row:
                    self.encode(out, item)

    def make(self, type_name: str, value: Any) -> GlobalValue:
        """A value of the named type, coded for this table (for building messages by hand)."""
        return GlobalValue(type_name, value, self.codes[type_name])


# ---- choosing a layout by software version and by length ------------------------------------

class Form:
    """One form a type code takes on the wire: its class and the decoder of this form, the body
    sizes it can have (None: open-ended, at least `min_size`), `rep`, the version a stream is
    taken to run when this form is recognised by its length alone, and the versions that send
    it, as text."""

    __slots__ = ("cls", "decode", "sizes", "min_size", "rep", "versions")

    def __init__(self, cls: type, decode, sizes: Optional[frozenset], min_size: int, rep: tuple, versions: str):
        self.cls, self.decode, self.sizes, self.min_size = cls, decode, sizes, min_size
        self.rep, self.versions = rep, versions

    def fits(self, size: int) -> bool:
        return size in self.sizes if self.sizes is not None else size >= self.min_size


_UNKNOWN = (None, None, False, None)


def segment(starts: tuple, version: tuple) -> int:
    """The segment of the version axis that holds `version`, given where every segment but the
    first starts (the first holds every version below the second)."""
    return bisect_right(starts, version)


class Forms:
    """The forms of every type code of one message, as the generator's tables give them.

    `by_code` maps each code to its forms. `rows` has a row per segment of the version axis
    (`starts`), with an entry per code in `by_code`'s order: the index of the form the
    segment's versions send, or ~index when none is sent there and the form is the nearest
    version's below (read as its `rep`). `by_length` maps each code to the body sizes that
    exactly one fixed-size form has, and that form's index.

    `fast(version)` maps each code to the decoder of the version's form: a part that it reads to
    its last byte is that form (the common case, one dict lookup). Anything else goes through
    `part()`, which applies the whole rule. `at(version)` is a table, filled on first use, from
    `size << 8 | code` (the part's whole size, header included) to (decoder, version to decode
    with, chosen by length?, form): what `choose` says, since codes, sizes and versions repeat. A
    code the spec does not lay out maps to _UNKNOWN."""

    __slots__ = ("by_code", "starts", "rows", "by_length", "resolved", "fast_by_version", "header")

    def __init__(self, by_code: dict, starts: tuple, rows: tuple, by_length: dict, header: int = 0):
        self.by_code = by_code
        self.starts = starts
        self.rows = tuple(dict(zip(by_code, row)) for row in rows)
        self.by_length = by_length
        self.header = header
        self.resolved: dict = {}          # version -> its table of choices
        self.fast_by_version: dict = {}   # version -> {code: decoder of the version's form}

    def sent(self, version: tuple) -> dict:
        """{code: the form the version sends} for the codes that have one at this version."""
        row = self.rows[segment(self.starts, version)]
        return {code: self.by_code[code][k] for code, k in row.items() if k >= 0}

    def fast(self, version: tuple) -> dict:
        table = self.fast_by_version.get(version)
        if table is None:
            table = self.fast_by_version[version] = {code: form.decode for code, form in self.sent(version).items()}
        return table

    def at(self, version: tuple) -> dict:
        table = self.resolved.get(version)
        if table is None:
            table = self.resolved[version] = {}
        return table

    def choose(self, code: int, size: int, version: tuple) -> tuple:
        """(form, version to read it with, chosen by length?) for a body of `size` bytes: the
        version's form when it fits; else the one fixed-size form of that size, read as its
        `rep`; else the version's form, whose short or extra bytes are then reported."""
        forms = self.by_code[code]
        k = self.rows[segment(self.starts, version)][code]
        mine = forms[k] if k >= 0 else forms[~k]
        if k < 0:
            version = mine.rep
        if mine.fits(size):
            return mine, version, False
        k = self.by_length[code].get(size)
        if k is not None:
            return forms[k], forms[k].rep, True
        return mine, version, False

    def pick(self, version: tuple, code: int, size: int, header: int) -> tuple:
        """The entry for a part of `size` bytes, its header of `header` bytes included."""
        table = self.at(version)
        if len(table) > 4096:        # open-ended forms come in any size: keep the table small
            table.clear()
        if code not in self.by_code:
            found = _UNKNOWN
        else:
            form, use, by_length = self.choose(code, size - header, version)
            found = (form.decode, use, by_length, form)
        table[size << 8 | code] = found
        return found

    def part(self, buf, body: int, stop: int, code: int, version: tuple, known: bool) -> tuple:
        """(the record of a sub-package whose version's form did not read it exactly, the version
        its layout size shows when the stream's is not known, else None)."""
        decode, use, by_length, form = self.pick(version, code, stop - body + self.header, self.header)
        if decode is None:
            # Kept raw; next time straight from the fast table.
            self.fast(version)[code] = lambda buf, body, stop, version: (
                UnknownPackage(code, bytes(buf[body:stop])), stop)
            return UnknownPackage(code, bytes(buf[body:stop])), None
        try:
            pkg, used = decode(buf, body, stop, use)
        except DecodeError as exc:
            return MalformedPackage(form.cls.TYPE, code, exc.text, bytes(buf[body:stop])), None
        if used < stop:
            pkg.extra = bytes(buf[used:stop])
        return pkg, (use if by_length and not known else None)


def peek_version(buf, pos: int, skips: tuple, tail: int) -> Optional[tuple]:
    """(major, minor, 0) of a Version message from its bytes, before its layout is chosen:
    `skips` are (fixed bytes, length-prefix struct) pairs on the way, `tail` the bytes after."""
    for fixed, prefix in skips:
        pos += fixed
        if pos + prefix.size > len(buf):
            return None
        (n,) = prefix.unpack_from(buf, pos)
        pos += prefix.size + max(n, 0)
    pos += tail
    if pos + 2 > len(buf):
        return None
    return buf[pos], buf[pos + 1], 0


# ---- what is kept raw: unknown and malformed parts, stream faults ---------------------------

@dataclass(slots=True)
class UnknownMessage:
    """A message whose type the spec does not lay out (or too short for its own header)."""

    message_type: int
    raw: bytes
    error: Optional[str] = None
    TYPE = "unknown"


@dataclass(slots=True)
class UnknownPackage:
    """A robot-state sub-package whose type the spec does not lay out."""

    package_type: int
    raw: bytes
    TYPE = "unknown"


@dataclass(slots=True)
class MalformedPackage:
    """A known sub-package that could not be read: its name, the reason and its bytes."""

    name: str
    package_type: int
    error: str
    raw: bytes


class _HeaderFields:
    """The common header of a robot or program-state message, kept as the spec names it: its
    fields read by name (`record.timestamp`), and the subtype by the spec's subtype name too."""

    __slots__ = ()

    def __getattr__(self, name: str):
        if name == self.subtype_name:
            return self.subtype
        for key, value in self.header:
            if key == name:
                return value
        raise AttributeError(f"{type(self).__name__} has no field {name!r}")


@dataclass(slots=True)
class UnknownSubtype(_HeaderFields):
    """A robot or program-state message whose subtype the spec does not lay out."""

    message_type: int
    subtype_name: str    # the spec's name of the subtype field
    subtype: int
    header: tuple        # ((name, value), ...): the decoded common header, in spec order
    raw: bytes
    TYPE = "unknown"


@dataclass(slots=True)
class MalformedSubtype(_HeaderFields):
    """A known robot or program-state message that could not be read."""

    name: str
    message_type: int
    subtype_name: str
    subtype: int
    header: tuple
    error: str
    raw: bytes


@dataclass(slots=True)
class StreamError:
    """A stream-level fault: bad length, unknown type, or a truncated tail."""

    offset: int
    error: str
    TYPE = "error"


Unknown = Union[UnknownMessage, UnknownPackage, UnknownSubtype]
