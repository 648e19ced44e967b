"""Decisions every target of an int32-record interface shares, made once over the model: the
public fields of each record (one per name), and its layouts along the release axis, each with
its size and the place of every field."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from .model import Int32Field, Record, RecordsProtocol


@dataclass(frozen=True)
class PublicField:
    """One name of a record: what its attribute, C member, JSON key and Wireshark field hold."""
    name: str
    label: str
    doc: str
    max_count: int                 # 1: one value; more: a list of up to that many
    scaled: bool
    unit: Optional[str]
    enum: Optional[ir.Enum]
    always: bool                   # sent in every release (else it is left out of a record without it)

    @property
    def is_list(self) -> bool:
        return self.max_count > 1


@dataclass(frozen=True)
class Slot:
    """A field in one layout: its public field, where its first int32 is, how many, its scale."""
    field: PublicField
    index: int
    count: int
    scale: Optional[int]
    scale_name: str


@dataclass(frozen=True)
class Layout:
    first: Optional[ir.Version]    # the first release that sends it; None: from the first
    next: Optional[ir.Version]     # where the next layout starts; None: the last
    slots: tuple[Slot, ...]
    size: int                      # int32 count

    def describe(self) -> str:
        high = None if self.next is None else _before(self.next)
        return ir.VersionRange(self.first, high).describe()


@dataclass(frozen=True)
class RecordPlan:
    record: Record
    fields: tuple[PublicField, ...]
    layouts: tuple[Layout, ...]
    starts: tuple[ir.Version, ...]           # of every layout but the first


@dataclass(frozen=True)
class RecordsPlan:
    model: RecordsProtocol
    records: tuple[RecordPlan, ...]


def _after(high: ir.Version) -> ir.Version:
    major, minor, bugfix = high
    return (major, minor + 1, 0) if bugfix == ir.BUGFIX_ANY else (major, minor, bugfix + 1)


def _before(low: ir.Version) -> ir.Version:
    major, minor, bugfix = low
    return (major, minor, bugfix - 1) if bugfix else (major, minor - 1, ir.BUGFIX_ANY) if minor else (major - 1, 999, ir.BUGFIX_ANY)


def _public(record: Record) -> tuple[PublicField, ...]:
    out: dict[str, PublicField] = {}
    for f in record.fields:
        same = [g for g in record.fields if g.name == f.name]
        if f.name not in out:
            always = any(g.versions.unbounded for g in same) or _covers(same)
            out[f.name] = PublicField(f.name, f.label, f.doc, max(g.count for g in same), f.scale is not None,
                                      f.unit, f.enum, always)
    return tuple(out.values())


def _covers(fields: list[Int32Field]) -> bool:
    """Whether the ranges of one name's entries leave no release out."""
    ranges = sorted((f.versions for f in fields), key=lambda r: r.low or (0, 0, 0))
    if ranges[0].low is not None:
        return False
    for a, b in zip(ranges, ranges[1:]):
        if a.high is None or b.low != _after(a.high):
            return False
    return ranges[-1].high is None


def _layouts(record: Record, public: dict[str, PublicField]) -> tuple[Layout, ...]:
    cuts = sorted({f.versions.low for f in record.fields if f.versions.low}
                  | {_after(f.versions.high) for f in record.fields if f.versions.high})
    firsts = [None] + cuts
    layouts = []
    for i, first in enumerate(firsts):
        at = first or (0, 0, 0)
        slots, index = [], 0
        for f in record.fields:
            if f.versions.contains(at):
                slots.append(Slot(public[f.name], index, f.count, f.scale, f.scale_name))
                index += f.count
        layouts.append(Layout(first, firsts[i + 1] if i + 1 < len(firsts) else None, tuple(slots), index))
    return tuple(layouts)


def plan(model: RecordsProtocol) -> RecordsPlan:
    records = []
    for record in model.records:
        fields = _public(record)
        layouts = _layouts(record, {f.name: f for f in fields})
        records.append(RecordPlan(record, fields, layouts, tuple(layout.first for layout in layouts[1:])))
    return RecordsPlan(model, tuple(records))
