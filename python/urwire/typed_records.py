"""The runtime of the typed-messages interfaces (RTDE): what every generated message class needs.

A generated module (urwire.generated.rtde) holds one class per layout; this module gives them
their base class, the readers and writers of their fields, recipes (the values of a data package
laid out by a setup exchange), a framer per direction, and the records that decoding makes of
what no layout fits. Connection state lives in the interface's own module (urwire.rtde).
"""
from __future__ import annotations

import struct
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Iterator, Optional

from . import _runtime as _rt
from ._runtime import DecodeError, StreamError
from .typed_json import message_json, raw_json, value_writers

short = _rt.short
read_prefixed_text = _rt.read_prefixed_text
write_prefixed_text = _rt.write_prefixed_text


# ---- the tables a generated module fills --------------------------------------------------------

@dataclass(frozen=True)
class ValueType:
    """An RTDE type name and its layout: `count` values of the struct code `code`."""
    name: str
    code: str
    count: int
    kind: str                      # int | float | bool: how JSON writes one item

    @property
    def size(self) -> int:
        return struct.calcsize(">" + self.code) * self.count


@dataclass(frozen=True)
class Variable:
    """One row of the variable table."""
    name: str
    type: str
    direction: str                 # "input": the client writes it; "output": the robot sends it
    label: str
    unit: Optional[str]
    since: dict                    # generation -> first version, "none" or "unknown"
    columns: tuple                 # (generation, first software version read from its column), in order
    items: tuple = ()              # a vector's item names, in order: ("Base", "Shoulder", ...)
    item_units: tuple = ()         # each item's unit where they differ (a pose: m, m, m, rad, ...)
    items: tuple = ()              # a vector's items as (name, unit) pairs: ("Base", "rad"), ...

    def available_in(self, version: tuple) -> Optional[bool]:
        """Whether a controller of this software version (major, minor[, bugfix]) has the variable:
        None when the sources do not say (its first version is "unknown")."""
        version = tuple(version) + (0,) * (3 - len(version))
        generation = [name for name, start in self.columns if version >= start][-1]
        first = self.since.get(generation, "none")
        if first == "none":
            return False
        if first == "unknown":
            return None
        wanted = tuple(int(x) for x in first.split("."))
        return version >= wanted + (0,) * (3 - len(wanted))


@dataclass(frozen=True)
class RecipeKind:
    """Outputs or inputs: which setup messages make these recipes, and whose data follow them."""
    name: str
    data_from_robot: bool
    requests: tuple
    replies: tuple


class Values(Mapping):
    """A data package's values, every one in its recipe's order. By name it is a mapping
    (`values["actual_q"]`); a recipe may name a variable twice, and then the name gives the first
    of its values, as the C library's rtde_data_find does, and `all(name)` gives each. `in_order()`
    is every value in recipe order, `pairs()` each with its name: what the JSON prints and the
    bytes hold. A name reads its value by the position `index` gives it: a decoded package shares
    its recipe's index, resolved once when the recipe was set up."""

    __slots__ = ("_names", "_ordered", "_index")

    def __init__(self, names, ordered: list, index: Optional[dict] = None):
        self._names = tuple(names)
        self._ordered = ordered            # one value per name, in order
        self._index = first_positions(self._names) if index is None else index

    @classmethod
    def of(cls, values) -> "Values":
        """Values as given: a Values, a dict by name, or (name, value) pairs."""
        if isinstance(values, Values):
            return values
        if isinstance(values, Mapping):
            return cls(tuple(values), list(values.values()))
        pairs = list(values)
        return cls([n for n, _ in pairs], [v for _, v in pairs])

    @property
    def names(self) -> tuple:
        return self._names

    def in_order(self) -> list:
        return self._ordered

    def pairs(self) -> list[tuple[str, Any]]:
        return list(zip(self._names, self._ordered))

    def all(self, name: str) -> list:
        """Every value of this name, in recipe order: one, or several where the recipe repeats it."""
        return [v for n, v in zip(self._names, self._ordered) if n == name]

    def __getitem__(self, name: str):
        return self._ordered[self._index[name]]

    def __contains__(self, name) -> bool:
        return name in self._index

    def __iter__(self):
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __eq__(self, other) -> bool:
        if isinstance(other, Values):
            return self.pairs() == other.pairs()
        if isinstance(other, Mapping):     # a dict by name: equal where no name is repeated
            return len(self._names) == len(self._index) and dict(zip(self._names, self._ordered)) == dict(other)
        return NotImplemented

    __hash__ = None

    def __repr__(self) -> str:
        # As a dict shows, with a repeated name once per value: the text views print it so.
        return "{" + ", ".join(f"{name!r}: {value!r}" for name, value in self.pairs()) + "}"


def first_positions(names) -> dict:
    """Each name's first position among `names`: where a Values finds the value of that name."""
    index: dict = {}
    for at, name in enumerate(names):
        index.setdefault(name, at)
    return index


class Recipe:
    """A recipe of one connection: its id (None for protocol 1's one output recipe), the variable
    names and their types in order, and where it was set up (the setup reply's index among the
    connection's records). A name may come twice: each gets its own value.

    Everything a data package's reading needs is worked out here, once per recipe: the struct of
    its values (`size` bytes, one unpack_from per package), the reader that turns the unpacked
    items into the values in order, the position of each name (`index`), and the writer of each
    value's JSON with its name's text (`json_writers`, typed_json.value_writers)."""

    __slots__ = ("id", "kind", "names", "types", "defined_at", "size", "index", "json_writers", "_struct", "_shapes",
                 "_read")

    def __init__(self, recipe_id: Optional[int], kind: str, names: list, types: list,
                 value_types: dict, defined_at: int = -1):
        self.id, self.kind, self.names, self.types = recipe_id, kind, tuple(names), tuple(types)
        self.defined_at = defined_at
        shapes = [value_types[t] for t in types]
        self._shapes = tuple(shapes)
        self._struct = struct.Struct(">" + "".join(s.code * s.count for s in shapes))
        self.size = self._struct.size
        self.index = first_positions(self.names)
        self._read = values_reader(self._shapes)
        self.json_writers = value_writers(self.names, self._shapes)

    def decode(self, buf, pos: int, end: int) -> tuple[Values, int]:
        if pos + self.size > end:
            raise short("values", pos, self.size, end)
        values = self._read(self._struct.unpack_from(buf, pos))
        return Values(self.names, values, self.index), pos + self.size

    def encode(self, out: bytearray, values) -> None:
        """Values in recipe order: a Values of this recipe's names by position (a name given twice
        keeps both values), anything else by name."""
        if isinstance(values, Values) and values.names == self.names:
            in_order = values.in_order()
        else:
            in_order = [values[name] for name in self.names]
        flat: list = []
        for value, shape in zip(in_order, self._shapes):
            if shape.count == 1:
                flat.append(int(value) if shape.kind == "bool" else value)
            else:
                flat.extend(value)
        out += self._struct.pack(*flat)

    def json_kinds(self) -> list[tuple[str, ValueType]]:
        return list(zip(self.names, self._shapes))


def values_reader(shapes: tuple):
    """A function from a package's unpacked items to its values in recipe order: a scalar is its
    item (a bool byte False, True or its number, as _runtime.BOOL reads it), a vector the list of
    its items. Written as one list display over fixed positions and compiled once per recipe, as
    dataclasses compile an __init__ per class: reading a package then runs no loop over its shapes
    (0.35 against 1.0 us for a driver's 9-variable recipe, beyond the unpacking)."""
    items, at = [], 0
    for shape in shapes:
        if shape.count > 1:
            items.append(f"[*f[{at}:{at + shape.count}]]")
        else:
            items.append(f"B[f[{at}]]" if shape.kind == "bool" else f"f[{at}]")
        at += shape.count
    # The text holds only positions counted from the spec's shapes: no byte of a package or reply
    # reaches it (a type no shape has makes no Recipe).
    return eval(f"lambda f: [{', '.join(items)}]", {"__builtins__": {}, "B": _rt.BOOL})


# ---- field readers and writers -----------------------------------------------------------------

def member(enum_or_bool, value: int):
    """An enum member where the code has one, else the number; a bool byte as bool (0, 1) or its number."""
    if isinstance(enum_or_bool, tuple):
        return enum_or_bool[value]
    return enum_or_bool._value2member_map_.get(value, value)


def read_rest_text(buf, pos: int, end: int) -> tuple[str, int]:
    return _rt.text(buf[pos:end]), end


def write_rest_text(out: bytearray, value: str) -> None:
    out += _rt.text_bytes(value)


def read_names(buf, pos: int, end: int, separator: str) -> tuple[list[str], int]:
    """Names joined by a separator up to the end; no bytes are no names."""
    text = _rt.text(buf[pos:end])
    return (text.split(separator) if text else []), end


def write_names(out: bytearray, names: list, separator: str) -> None:
    out += _rt.text_bytes(separator.join(names))


def read_values(buf, pos: int, end: int, recipe: Optional[Recipe]) -> tuple[Values, int]:
    if recipe is None:
        raise DecodeError("values", pos, "no recipe to read them by")
    return recipe.decode(buf, pos, end)


def write_values(out: bytearray, values: dict, recipe: Optional[Recipe]) -> None:
    if recipe is None:
        raise _rt.EncodeError("a data package is written by its recipe: pass recipe=")
    recipe.encode(out, values)


def check_end(pos: int, end: int) -> None:
    if pos < end:
        raise DecodeError("extra", pos, f"{end - pos} bytes after the layout")


# ---- messages ----------------------------------------------------------------------------------

class Message:
    """The base of every generated message class: a header (size, type code) and a body."""

    __slots__ = ("_notes",)
    NAME = ""
    CODE = 0
    JSON: tuple = ()                # (attribute, JSON kind, optional): as the primary's records list theirs
    extra = b""                     # a message has no bytes after its layout: such a one is a RawMessage
    HEADER = struct.Struct(">HB")

    @property
    def notes(self) -> dict:
        """What decoding in a connection found out about this message: a setup reply's refused
        names, the recipe a data package was read by."""
        return getattr(self, "_notes", None) or {}

    def note(self, key: str, value: Any) -> None:
        notes = getattr(self, "_notes", None)
        self._notes = {key: value} if not notes else {**notes, key: value}

    def encode(self, recipe: Optional[Recipe] = None) -> bytes:
        """The whole message, header included; a data package is written by the recipe it was
        read by, or the one given."""
        body = bytearray()
        self.encode_body(body, recipe if recipe is not None else self.notes.get("recipe"))
        return frame(self.CODE, bytes(body))

    def encode_body(self, out: bytearray, recipe=None) -> None:  # pragma: no cover - generated
        raise NotImplementedError

    def canonical_json(self) -> str:
        return message_json(self)


def frame(code: int, body: bytes) -> bytes:
    size = Message.HEADER.size + len(body)
    if size > 0xFFFF:
        raise _rt.EncodeError(f"a message of {size} bytes does not fit the uint16 size")
    return Message.HEADER.pack(size, code) + body


@dataclass(slots=True)
class RawMessage:
    """A message kept whole: a type code with no layout (named or not), one whose bytes do not fit
    its layout, or a data package of a recipe the connection never set up (`error` says which)."""
    type: str                       # the layout's name, "unknown", or the undocumented code's name
    code: int
    raw: bytes                      # the whole message, header included
    error: Optional[str] = None
    recipe_id: Optional[int] = None
    JSON = (("code", "int", False), ("recipe_id", "int", True), ("error", "text", True))   # for the text views
    extra = b""

    @property
    def LABEL(self) -> str:
        return f"{self.type.replace('_', ' ').capitalize()} ({len(self.raw)} bytes, kept whole)"

    def encode(self, recipe: Optional[Recipe] = None) -> bytes:
        return self.raw

    def canonical_json(self) -> str:
        return raw_json(self)


# ---- framing -----------------------------------------------------------------------------------

class Framer:
    """One direction of a connection: bytes in, whole messages out as (offset, code, bytes), in order.
    A size below the header's or a type code no layout knows is a stream fault: a StreamError, then
    the framer looks byte by byte for a plausible header."""

    def __init__(self, known_codes: frozenset, header: struct.Struct = Message.HEADER):
        self.known = known_codes
        self.header = header
        self.buf = bytearray()
        self.offset = 0             # of buf[0] in the direction's stream
        self.scanning = False       # looking for the next plausible header after a fault

    def feed(self, data) -> Iterator:
        self.buf += bytes(data)
        pos, head = 0, self.header.size
        buf = self.buf
        while len(buf) - pos >= head:
            size, code = self.header.unpack_from(buf, pos)
            if size < head or code not in self.known:
                # One fault per scan, however the bytes were cut: a scan that ran out of bytes
                # goes on silently when more come.
                fault = None if self.scanning else \
                    StreamError(self.offset + pos, f"bad message header: size {size}, type {code}")
                self.scanning = True
                pos = self._resync(pos + 1)
                if fault is not None:
                    yield fault
                continue
            self.scanning = False
            if len(buf) - pos < size:
                break
            yield self.offset + pos, code, bytes(buf[pos:pos + size])
            pos += size
        del buf[:pos]
        self.offset += pos

    def _resync(self, pos: int) -> int:
        head = self.header.size
        while len(self.buf) - pos >= head:
            size, code = self.header.unpack_from(self.buf, pos)
            if size >= head and code in self.known:
                return pos
            pos += 1
        return pos

    def close(self) -> list:
        if not self.buf:
            return []
        fault = StreamError(self.offset, f"truncated message: {len(self.buf)} bytes at the end of the stream")
        self.offset += len(self.buf)
        self.buf.clear()
        return [fault]

    def restart(self, offset: int) -> list:
        """The stream lost bytes: what is held is given up (close()'s record), and framing starts
        afresh at stream offset `offset`."""
        out = self.close()
        self.offset = offset
        self.scanning = False
        return out
