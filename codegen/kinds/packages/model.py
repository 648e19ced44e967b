"""The primary interface's IR (spec/ur_primary.yaml): value layouts, laid-out sub-packages and
message subtypes, the messages that hold them and the protocol. Versions, scalars, enums, fields
and structs are every kind's (codegen/ir.py)."""
from __future__ import annotations

from dataclasses import dataclass, field as dc_field
from typing import Optional, Union

from ...ir import (NOWHERE, ALL_VERSIONS, Enum, EnumTable, EnumValue, Scalar, ScalarField, Struct, Version,
                   VersionRange, Where)


# ---- values of global variables -----------------------------------------------------------

@dataclass
class ValueLayout:
    type_name: str               # NONE, STRING, POSE, ...
    layout: str                  # empty | string | array | scalar | list | matrix
    length: Optional[Scalar]     # string length, list count, matrix rows and columns
    item: Optional[Scalar]       # scalar and array item
    count: int                   # array count
    doc: str
    where: Where = NOWHERE

    @property
    def min_size(self) -> int:
        """The fewest data bytes after the type byte: a string or LIST may be empty, a MATRIX
        of no items is its two counts."""
        if self.layout == "scalar":
            return self.item.size
        if self.layout == "array":
            return self.item.size * self.count
        if self.layout in ("string", "list"):
            return self.length.size
        if self.layout == "matrix":
            return 2 * self.length.size
        return 0


# ---- messages -----------------------------------------------------------------------------

@dataclass
class Layout:
    """A laid-out sub-package or message subtype."""

    name: str
    code: EnumValue
    doc: str
    field_note: str
    struct: Struct
    sets_version: Optional[tuple[str, str, Optional[str]]] = None   # (major, minor, bugfix field)
    summary: list[tuple[str, str]] = dc_field(default_factory=list)  # (text before, field name)
    where: Where = NOWHERE
    versions: VersionRange = ALL_VERSIONS     # the software versions that send this layout
    inferred: bool = False    # its fields are read from real bytes, not from a document
    label: str = ""           # what people call it, where its name in words would not do ("HMC")

    @property
    def marks(self) -> list[str]:
        """What every target shows after the layout's name: "undocumented" for a code no document
        lays out, "inferred" when its fields are a reading of real bytes."""
        return [mark for mark, on in (("undocumented", self.code.undocumented), ("inferred", self.inferred)) if on]


@dataclass
class HeaderField:
    scalar: Scalar
    enum: Optional[Enum]
    doc: str
    where: Where = NOWHERE
    label: str = ""


@dataclass
class PackageListMessage:
    """A message made of length-framed sub-packages (robot state)."""

    name: str
    code: EnumValue
    doc: str
    field_note: str
    packages: list[Layout]
    package_type: Enum
    where: Where = NOWHERE

    @property
    def unlaid_codes(self) -> list[EnumValue]:
        """Codes the spec names but does not lay out: kept raw, never an error."""
        laid = {p.code.value for p in self.packages}
        return [v for v in self.package_type.values if v.value not in laid]


@dataclass
class DispatchMessage:
    """A message with a common header and then a subtype byte choosing the layout; or, with no
    subtype (a body message), one layout right after the message header, its code the message
    type's own."""

    name: str
    code: EnumValue
    doc: str
    field_note: str
    header: Struct
    subtype: Optional[ScalarField]
    subtypes: list[Layout]
    where: Where = NOWHERE
    message_types: Optional[Enum] = None   # a body message: the enum its one code is of

    @property
    def has_subtype(self) -> bool:
        return self.subtype is not None

    @property
    def subtype_enum(self) -> Enum:
        """The enum the layouts' codes come from: the subtype's, or the message type's."""
        if self.subtype is None:
            assert self.message_types is not None
            return self.message_types
        assert self.subtype.enum is not None
        return self.subtype.enum

    @property
    def unlaid_codes(self) -> list[EnumValue]:
        if self.subtype is None:
            return []
        laid = {s.code.value for s in self.subtypes}
        return [v for v in self.subtype_enum.values if v.value not in laid]

    @property
    def header_size(self) -> int:
        assert self.header.fixed_size is not None
        return self.header.fixed_size + (self.subtype.scalar.size if self.subtype else 0)


Message = Union[PackageListMessage, DispatchMessage]


@dataclass
class Protocol:
    name: str
    title: str
    doc: str
    ports: list[int]
    max_message_length: int
    max_value_depth: int
    documented_versions: list[Version]
    default_version: Version
    enums: dict[str, Enum]
    value_layouts: dict[str, ValueLayout]
    message_length: HeaderField
    message_type: HeaderField
    package_length: HeaderField
    package_type: HeaderField
    messages: list[Message]
    source: str = "<spec>"           # the spec file, for problems found after resolving
    generations: list[tuple[str, VersionRange]] = dc_field(default_factory=list)  # released series
    robot_buffer: Optional[int] = None  # a framer buffer that holds every message real robots send

    @property
    def message_type_enum(self) -> Enum:
        assert self.message_type.enum is not None
        return self.message_type.enum

    @property
    def header_size(self) -> int:
        return self.message_length.scalar.size + self.message_type.scalar.size

    @property
    def package_header_size(self) -> int:
        return self.package_length.scalar.size + self.package_type.scalar.size

    @property
    def known_message_codes(self) -> list[int]:
        """Every message type the spec names: the codes a plausible header may carry."""
        return sorted(v.value for v in self.message_type_enum.values)

    @property
    def unlaid_message_codes(self) -> list[EnumValue]:
        laid = {m.code.value for m in self.messages}
        return [v for v in self.message_type_enum.values if v.value not in laid]

    @property
    def value_type(self) -> Enum:
        return self.enums["value_type"]

    def value_min_size(self, table: EnumTable) -> int:
        """The fewest bytes one value of a value-type table takes: its type byte and the
        smallest data. Every LIST or MATRIX item takes at least this much, so a count whose
        items cannot fit in the bytes left is an error before any item is read."""
        return self.value_type.scalar.size + min(self.value_layouts[v.name].min_size for v in table.values)

    def all_layouts(self) -> list[Layout]:
        out: list[Layout] = []
        for m in self.messages:
            out.extend(m.packages if isinstance(m, PackageListMessage) else m.subtypes)
        return out
