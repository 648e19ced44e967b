"""The Wireshark model of the primary interface, computed once from the plan: what both dissectors
show, as plain data that the Lua (lua.py) and the native C (epan.py) renderers only spell.

Every decision is made here: which field each spec field becomes (one per filter name, of the
widest type among the name's entries in every version), its filter name
(`ur.<message_or_package>.<field>`, docs/contract.md#what-every-target-keeps), label, description
and unit; the value strings of every enum (one per version table); the descriptors each layout is
walked with (one per field, in wire order, a `Cond` around each condition group); the forms each
type code takes across software versions (plan.Variant); where the Version message keeps its
numbers; and which fields the Info column shows. Names here are the model's own (field keys
"<owner>.<name>", layout and part names unique in their kind); each renderer spells them in its
language, and versions stay versions (ir.Version) or ir.version_number integers.
"""
from __future__ import annotations

from dataclasses import dataclass, field as dc_field
from typing import ClassVar, Optional, Union

from ... import ir
from ...blurbs import blurb, one_line
from ...comments import node_text
from ...errors import Problem, SpecError
from ...naming import words
from . import model, plan
from .naming import layout_label, table_suffix, wireshark_field

# The most tree items one message shows in Wireshark (runtime/lua/packages/items.lua, runtime/epan/packages/ur_items.c);
# an expert note says how many more it holds. Wireshark itself stops a packet at a million items.
MAX_TREE_ITEMS = 10_000


# ---- value strings ----------------------------------------------------------------------------

@dataclass
class ValueStrings:
    """One version table of an enum: its names by wire value. `suffix` says its versions as an
    identifier part (table_suffix: UpTo3_2); the newest table has none, and is the value strings of
    the enum's fields, so that filters by name follow today's firmware."""

    suffix: Optional[str]
    versions: str                     # "3.3 to 5.8"
    low: Optional[int]                # ir.version_number, None for open
    high: Optional[int]
    entries: list[tuple[int, str]]


@dataclass
class EnumStrings:
    """Every value string of an enum; `versioned` when its codes depend on the version, then the
    dissectors also name a code by the stream version's table."""

    name: str
    doc: str
    versioned: bool
    tables: list[ValueStrings]

    @property
    def newest(self) -> ValueStrings:
        return self.tables[-1]


# ---- fields -----------------------------------------------------------------------------------

@dataclass
class Field:
    """One Wireshark field (a filter name). `shape` says what it holds: integer, float, bool, flag
    (one bit of an integer field), none (a subtree), text, bytes."""

    key: str                          # "<owner>.<name>": the model's name of it
    shape: str
    filter: str                       # ur.robot_mode_data.robot_mode
    label: str
    description: str
    scalar: Optional[str] = None      # integer, float, bool: the spec's scalar (the widest of its entries)
    hex: bool = False                 # integer: shown in hexadecimal (an unsigned one split into bits)
    ascii: bool = False               # text: ASCII only (a value type's name), else any Unicode
    enum: Optional[EnumStrings] = None    # integer: named by this enum's newest value strings
    unit: Optional[str] = None        # integer or float: its spec unit ("rad")
    bits: int = 0                     # flag: width of its integer
    mask: int = 0                     # flag: its bit
    parent: Optional[str] = None      # flag: the key of its integer


# The dissector's own fields and expert infos, after the spec's: the Lua dissector declares the
# same in runtime/lua/packages/declare.lua, in the same order. No spec field may take their filter names.
OWN_FIELDS = [
    Field("raw", "bytes", "ur.raw", "Raw",
          "Bytes kept whole: a type the spec does not lay out, or a part that could not be read."),
    Field("extra", "bytes", "ur.extra", "Extra bytes", "Bytes after the known layout of a package or message."),
    Field("skipped", "bytes", "ur.skipped", "Skipped bytes",
          "Bytes skipped while looking for the next plausible message header."),
    Field("software_version", "text", "ur.software_version", "Software version",
          "The software version this message is read with (its layouts, enum names and value types): the "
          "stream's Version message, else the ur.version preference, else what the layout sizes show (\"3.2 to "
          "3.4 (from layout sizes)\"), else the default.", ascii=True),
    Field("version_assumed", "bool", "ur.version_assumed", "Version assumed",
          "True when no Version message was seen on this stream: the version comes from the ur.version "
          "preference, the layout sizes or the default.", scalar="bool"),
    Field("unknown_package", "none", "ur.unknown_package", "Unknown package",
          "A sub-package type the spec does not lay out, kept raw."),
    Field("urscript", "text", "ur.urscript", "URScript", "Bytes from the client to the robot: URScript program text."),
]


@dataclass(frozen=True)
class Expert:
    name: str
    filter: str
    group: str                        # malformed, protocol, undecoded, assumption (Wireshark's PI_ groups)
    severity: str                     # error, warn, note
    text: str


EXPERTS = [
    Expert("bad_length", "ur.bad_length", "malformed", "error", "Message length out of range (resynchronising)"),
    Expert("bad_type", "ur.bad_type", "malformed", "error", "Unknown message type (resynchronising)"),
    Expert("malformed", "ur.malformed", "malformed", "error", "Package or message too short or malformed"),
    Expert("extra", "ur.extra_bytes", "protocol", "warn", "Bytes after the known layout"),
    Expert("unknown", "ur.unknown", "undecoded", "note", "Type not laid out by the spec, kept raw"),
    Expert("assumed", "ur.assumed_version", "assumption", "note", "Software version assumed (no Version message seen)"),
    Expert("version_range", "ur.version_out_of_range", "protocol", "warn",
           "Version message number out of range: set aside, the stream is read as major.minor"),
    Expert("by_length", "ur.layout_by_length", "assumption", "note",
           "Layout chosen by its length, not by the software version"),
    Expert("items_hidden", "ur.items_hidden", "undecoded", "note", "More tree items than a message shows"),
    Expert("internal", "ur.internal_error", "malformed", "error", "urwire dissector error"),
]
OWN_NAMES = {f.filter for f in OWN_FIELDS} | {e.filter for e in EXPERTS}


# ---- descriptors: what the runtime walks, one per field ---------------------------------------

@dataclass
class Descriptor:
    kind: ClassVar[str]
    path: str                         # the field's name in its layout
    show: Optional[str]               # Info column: the text put before its value, when shown


@dataclass
class Read(Descriptor):
    """A scalar read into `field`; `value` when its wire type is narrower than the field's (another
    entry of the name is wider), so the value is added explicitly."""

    field: str
    size: int
    signed: bool
    float: bool
    unit: Optional[str]               # a float's unit as the tree shows it after the value: " rad"
    enum: Optional[EnumStrings]       # its value strings; by version too when enum.versioned
    label: str
    value: bool = False

    @property
    def by_version(self) -> bool:
        """Named by the stream version's table of its enum (the label then heads the name)."""
        return self.enum is not None and self.enum.versioned


@dataclass
class Scalar(Read):
    kind: ClassVar[str] = "scalar"
    keep: Optional[str] = None        # kept for a later field (present_if, a switch): its name


@dataclass
class Bits(Scalar):
    kind: ClassVar[str] = "bits"
    bits: list[str] = dc_field(default_factory=list)    # one flag field per named bit


@dataclass
class Array(Read):
    kind: ClassVar[str] = "array"
    count: int = 0


@dataclass
class Group(Descriptor):
    kind: ClassVar[str] = "group"
    field: str
    label: str
    count: Optional[int]              # None: repeated to the end
    size: Optional[int]               # an item's fixed size, None when variable
    item: str                         # the layout of one item


@dataclass
class String(Descriptor):
    kind: ClassVar[str] = "string"
    field: str


@dataclass
class PString(Descriptor):
    kind: ClassVar[str] = "pstring"
    field: str
    size: int                         # of the length prefix
    signed: bool


@dataclass
class Strings(Descriptor):
    kind: ClassVar[str] = "strings"
    field: str
    term: int


@dataclass
class Bytes(Descriptor):
    kind: ClassVar[str] = "bytes"
    field: Optional[str]


@dataclass
class Case:
    field: str
    size: int
    unit: Optional[str]               # as Read.unit
    code: Optional[int] = None        # the selector's value; None for the default


@dataclass
class Switch(Descriptor):
    kind: ClassVar[str] = "switch"
    sel: str
    default: Case
    cases: list[Case]


@dataclass
class Values(Descriptor):
    """Typed values: one item per value, its type, and one field per data kind."""

    kind: ClassVar[str] = "values"
    term: int
    label: str
    roles: list[tuple[str, str]]      # (role, field key): item, type, code, count, rows, cols, row
    kinds: list[tuple[str, str]]      # (scalar name, field key)
    string: str


@dataclass
class Cond:
    """The descriptors of a condition group: present when `present_if` (a kept field) is nonzero
    and the stream's version is within low..high (ir.version_number, None for open)."""

    kind: ClassVar[str] = "cond"
    present_if: Optional[str]
    low: Optional[int]
    high: Optional[int]
    fields: list["AnyDescriptor"]


AnyDescriptor = Union[Scalar, Bits, Array, Group, String, PString, Strings, Bytes, Switch, Values, Cond]


@dataclass
class Layout:
    name: str                         # unique among layouts
    doc: str
    descriptors: list[AnyDescriptor]


# ---- messages ---------------------------------------------------------------------------------

@dataclass
class Part:
    """A sub-package, subtype or body layout of a message."""

    name: str                         # unique among parts
    key: str                          # the layout's spec name
    label: str
    item: str                         # its subtree field
    layout: str
    header: Optional[str] = None      # subtypes: the header layout, its fields under the subtype's name
    summary: bool = False             # packages: it has an Info summary
    needs_version: bool = False       # subtypes and bodies: reading or choosing it depends on the version
    refs: list[str] = dc_field(default_factory=list)   # packages: its fields (what a filter may ask for)


@dataclass
class Form:
    """One form of a type code (plan.Variant)."""

    part: Part
    sizes: Optional[list[int]]        # its body sizes; None when open-ended
    min: int
    rep: ir.Version                   # the version it stands for when its length alone chose it
    versions: str                     # the versions that send it


@dataclass
class Code:
    """The forms of one type code, and the plan's tables: the form of each segment
    (MessagePlan.by_segment: 1-based, negative for the nearest below's) and the sizes that
    recognise one form (by_length: (size, 1-based form))."""

    code: int
    single: bool                      # one form serves every version
    forms: list[Form]
    segments: list[int]
    by_length: list[tuple[int, int]]
    summary: bool = False             # packages: one of its forms has a summary


@dataclass
class Message:
    """A message type: `kind` packages (robot state), subtypes (a header, then a subtype byte) or
    body (one layout after the message header)."""

    kind: str
    code: int
    label: str
    doc: str
    forms_table: str                  # the name of its table of forms
    parts: list[Part]
    codes: list[Code]
    body_offset: int = 0
    names: Optional[EnumStrings] = None   # packages and subtypes: the codes' names
    needs_version: bool = False       # packages: reading or choosing one depends on the version
    length: Optional[str] = None      # packages: the package header's fields
    type: Optional[str] = None
    header: Optional[str] = None      # subtypes: the header and subtype layout
    subtype_field: Optional[str] = None
    subtype_label: Optional[str] = None


# ---- the protocol -----------------------------------------------------------------------------

@dataclass
class ValueKind:
    code: int
    name: str
    layout: str                       # empty | string | array | scalar | list | matrix
    item: Optional[str]               # the scalar of a scalar or array
    size: int
    count: int
    length: int                       # bytes of a string length, list count, matrix counts


@dataclass
class ValueTypes:
    """The value-type codes of one software-version range."""

    low: Optional[int]
    high: Optional[int]
    versions: str
    kinds: list[ValueKind]
    min_size: int


@dataclass
class VersionStep:
    fixed: int                        # bytes to skip
    prefix: int                       # then a length-prefixed text with a prefix of this size
    signed: bool


@dataclass
class Bugfix:
    size: int
    signed: bool
    low: Optional[int]
    high: Optional[int]


@dataclass
class VersionReader:
    """Where the Version message keeps its numbers: fixed bytes and length-prefixed strings, then
    major and minor, then (in the versions its range gives) the bugfix number."""

    message: int
    subtype: int
    subtype_offset: int
    steps: list[VersionStep]
    tail: int
    rest: int
    bugfix: Optional[Bugfix]


@dataclass
class Dissector:
    title: str
    doc: str
    enums: list[EnumStrings]
    fields: list[Field]
    layouts: list[Layout]
    messages: list[Message]
    version: VersionReader
    value_tables: list[ValueTypes]
    known_codes: list[int]
    message_types: EnumStrings
    constants: dict                   # sizes and defaults the runtime reads
    segment_starts: list[ir.Version]  # where every segment of the version axis but the first starts
    default_version: ir.Version
    own_fields: list[Field] = dc_field(default_factory=lambda: list(OWN_FIELDS))
    experts: list[Expert] = dc_field(default_factory=lambda: list(EXPERTS))


# ---- building it ------------------------------------------------------------------------------

def describe(f: ir.Field, sent: str = "") -> str:
    """A field's description (its blurb, codegen/blurbs.py): the spec's doc, else its label; its
    unit; the versions that send it (`sent`, see sent_by)."""
    return blurb(f.doc, f.label, f.unit, sent=sent)


def sent_by(struct: ir.Struct, owner: str, out: dict) -> None:
    """Which versions send each field of a layout, by its key: "3.0 and later", or "" for every
    version. The plan's forms hold fields with their version ranges already applied."""
    for name in dict.fromkeys(f.name for f in struct.fields):
        entries = struct.named(name)
        ranges = [] if any(e.versions.unbounded for e in entries) else [e.versions.describe() for e in entries]
        out[f"{owner}.{name}"] = ", ".join(ranges)
        for e in entries:
            if isinstance(e, ir.GroupField):
                sent_by(e.item, owner, out)


def _a(word: str) -> str:
    return ("an " if word[0] in "aeiou" else "a ") + word


def unit_text(unit: Optional[str]) -> Optional[str]:
    """What follows a value in the tree: " rad"."""
    return f" {unit}" if unit else None


def version_number(v: Optional[ir.Version]) -> Optional[int]:
    """A version as the runtime compares it: ir.version_number (5.25.1 is 5025001); None stays."""
    return None if v is None else ir.version_number(v)


# Descriptor kinds the Info column can step over on its way to a summary field, and the kinds it
# can show (runtime/lua/packages/info.lua, runtime/epan/packages/ur_info.c).
STEPS_OVER = {"scalar", "bits", "array", "pstring", "string"}
SHOWS = {"scalar", "bits", "pstring", "string"}
SCALAR_SHAPES = {"integer", "float", "bool"}


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.problems: list[Problem] = []
        self.fields: list[Field] = []
        self.by_key: dict[str, Field] = {}
        self.layouts: list[Layout] = []
        self.names: set[tuple[str, str]] = set()   # (layouts or parts, name) taken
        self.strings: dict[str, EnumStrings] = {}   # enum -> its value strings
        # Every scalar entry of a field key (a name may repeat in other versions, with another
        # wire type): the field takes the widest; narrower reads add their value explicitly.
        self.entries: dict[str, list[ir.Scalar]] = {}
        self.reads: list[tuple[Read, str, ir.Scalar]] = []
        self.sent: dict[str, str] = {}        # field key -> the versions that send it (sent_by)

    # ---- fields ----

    def add_field(self, pf: Field, where: ir.Where = ir.NOWHERE) -> str:
        """Declare a field once (a header layout shared by subtypes names it again, a name may
        repeat in another version's entry); its key."""
        known = self.by_key.get(pf.key)
        if known is None and pf.filter in OWN_NAMES:
            self.problems.append(where.problem(f"{pf.filter} is the dissector's own name: give the field or "
                                               f"layout a name of its own"))
        if known is None:
            self.by_key[pf.key] = pf
            self.fields.append(pf)
        elif known.shape != pf.shape and not {known.shape, pf.shape} <= SCALAR_SHAPES:
            self.problems.append(where.problem(
                f"{pf.filter} would be both {_a(known.shape)} and {_a(pf.shape)} field: "
                "a Wireshark filter name has one type, give one of them a name of its own"))
        elif known.shape == "flag" and known.mask != pf.mask:
            self.problems.append(where.problem(f"the bit {pf.filter} stands at two places"))
        elif pf.description:
            known.description = pf.description   # a name's later entry is its newer form: its doc describes it
        return pf.key

    def owned_field(self, owner: str, name: str, shape: str, label: str, desc: str,
                    where: ir.Where = ir.NOWHERE, **more) -> str:
        return self.add_field(Field(f"{owner}.{name}", shape, wireshark_field(owner, name), label, desc, **more),
                              where)

    def scalar_field(self, owner: str, name: str, s: ir.Scalar, enum: Optional[ir.Enum], label: str, doc: str,
                     where: ir.Where = ir.NOWHERE, unit: Optional[str] = None, hex_base: bool = False) -> str:
        """An integer's unit is its field's unit string, which every Wireshark shows; a float's
        follows its value in the tree (Read.unit), as Wireshark 4.0 shows no unit string of a
        float field."""
        self.entries.setdefault(f"{owner}.{name}", []).append(s)
        if s.is_float:
            return self.owned_field(owner, name, "float", label, doc, where, scalar=s.name, unit=unit)
        if s.is_bool:
            return self.owned_field(owner, name, "bool", label, doc, where, scalar=s.name)
        if unit:
            return self.owned_field(owner, name, "integer", label, doc, where, scalar=s.name, unit=unit)
        return self.owned_field(owner, name, "integer", label, doc, where, scalar=s.name, hex=hex_base,
                                enum=self.strings[enum.name] if enum is not None else None)

    def read(self, d: Read, key: str, s: ir.Scalar) -> Read:
        """A descriptor that reads a scalar into field `key`: told after every layout is built
        whether its wire type is narrower than the field's (settle)."""
        self.reads.append((d, key, s))
        return d

    def settle(self) -> None:
        """One field per key, of the widest type among its entries (a filter name has one type:
        docs/contract.md#names-across-versions; resolve.same_name lets the entries of a name
        differ in size only); narrower reads then add their value explicitly."""
        wide: dict[str, ir.Scalar] = {}
        for key, entries in self.entries.items():
            scalars = list({s.name: s for s in entries}.values())
            if len(scalars) == 1:
                continue
            wide[key] = max(scalars, key=lambda s: s.size)
            self.by_key[key].scalar = wide[key].name
            for flag in self.fields:
                if flag.parent == key:
                    flag.bits = wide[key].bits
        for d, key, s in self.reads:
            d.value = s.name != wide.get(key, s).name

    def header_field(self, key: str, h: model.HeaderField) -> str:
        """ur.length, ur.type, ur.package.*: outside the owner.field scheme."""
        return self.add_field(Field(key, "integer", f"ur.{key}", h.label, h.doc, scalar=h.scalar.name,
                                    enum=self.strings[h.enum.name] if h.enum is not None else None), h.where)

    def add_item(self, name: str, label: str, doc: str, where: ir.Where) -> str:
        """The subtree field of a package or message: ur.<name>, true when it is present."""
        if name in self.by_key:
            self.problems.append(where.problem(f"the filter name ur.{name} is taken already"))
        return self.add_field(Field(name, "none", f"ur.{name}", label, doc), where)

    def unique(self, space: str, name: str) -> str:
        """A layout or part name, once (two group items may share a name in other versions)."""
        unique, n = name, 2
        while (space, unique) in self.names:
            unique, n = f"{name}_{n}", n + 1
        self.names.add((space, unique))
        return unique

    def enum_of(self, enum: Optional[ir.Enum]) -> Optional[EnumStrings]:
        return None if enum is None else self.strings[enum.name]

    # ---- descriptors ----

    def descriptors(self, owner: str, steps: list[plan.Step], keep: set[str],
                    show: Optional[dict] = None) -> list[AnyDescriptor]:
        """The descriptors of a layout's plan, in wire order: one per field, and a `Cond` around
        the fields of each condition group."""
        out: list[AnyDescriptor] = []
        show = show or {}
        for step in steps:
            if isinstance(step, plan.CondGroup):
                c = step.condition
                out.append(Cond(c.flag, version_number(c.low), version_number(c.high),
                                self.descriptors(owner, step.steps, keep, show)))
                continue
            for f in step.fields if isinstance(step, plan.FixedRun) else [step.field]:
                out.append(self.descriptor(owner, f, describe(f, self.sent.get(f"{owner}.{f.name}", "")), f.name,
                                           keep, show.get(f.name)))
        return out

    def descriptor(self, owner: str, f: ir.AnyField, doc: str, path: str, keep: set[str],
                   show: Optional[str]) -> AnyDescriptor:
        """One field's descriptor; `show` is the text the Info column puts before its value."""
        # A float's unit follows its value in the tree (see scalar_field).
        unit = unit_text(f.unit) if isinstance(f, (ir.ScalarField, ir.ArrayField)) and f.scalar.is_float else None
        if isinstance(f, ir.ScalarField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, f.label, doc, f.where, unit=f.unit,
                                    hex_base=bool(f.bits) and not f.scalar.signed)
            read = dict(path=path, show=show, field=key, size=f.scalar.size,
                        signed=f.scalar.signed and not f.scalar.is_float, float=f.scalar.is_float, unit=unit,
                        enum=self.enum_of(f.enum), label=f.label, keep=f.name if f.name in keep else None)
            if not f.bits:
                return self.read(Scalar(**read), key, f.scalar)
            bits = [self.owned_field(owner, f"{f.name}.{b}", "flag", label, f"Bit {i} of {f.label}: {label}.",
                                     f.where, bits=f.scalar.bits, mask=1 << i, parent=key)
                    for i, (b, label) in enumerate(zip(f.bits, f.bit_labels))]
            return self.read(Bits(**read, bits=bits), key, f.scalar)
        if isinstance(f, ir.ArrayField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, f.label, doc, f.where, unit=f.unit)
            return self.read(Array(path, show, key, f.scalar.size, f.scalar.signed and not f.scalar.is_float,
                                   f.scalar.is_float, unit, self.enum_of(f.enum), f.label, count=f.count),
                             key, f.scalar)
        if isinstance(f, ir.GroupField):
            key = self.owned_field(owner, f.name, "none", f.item_label, doc, f.where)
            item = self.plan.item_of(f)
            item_name = self.unique("layouts", f"{owner}_{f.item.name}")
            self.layouts.append(Layout(item_name, one_line(f.doc) or f"One entry of {f.name}.",
                                       self.descriptors(owner, item.layout.steps, keep)))
            return Group(path, show, key, f.item_label, f.count,
                         item.layout.fixed_size if item.fixed else None, item_name)
        if isinstance(f, ir.StringField):
            key = self.owned_field(owner, f.name, "text", f.label, doc, f.where)
            if f.length is None:
                return String(path, show, key)
            return PString(path, show, key, f.length.size, f.length.signed)
        if isinstance(f, ir.StringListField):
            key = self.owned_field(owner, f.name, "text", f.item_label, doc, f.where)
            return Strings(path, show, key, f.terminator)
        if isinstance(f, ir.BytesField):
            return Bytes(path, show, self.owned_field(owner, f.name, "bytes", f.label, doc, f.where))
        if isinstance(f, ir.SwitchField):
            default = Case(self.scalar_field(owner, f.name, f.default, None, f.label, doc, f.where, unit=f.unit),
                           f.default.size, unit_text(f.unit) if f.default.is_float else None)
            cases = []
            for code, s in sorted(f.cases.items()):
                key = self.scalar_field(owner, f"{f.name}_{s.name}", s, None, f.label,
                                        one_line(doc, f"(as {s.name}: {f.selector.name} is {code})"), f.where,
                                        unit=f.unit)
                cases.append(Case(key, s.size, unit_text(f.unit) if s.is_float else None, code))
            return Switch(path, show, f.selector.name, default, cases)
        if isinstance(f, ir.ValueListField):
            return self.values(owner, f, path, show)
        self.problems.append(f.where.problem(f"no Wireshark descriptor for a {type(f).__name__}"))
        return Bytes(path, show, None)

    def values(self, owner: str, f: ir.ValueListField, path: str, show: Optional[str]) -> Values:
        """The fields of typed values: one item per value, its type, and one field per data kind."""
        def add(name: str, shape: str, label: str, desc: str, **more) -> str:
            return self.owned_field(owner, name, shape, label, desc, f.where, **more)

        roles = [
            ("item", add(f.name, "none", f.item_label, describe(f))),
            ("type", add("type", "text", "Type", "Value type name, from the table of the stream's software version.",
                         ascii=True)),
            ("code", add("type_code", "integer", "Type code", "Value type byte.", scalar="uint8")),
            ("count", add("length", "integer", "Length", "Items of a LIST, or bytes of a string.", scalar="int16")),
            ("rows", add("rows", "integer", "Rows", "Rows of a MATRIX.", scalar="int16")),
            ("cols", add("columns", "integer", "Columns", "Columns of a MATRIX.", scalar="int16")),
            ("row", add("row", "none", "Row", "One row of a MATRIX.")),
        ]
        kinds = []
        for kind in sorted({lay.item.name for lay in self.p.value_layouts.values() if lay.item is not None}):
            kinds.append((kind, self.scalar_field(owner, f"value_{kind}", ir.SCALARS[kind], None, "Value",
                                                  f"A value of type {kind}.", f.where)))
        string = add("value_string", "text", "Value", "A string value.")
        return Values(path, show, f.terminator, f.item_label, roles, kinds, string)

    # ---- layouts and messages ----

    @staticmethod
    def keep_names(struct: ir.Struct) -> set[str]:
        out = set()
        for f in struct.fields:
            if f.present_if:
                out.add(f.present_if)
            if isinstance(f, ir.SwitchField):
                out.add(f.selector.name)
        return out

    def layout(self, owner: str, layout: plan.LayoutPlan, doc: str, show: dict) -> Layout:
        view = Layout(self.unique("layouts", owner), doc,
                      self.descriptors(owner, layout.steps, self.keep_names(layout.struct), show=show))
        self.layouts.append(view)
        return view

    def header_layout(self, name: str, owner: str, slots: list[plan.HeaderSlot], doc: str) -> str:
        """A message header (a fixed run of scalars), its fields named under `owner`."""
        unique = self.unique("layouts", name)
        self.layouts.append(Layout(unique, doc, [self.descriptor(owner, s.field, describe(s.field), s.field.name,
                                                                 set(), None) for s in slots]))
        return unique

    def check_summary(self, layout: model.Layout, descriptors: list[AnyDescriptor], show: dict) -> None:
        """The Info column reads a summary from the raw bytes (runtime/lua/packages/info.lua): each field must
        be one it can show, after fields it can step over (fixed ones, texts, version-gated parts)."""
        missing = set(show)

        def check(steps: list[AnyDescriptor]) -> bool:
            """False where the Info column stops: at a field it cannot step over, or when every
            summary field is found."""
            for d in steps:
                if isinstance(d, Cond):
                    if d.present_if is None:
                        if not check(d.fields):
                            return False
                        continue
                    return False
                if d.path in missing:
                    is_float = isinstance(d, Scalar) and d.float
                    if d.kind not in SHOWS or is_float:
                        self.problems.append(layout.where.problem(
                            f"the summary cannot show '{d.path}', a {'float' if is_float else d.kind} field"))
                    missing.discard(d.path)
                if not missing:
                    return False
                if d.kind not in STEPS_OVER and not (isinstance(d, Group) and d.count is not None
                                                     and d.size is not None):
                    return False
            return True

        check(descriptors)
        for name in sorted(missing):
            self.problems.append(layout.where.problem(
                f"the summary's field '{name}' comes after a field the Info column cannot step over"))

    def shown_layout(self, lay: model.Layout, choice_plan: plan.LayoutPlan) -> tuple[str, bool]:
        """The layout of a package or subtype, its summary fields marked `show` with the text put
        before each; and whether it has a summary."""
        show = {name: before for before, name in lay.summary}
        sent_by(lay.struct, lay.name, self.sent)
        view = self.layout(lay.name, choice_plan, node_text(lay), show)
        if show:
            self.check_summary(lay, view.descriptors, show)
        return view.name, bool(show)

    @staticmethod
    def forms(mp: plan.MessagePlan, parts: dict[int, Part]) -> list[Code]:
        """Per type code, the forms it takes (plan.Variant) and the plan's tables of them."""
        out = []
        for code, variants in sorted(mp.variants.items()):
            forms = [Form(parts[id(v.layout)], sorted(v.sizes) if v.sizes is not None else None, v.min_size, v.rep,
                          v.describe()) for v in variants]
            rows = mp.by_segment[code]
            single = len(variants) == 1 and not any(sf.nearest for sf in rows)
            segments = [-(sf.form + 1) if sf.nearest else sf.form + 1 for sf in rows]
            by_length = [(size, k + 1) for size, k in mp.by_length[code].items()]
            out.append(Code(code, single, forms, segments, by_length))
        return out

    @staticmethod
    def version_dependent(mp: plan.MessagePlan, lay: model.Layout) -> bool:
        """True when reading this layout, or choosing it, depends on the software version."""
        return lay.struct.needs_version or not lay.versions.unbounded or len(mp.variants[lay.code.value]) > 1

    def package_message(self, mp: plan.MessagePlan) -> Message:
        m = mp.message
        parts, parts_of = [], {}
        for c in mp.layouts:
            pk = c.layout
            label = layout_label(pk)
            layout, summary = self.shown_layout(pk, c.plan)
            part = Part(self.unique("parts", pk.name), pk.name, label, self.add_item(pk.name, label, one_line(pk.doc),
                                                                                    pk.where),
                        layout, summary=summary)
            parts_of[id(pk)] = part
            parts.append(part)
        codes = self.forms(mp, parts_of)
        for code in codes:
            code.summary = any(f.part.summary for f in code.forms)
        return Message("packages", m.code.value, words(m.name), node_text(m), f"{m.name}_packages", parts, codes,
                       names=self.strings[m.package_type.name],
                       needs_version=any(self.version_dependent(mp, c.layout) for c in mp.layouts),
                       length="package.length", type="package.type")

    def dispatch_message(self, mp: plan.MessagePlan) -> Message:
        m = mp.message
        sub_field = self.scalar_field(m.name, m.subtype.name, m.subtype.scalar, m.subtype.enum, m.subtype.label,
                                      one_line(m.subtype.doc, "Subtype of the message."), m.subtype.where)
        # The header then the subtype: shown as such when the subtype is unknown.
        header = self.header_layout(m.name, m.name, mp.header, f"Header and subtype of every {words(m.name).lower()}.")
        parts, parts_of = [], {}
        for c in mp.layouts:
            st = c.layout
            # The header fields of a subtype are filterable under its own name (ur.key.timestamp).
            sub_header = self.header_layout(f"{st.name}_header", st.name,
                                            [slot for slot in mp.header if not slot.is_subtype],
                                            f"Header of the {st.name} message.")
            body, _ = self.shown_layout(st, c.plan)
            name = self.unique("parts", st.name)
            label = layout_label(st)
            part = Part(name, st.name, label, self.add_item(st.name, label, one_line(st.doc), st.where), body,
                        header=sub_header, needs_version=self.version_dependent(mp, st))
            parts_of[id(st)] = part
            parts.append(part)
        return Message("subtypes", m.code.value, words(m.name), node_text(m), f"{m.name}_subtypes", parts,
                       self.forms(mp, parts_of), body_offset=mp.body_offset, names=self.strings[m.subtype_enum.name],
                       header=header, subtype_field=sub_field, subtype_label=m.subtype.label)

    def body_message(self, mp: plan.MessagePlan) -> Message:
        """A message that is one layout right after the message header (no subtype byte)."""
        m = mp.message
        (lay,) = {id(c.layout): c.layout for c in mp.layouts}.values()
        body, _ = self.shown_layout(lay, mp.layouts[0].plan)
        name = self.unique("parts", lay.name)
        label = layout_label(lay)
        part = Part(name, lay.name, label, self.add_item(lay.name, label, one_line(lay.doc), lay.where), body,
                    needs_version=self.version_dependent(mp, lay))
        return Message("body", m.code.value, label, node_text(m), f"{m.name}_forms", [part],
                       self.forms(mp, {id(lay): part}), body_offset=mp.body_offset)

    # ---- the protocol ----

    def value_tables(self) -> list[ValueTypes]:
        """The value-type codes of each software-version range, with how each type is laid out."""
        p = self.p
        tables = []
        for t in p.value_type.tables:
            kinds = []
            for v in t.values:
                lay = p.value_layouts[v.name]
                kinds.append(ValueKind(v.value, v.name, lay.layout, lay.item.name if lay.item else None,
                                       lay.item.size if lay.item else 0, lay.count if lay.layout == "array" else 1,
                                       lay.length.size if lay.length else 0))
            tables.append(ValueTypes(version_number(t.versions.low), version_number(t.versions.high),
                                     t.versions.describe(), kinds, p.value_min_size(t)))
        return tables

    def constants(self) -> dict:
        """Sizes and defaults the runtime reads."""
        p = self.p
        for what, h in (("message type", p.message_type), ("package type", p.package_type)):
            if h.scalar.size != 1:
                self.problems.append(h.where.problem(
                    f"the {what} must be one byte (the dissectors read it as one)"))
        return dict(title=p.title, header_size=p.header_size, length_size=p.message_length.scalar.size,
                    package_header_size=p.package_header_size, package_length_size=p.package_length.scalar.size,
                    max_message_length=p.max_message_length, max_value_depth=p.max_value_depth,
                    max_tree_items=MAX_TREE_ITEMS,
                    default_ports=",".join(str(x) for x in p.ports),
                    default_version=ir.version_text(p.default_version))

    def enums(self) -> list[EnumStrings]:
        """Every enum's value strings, one per version table (value types are named by the
        runtime, from the version's table)."""
        out = []
        for e in self.p.enums.values():
            if e is self.p.value_type:
                continue
            tables = [ValueStrings(None if t is e.tables[-1] else table_suffix(t), t.versions.describe(),
                                   version_number(t.versions.low), version_number(t.versions.high),
                                   [(v.value, v.name) for v in t.values]) for t in e.tables]
            self.strings[e.name] = EnumStrings(e.name, node_text(e), e.versioned, tables)
            out.append(self.strings[e.name])
        return out

    def version_reader(self) -> VersionReader:
        v = self.plan.version
        if any(f.fixed_size != 1 for f in (v.major, v.minor)):
            self.problems.append(v.layout.where.problem(
                "major and minor versions must be one byte each (the dissectors read them so)"))
        bugfix = None
        if v.bugfix is not None:
            s = v.bugfix.scalar
            if s.is_float or s.is_bool or s.size > 4:
                self.problems.append(v.bugfix.where.problem(
                    "the bugfix number must be an integer of at most 4 bytes (the dissectors read it so)"))
            bugfix = Bugfix(s.size, s.signed, version_number(v.bugfix.versions.low),
                            version_number(v.bugfix.versions.high))
        steps = [VersionStep(skip.fixed + (v.body_offset if i == 0 else 0), skip.prefix, skip.signed)
                 for i, skip in enumerate(v.skips)]
        return VersionReader(v.message_code, v.subtype_code, v.subtype_offset, steps,
                             v.tail + (0 if v.skips else v.body_offset), v.rest, bugfix)

    def build(self) -> Dissector:
        p = self.p
        enums = self.enums()
        self.header_field("length", p.message_length)
        self.header_field("type", p.message_type)
        self.header_field("package.length", p.package_length)
        self.header_field("package.type", p.package_type)
        messages = [(self.dispatch_message(mp) if mp.message.has_subtype else self.body_message(mp))
                    if mp.is_dispatch else self.package_message(mp) for mp in self.plan.messages]
        self.settle()
        # Which fields of a package a filter or column may ask for (TreeItem:referenced).
        for m in messages:
            for part in m.parts if m.kind == "packages" else []:
                part.refs = [f.key for f in sorted(self.fields, key=lambda f: f.key)
                             if f.key.startswith(part.key + ".")]
        version, constants = self.version_reader(), self.constants()
        if self.problems:
            raise SpecError(p.source, self.problems)
        return Dissector(p.title, one_line(p.doc), enums, self.fields, self.layouts, messages, version,
                         self.value_tables(), p.known_message_codes, self.strings[p.message_type_enum.name],
                         constants, [s.first for s in self.plan.segments if s.first], p.default_version)


def dissector(protocol_plan: plan.ProtocolPlan) -> Dissector:
    """The Wireshark model of the primary interface, which both dissectors render."""
    return _Builder(protocol_plan).build()
