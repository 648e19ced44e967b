"""The Wireshark model of an int32-record interface, computed once from the plan: its fields (one
per name over both records: label, unit, scale, enum), its enums, and each direction's record with
its layouts by driver release, as plain data that lua.py and epan.py both render."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from ...blurbs import blurb
from .model import FROM_ROBOT, TO_ROBOT
from .plan import RecordsPlan


@dataclass(frozen=True)
class Field:
    name: str                    # filtered as <protocol>.<name>; a scaled one's raw int32 as <name>_raw
    label: str
    unit: Optional[str]
    doc: str
    scaled: bool                 # shown as a double, its raw int32 beside it
    enum: Optional[str]          # the enum whose names its codes have

    @property
    def shown_label(self) -> str:
        """The label with the unit, as the tree shows the field: "Read timeout (ms)"."""
        return self.label + (f" ({self.unit})" if self.unit else "")

    @property
    def blurb(self) -> str:
        """Its description (codegen/blurbs.py)."""
        return blurb(self.doc, self.label, self.unit)

    @property
    def raw_blurb(self) -> str:
        """A scaled field's raw int32's description."""
        return f"{self.label} as sent: the int32 before the driver's scale is applied."

    @property
    def comment(self) -> str:
        return " ".join(t for t in (f"{self.shown_label}.", self.doc.strip()) if t)


@dataclass(frozen=True)
class Slot:
    field: Field
    index: int                   # of its first int32 in the record
    count: int
    scale: Optional[int]
    scale_name: str


@dataclass(frozen=True)
class Layout:
    describe: str                # the releases that send it
    size: int                    # bytes
    slots: tuple[Slot, ...]


@dataclass(frozen=True)
class Record:
    name: str
    direction: str               # TO_ROBOT or FROM_ROBOT
    label: str
    starts: tuple[int, ...]      # ir.version_number of every layout's first release but the first's
    layouts: tuple[Layout, ...]


@dataclass(frozen=True)
class Dissector:
    plan: RecordsPlan
    fields: tuple[Field, ...]    # records' order, then fields' order, one per name
    enums: tuple[ir.Enum, ...]
    to_robot: Optional[Record]
    from_robot: Optional[Record]

    @property
    def records(self) -> tuple[Record, ...]:
        return tuple(r for r in (self.to_robot, self.from_robot) if r is not None)


def dissector(planned: RecordsPlan) -> Dissector:
    fields: dict[str, Field] = {}
    for r in planned.records:
        for f in r.fields:
            fields.setdefault(f.name, Field(f.name, f.label, f.unit, f.doc, f.scaled, f.enum.name if f.enum else None))
    records = {}
    for r in planned.records:
        layouts = tuple(Layout(lay.describe(), 4 * lay.size,
                               tuple(Slot(fields[s.field.name], s.index, s.count, s.scale, s.scale_name)
                                     for s in lay.slots))
                        for lay in r.layouts)
        records[r.record.direction] = Record(r.record.name, r.record.direction, r.record.label,
                                             tuple(ir.version_number(s) for s in r.starts), layouts)
    return Dissector(planned, tuple(fields.values()), tuple(planned.model.enums.values()),
                     records.get(TO_ROBOT), records.get(FROM_ROBOT))
