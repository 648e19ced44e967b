"""The model of an interface of fixed packets chosen by size: the IR its resolver makes. Its
fields are the primary IR's own (ir.ScalarField, ir.ArrayField) and its enums ir.Enum, so that
labels, units, comments and version ranges mean the same in every interface."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...items import Bit, Item


@dataclass
class SizedLayout:
    """One layout: the fields after the size field, for the software versions that send it."""

    name: str
    label: str
    doc: str
    field_note: str
    size: int                        # the whole packet's, size field included
    versions: list[ir.VersionRange]  # every range that sends it, in the spec's order
    fields: list[ir.AnyField]
    where: ir.Where = ir.NOWHERE

    def describe(self) -> str:
        """"3.10 to 3.15 or 5.4 to 5.9"."""
        return " or ".join(r.describe() for r in self.versions)


@dataclass
class SizedProtocol:
    name: str
    title: str
    doc: str
    ports: list[int]
    max_message_size: int
    generations: list[tuple[str, ir.VersionRange]]
    size_field: ir.ScalarField       # the int32 that opens every packet
    same_size: str                   # the spec's words for how layouts of one size are told apart
    enums: dict[str, ir.Enum]
    catalogue: list[ir.AnyField]     # every field any layout sends, once, in the spec's order
    layouts: list[SizedLayout]
    items: dict[str, tuple[Item, ...]]     # a vector's named items by its name (codegen/items.py)
    bits: dict[str, tuple[Bit, ...]]       # the flags a double's whole value carries, by its name

    @property
    def size_field_bytes(self) -> int:
        return self.size_field.scalar.size
