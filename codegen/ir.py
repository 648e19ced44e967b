"""The resolved model (IR) every kind builds on: software versions and their ranges, scalars,
enums (one table per version range), fields and structs, and how the canonical JSON writes them.

Everything a target needs is decided here once: scalar sizes, fixed sizes of structs, which
enum table applies to which software version. Each kind adds the rest of its IR in its own
model.py (the primary interface's messages and layouts: kinds/packages/model.py). Targets never
look at the YAML.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field as dc_field
from typing import Optional, Union

from .errors import Problem

Version = tuple[int, int, int]   # major, minor, bugfix

# An upper bound written as major.minor covers every bugfix release of it ("until 5.8" takes in
# 5.8.3); bugfix numbers run far below this.
BUGFIX_ANY = 999

# The last minor release an upper bound names: "until: 5.99" (the e-Series' end) takes in every
# later 5.x. The version just past such a bound, 5.100, is no release a reader knows: it is said
# from the bound, "after 5.99".
LAST_MINOR = 99


@dataclass(frozen=True)
class Where:
    """Where a node stands in the spec: its YAML path and line, for problems found after
    resolving (a target that cannot render a node names it like a spec error)."""

    path: str = "(top)"
    line: Optional[int] = None

    def problem(self, message: str) -> Problem:
        return Problem(self.path, message, self.line)


NOWHERE = Where()


def parse_version(text: str, upper: bool = False) -> Version:
    """"5.9" -> (5, 9, 0); "5.25.1" -> (5, 25, 1). As an upper bound, "5.8" is (5, 8, BUGFIX_ANY)."""
    parts = [int(x) for x in text.split(".")]
    if len(parts) == 2:
        parts.append(BUGFIX_ANY if upper else 0)
    major, minor, bugfix = parts
    return major, minor, bugfix


def version_text(version: Version) -> str:
    """(5, 9, 0) -> "5.9"; (5, 25, 1) -> "5.25.1"; an upper bound (5, 8, BUGFIX_ANY) -> "5.8"."""
    major, minor, bugfix = version
    return f"{major}.{minor}" if bugfix in (0, BUGFIX_ANY) else f"{major}.{minor}.{bugfix}"


def past_last_minor(version: Version) -> Optional[Version]:
    """The bound X.99 (every X.99.x) when `version` is the first version past it: (10, 100, 0) ->
    (10, 99, BUGFIX_ANY); None for a version that reads as itself."""
    major, minor, bugfix = version
    return (major, LAST_MINOR, BUGFIX_ANY) if (minor, bugfix) == (LAST_MINOR + 1, 0) else None


def version_number(version: Version) -> int:
    """One integer per version, in version order: what targets without tuples compare."""
    major, minor, bugfix = version
    return (major * 1000 + minor) * 1000 + min(bugfix, BUGFIX_ANY)


def version_of_number(number: int) -> Version:
    """The version a version_number counts: 5025001 -> (5, 25, 1)."""
    return number // 1_000_000, number // 1000 % 1000, number % 1000


@dataclass(frozen=True)
class VersionRange:
    """Inclusive range of software versions; None means unbounded."""

    low: Optional[Version] = None
    high: Optional[Version] = None

    def contains(self, version: Version) -> bool:
        return (self.low is None or version >= self.low) and (self.high is None or version <= self.high)

    def overlaps(self, other: "VersionRange") -> bool:
        lo = max(self.low or (0, 0, 0), other.low or (0, 0, 0))
        hi = min(self.high or (1 << 30, 0, 0), other.high or (1 << 30, 0, 0))
        return lo <= hi

    @property
    def unbounded(self) -> bool:
        return self.low is None and self.high is None

    def describe(self, first: Optional[Version] = None) -> str:
        """The range as a reader says it: "1.5 to 1.8", "5.25.1 and later", "up to 3.1", "5.0"
        (every 5.0.x), "after 10.99" (past_last_minor). An upper bound keeps an explicit bugfix
        ("up to 5.25.0": before 5.25.1); a range that starts at `first` (the first release) reads
        "up to". Every target's comments, docstrings and run-time texts use this: no bound prints
        as a tuple or a number."""
        if self.low and self.high and self.low[:2] == self.high[:2] and (self.low[2], self.high[2]) == (0, BUGFIX_ANY):
            return version_text(self.low)                            # one minor release: "1.8"
        low = None if self.low is None or (first is not None and self.low <= first) else self.low
        high = self.high and (version_text(self.high) if self.high[2] else "%d.%d.0" % self.high[:2])
        bound = low and past_last_minor(low)
        if bound:
            since = f"after {version_text(bound)}"
            return f"{since}, up to {high}" if self.high else since
        if low and self.high:
            return f"{version_text(low)} to {high}"
        if low:
            return f"{version_text(low)} and later"
        if self.high:
            return f"up to {high}"
        return "all versions"


ALL_VERSIONS = VersionRange()


@dataclass(frozen=True)
class Scalar:
    name: str
    size: int
    signed: bool
    is_float: bool = False
    is_bool: bool = False

    @property
    def is_integer(self) -> bool:
        return not self.is_float and not self.is_bool

    @property
    def bits(self) -> int:
        return self.size * 8

    @property
    def min(self) -> int:
        return -(1 << (self.bits - 1)) if self.signed else 0

    @property
    def max(self) -> int:
        return (1 << (self.bits - 1)) - 1 if self.signed else (1 << self.bits) - 1


SCALARS: dict[str, Scalar] = {
    s.name: s
    for s in (
        Scalar("bool", 1, False, is_bool=True),
        Scalar("int8", 1, True),
        Scalar("uint8", 1, False),
        Scalar("int16", 2, True),
        Scalar("uint16", 2, False),
        Scalar("int32", 4, True),
        Scalar("uint32", 4, False),
        Scalar("int64", 8, True),
        Scalar("uint64", 8, False),
        Scalar("float32", 4, True, is_float=True),
        Scalar("float64", 8, True, is_float=True),
    )
}


@dataclass
class EnumValue:
    name: str
    value: int
    doc: str = ""
    undocumented: bool = False
    versions: VersionRange = ALL_VERSIONS
    field_note: str = ""     # sources, for docs only


@dataclass
class EnumTable:
    versions: VersionRange
    values: list[EnumValue]


@dataclass
class Enum:
    name: str
    scalar: Scalar
    doc: str
    field_note: str
    tables: list[EnumTable]

    @property
    def versioned(self) -> bool:
        """True when the codes depend on the software version (the value-type tables)."""
        return len(self.tables) > 1

    @property
    def values(self) -> list[EnumValue]:
        """Every member of every table, once per (name, value), in table order."""
        seen, out = set(), []
        for table in self.tables:
            for v in table.values:
                if (v.name, v.value) not in seen:
                    seen.add((v.name, v.value))
                    out.append(v)
        return out

    @property
    def names(self) -> list[str]:
        """Every member name once, in first-seen order."""
        return list(dict.fromkeys(v.name for v in self.values))

    def member(self, name: str) -> EnumValue:
        for v in self.values:
            if v.name == name:
                return v
        raise KeyError(name)

    def table_for(self, version: Version) -> EnumTable:
        for table in self.tables:
            if table.versions.contains(version):
                return table
        return self.tables[-1]


# ---- fields -------------------------------------------------------------------------------

@dataclass
class Field:
    name: str
    label: str = ""                         # what a person reads: "Actual joint position"
    unit: Optional[str] = None              # of a physical value: "rad", "°C" (the schema's list)
    doc: str = ""
    field_note: str = ""
    present_if: Optional[str] = None        # name of an earlier field: present when it is nonzero
    versions: VersionRange = ALL_VERSIONS   # present only for streams of these versions
    where: Where = NOWHERE

    @property
    def conditional(self) -> bool:
        return self.present_if is not None or not self.versions.unbounded

    @property
    def titled(self) -> str:
        """The label with its unit, as a heading reads it: "Actual joint position (rad)"."""
        return f"{self.label} ({self.unit})" if self.unit else self.label

    @property
    def fixed_size(self) -> Optional[int]:
        """Bytes on the wire when known without reading; None for variable-size fields."""
        return None

    @property
    def min_size(self) -> int:
        return self.fixed_size or 0


@dataclass
class ScalarField(Field):
    scalar: Scalar = SCALARS["uint8"]
    enum: Optional[Enum] = None
    bits: list[str] = dc_field(default_factory=list)
    bit_labels: list[str] = dc_field(default_factory=list)   # one per bit: "Standard 0"

    @property
    def fixed_size(self) -> Optional[int]:
        return self.scalar.size


@dataclass
class ArrayField(Field):
    """`count` scalars in a row."""

    scalar: Scalar = SCALARS["uint8"]
    count: int = 1
    enum: Optional[Enum] = None

    @property
    def fixed_size(self) -> Optional[int]:
        return self.scalar.size * self.count


@dataclass
class GroupField(Field):
    """A repeated group of fields: `count` times, or until the end of the layout."""

    item: "Struct" = None  # type: ignore[assignment]
    count: Optional[int] = None
    item_label: str = "Item"              # one entry: "Joint" (shown as "Joint 0")

    @property
    def to_end(self) -> bool:
        return self.count is None

    @property
    def fixed_size(self) -> Optional[int]:
        if self.count is None or self.item.fixed_size is None:
            return None
        return self.count * self.item.fixed_size

    @property
    def min_size(self) -> int:
        return 0 if self.count is None else self.count * self.item.min_size


@dataclass
class StringField(Field):
    """Bytes shown as text: length-prefixed (`length`), or running to the end of the layout."""

    length: Optional[Scalar] = None

    @property
    def to_end(self) -> bool:
        return self.length is None

    @property
    def min_size(self) -> int:
        return self.length.size if self.length else 0


@dataclass
class StringListField(Field):
    """Strings each ended by `terminator`, until the end of the layout."""

    terminator: int = 0x0A
    item_label: str = ""                  # one string: "Variable name"


@dataclass
class BytesField(Field):
    """Opaque bytes until the end of the layout."""


@dataclass
class SwitchField(Field):
    """One scalar whose type is chosen by the value of an earlier field."""

    selector: ScalarField = None  # type: ignore[assignment]
    cases: dict[int, Scalar] = dc_field(default_factory=dict)
    default: Scalar = SCALARS["uint32"]

    @property
    def fixed_size(self) -> Optional[int]:
        sizes = {s.size for s in self.cases.values()} | {self.default.size}
        return sizes.pop() if len(sizes) == 1 else None

    @property
    def min_size(self) -> int:
        return min([s.size for s in self.cases.values()] + [self.default.size])


@dataclass
class ValueListField(Field):
    """Typed values (a type byte, its data, `terminator`) until the end of the layout."""

    value_type: Enum = None  # type: ignore[assignment]
    terminator: int = 0x0A
    item_label: str = ""                  # one value: "Variable" (shown as "Variable 0")


AnyField = Union[ScalarField, ArrayField, GroupField, StringField, StringListField, BytesField,
                 SwitchField, ValueListField]


@dataclass
class Struct:
    name: str
    doc: str
    fields: list[AnyField]

    @property
    def fixed_size(self) -> Optional[int]:
        total = 0
        for f in self.fields:
            if f.conditional or f.fixed_size is None:
                return None
            total += f.fixed_size
        return total

    @property
    def min_size(self) -> int:
        return sum(0 if f.conditional else f.min_size for f in self.fields)

    def field(self, name: str) -> AnyField:
        for f in self.fields:
            if f.name == name:
                return f
        raise KeyError(name)

    @property
    def needs_version(self) -> bool:
        """True when decoding depends on the stream's software version."""
        for f in self.fields:
            if not f.versions.unbounded or isinstance(f, ValueListField):
                return True
            if isinstance(f, (ScalarField, ArrayField)) and f.enum is not None and f.enum.versioned:
                return True
            if isinstance(f, GroupField) and f.item.needs_version:
                return True
        return False

    def at(self, version: Version) -> "Struct":
        """The struct as a stream of `version` sends it: its fields of that version, with no
        version ranges left (flag conditions stay)."""
        fields = []
        for f in self.fields:
            if f.versions.contains(version):
                g = copy.copy(f)
                g.versions = ALL_VERSIONS
                if isinstance(g, GroupField):
                    g.item = g.item.at(version)
                fields.append(g)
        return Struct(self.name, self.doc, fields)

    def named(self, name: str) -> list[AnyField]:
        """Every entry of a name: one, or several in disjoint version ranges."""
        return [f for f in self.fields if f.name == name]

    @property
    def fixed_item(self) -> bool:
        """True when an item of this struct is read inside its parent's fixed run: every field's
        size is known without reading and no condition or choice is made on the way."""
        return all(in_fixed_run(g) and not g.conditional for g in self.fields)

    @property
    def public_fields(self) -> list[AnyField]:
        """One field per name, in first-seen order: what a record holds (its attributes,
        members, filter fields). A name with several entries takes the widest scalar: resolve
        lets them differ in size only (resolve.same_name), so it holds every entry's values."""
        out: dict[str, AnyField] = {}
        for f in self.fields:
            if f.name not in out:
                out[f.name] = f
            elif isinstance(f, ScalarField) and f.scalar.size > out[f.name].scalar.size:
                out[f.name] = f
        return list(out.values())


def in_fixed_run(f: AnyField) -> bool:
    """Fields a fixed run can hold: known size, and no choice made while reading."""
    if isinstance(f, GroupField):
        return f.count is not None and f.item.fixed_item
    return f.fixed_size is not None and not isinstance(f, SwitchField)


# ---- canonical JSON kinds (docs/canonical-json.md): how every target writes a value ----------

def scalar_json_kind(s: Scalar) -> str:
    """bool, int, f32 (shortest text that reads back as the float32) or f64."""
    return "bool" if s.is_bool else ("f32" if s.size == 4 else "f64") if s.is_float else "int"


def json_kind(f: AnyField) -> str:
    """How the canonical JSON writes a field: a scalar's kind, enum (by name), list:<kind>,
    items, text, texts, hex, int|<float kind> (a switch), values."""
    if isinstance(f, ScalarField):
        return "enum" if f.enum is not None and not f.scalar.is_bool else scalar_json_kind(f.scalar)
    if isinstance(f, ArrayField):
        return "list:" + scalar_json_kind(f.scalar)
    if isinstance(f, GroupField):
        return "items"
    if isinstance(f, StringField):
        return "text"
    if isinstance(f, StringListField):
        return "texts"
    if isinstance(f, BytesField):
        return "hex"
    if isinstance(f, SwitchField):
        floats = [s for s in list(f.cases.values()) + [f.default] if s.is_float]
        return "int|" + scalar_json_kind(floats[0]) if floats else "int"
    return "values"
