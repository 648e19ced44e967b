"""The Wireshark model of a sized-packets interface, computed once from the plan: the fields (one
double each, with label, unit and comment, and the size field; a vector with named items one per
item, filtered by the vector's name; a double that carries bits one flag per bit), the enum names
by version range, each layout's slots and the forms by size, as plain data that lua.py and epan.py
both render."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from ...blurbs import blurb, one_line, sentence
from ...comments import field_text, node_text, value_text
from ...items import Item, flag_width, titled
from .plan import SizedPlan

INFO_FIELD = "robot_mode"       # the field whose name the Info column shows beside the layout's


@dataclass(frozen=True)
class Flag:
    """One named bit of a double's whole value."""
    name: str                    # filtered as <protocol>.<field>.<name>
    label: str
    mask: int
    comment: str


@dataclass(frozen=True)
class Field:
    name: str                    # filtered as <protocol>.<name>
    label: str
    unit: Optional[str]
    comment: str
    enum: Optional[str]          # the enum whose codes it carries
    is_array: bool
    items: tuple[Item, ...] = ()         # a vector's named items: one field each, none for the vector
    flags: tuple[Flag, ...] = ()
    flag_width: int = 0                  # the bits its flags are shown in
    doc: str = ""                        # its description (codegen/blurbs.py)
    spec_doc: str = ""                   # the spec's doc alone, which its items' descriptions repeat

    @property
    def group(self) -> str:
        """An array's subtree text: its label and unit."""
        return titled(self.label, self.unit)


@dataclass(frozen=True)
class Enum:
    name: str
    doc: str


@dataclass(frozen=True)
class NameTable:
    """One enum's names for one version range of its codes."""
    enum: str
    index: int                   # its place among the enum's ranges
    entries: tuple[tuple[int, str, str], ...]   # value, name, comment

    @property
    def ident(self) -> str:
        return f"{self.enum}_{self.index}"


@dataclass(frozen=True)
class Slot:
    field: Field
    offset: int                  # in the packet, size field included
    count: int                   # doubles


@dataclass(frozen=True)
class Layout:
    name: str
    label: str
    size: int
    versions: str                # "3.10 to 3.15 or 5.4 to 5.9"
    slots: tuple[Slot, ...]      # packet order

    @property
    def info(self) -> Optional[Slot]:
        """Where it sends the field whose name the Info column shows."""
        return next((s for s in self.slots if s.field.name == INFO_FIELD), None)


@dataclass(frozen=True)
class Form:
    versions: str
    low: int                     # ir.version_number bounds, inclusive
    high: int
    layout: int                  # index into Dissector.layouts
    tables: tuple[Optional[NameTable], ...]   # per Dissector.enums: its names in this range, or None


@dataclass(frozen=True)
class Dissector:
    plan: SizedPlan
    size_field: Field
    fields: tuple[Field, ...]    # the catalogue, spec order
    enums: tuple[Enum, ...]      # the enums some layout's fields carry
    tables: tuple[NameTable, ...]
    layouts: tuple[Layout, ...]
    by_size: tuple[tuple[int, tuple[Form, ...]], ...]   # sizes ascending, each's forms in the order tried


def _field(f: ir.AnyField, items: tuple[Item, ...] = (), bits: tuple = ()) -> Field:
    enum = getattr(f, "enum", None)
    flags = tuple(Flag(b.name, b.label, b.mask, f"Bit {b.position} of {f.label}: {b.label}.") for b in bits)
    return Field(f.name, f.label, f.unit or None, field_text([f], versions=False), enum.name if enum else None,
                 isinstance(f, ir.ArrayField), items, flags, flag_width(bits) if bits else 0,
                 blurb(f.doc, f.label, f.unit, node_text(enum) if enum and not f.doc else ""), f.doc)


def item_blurb(f: Field, item: Item) -> str:
    """A named item's description: which item of which vector, then the vector's."""
    return blurb(one_line(f"{item.label} of {f.label}.", sentence(f.spec_doc)), f.label, item.unit)


def dissector(planned: SizedPlan) -> Dissector:
    protocol = planned.protocol
    fields = {f.name: _field(f, protocol.items.get(f.name, ()), protocol.bits.get(f.name, ()))
              for f in protocol.catalogue}
    enums = planned.enums
    tables = {(e.name, i): NameTable(e.name, i, tuple((v.value, v.name, value_text(v)) for v in table.values))
              for e in enums for i, table in enumerate(e.tables)}
    layouts = tuple(Layout(lp.layout.name, lp.layout.label, lp.layout.size, lp.layout.describe(),
                           tuple(Slot(fields[s.field.name], s.offset, s.count) for s in lp.slots))
                    for lp in planned.layouts)
    by_size = []
    for size in planned.sizes:
        forms = []
        for index in planned.by_size[size]:
            form = planned.forms[index]
            names = tuple(tables[(e.name, e.tables.index(form.tables[e.name]))] if e.name in form.tables else None
                          for e in enums)
            forms.append(Form(form.describe(), form.low, form.high, form.layout, names))
        by_size.append((size, tuple(forms)))
    return Dissector(planned, _field(protocol.size_field), tuple(fields.values()),
                     tuple(Enum(e.name, node_text(e) or e.name) for e in enums), tuple(tables.values()), layouts,
                     tuple(by_size))
