"""The plan every target renders: where each field of each layout sits, and which layout a
packet's size (and the stream's software version, when known) chooses.

A *form* is one layout as one of its version ranges sends it: the layout's fields, and the enum
tables of that range (a 1108-byte packet's joint modes read as CB3 codes for 3.5 to 3.9 and as
e-Series codes for 5.0 to 5.3). The spec's same_size rule becomes `by_size`: for each size, its
forms in the spec's order; a target takes the first whose range holds the stream's version, and
the last (the newest) when the version is unknown or none holds it."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from .model import SizedLayout, SizedProtocol


@dataclass
class Slot:
    """One field of a layout: its offset in the packet (size field included), and its place among
    the packet's doubles (`first`, `count`), which is how a target reading them all at once finds it."""

    field: ir.AnyField
    offset: int
    first: int
    count: int
    enum: Optional[ir.Enum]

    @property
    def is_array(self) -> bool:
        return isinstance(self.field, ir.ArrayField)


@dataclass
class LayoutPlan:
    index: int
    layout: SizedLayout
    slots: list[Slot]
    doubles: int                       # how many doubles follow the size field


@dataclass
class Form:
    layout: int                        # index into SizedPlan.layouts
    low: int                           # ir.version_number bounds of its range, inclusive
    high: int
    versions: ir.VersionRange
    tables: dict[str, ir.EnumTable]    # enum name -> its table for this range

    def describe(self) -> str:
        return self.versions.describe()


@dataclass
class SizedPlan:
    protocol: SizedProtocol
    layouts: list[LayoutPlan]
    forms: list[Form]
    by_size: dict[int, list[int]]      # size -> indices into forms, in the order the rule tries them

    @property
    def sizes(self) -> list[int]:
        return sorted(self.by_size)

    @property
    def enums(self) -> list[ir.Enum]:
        """The enums some layout's fields take their meanings from, in the spec's order."""
        used = {s.enum.name for lp in self.layouts for s in lp.slots if s.enum is not None}
        return [e for name, e in self.protocol.enums.items() if name in used]


_LOWEST = (0, 0, 0)
_HIGHEST = (999, 999, ir.BUGFIX_ANY)


def plan(protocol: SizedProtocol) -> SizedPlan:
    layouts = [_layout_plan(i, layout, protocol.size_field_bytes) for i, layout in enumerate(protocol.layouts)]
    forms: list[Form] = []
    by_size: dict[int, list[int]] = {}
    for lp in layouts:
        for rng in lp.layout.versions:
            low, high = rng.low or _LOWEST, rng.high or _HIGHEST
            tables = {e.name: e.table_for(low) for e in {s.enum.name: s.enum for s in lp.slots if s.enum}.values()}
            by_size.setdefault(lp.layout.size, []).append(len(forms))
            forms.append(Form(lp.index, ir.version_number(low), ir.version_number(high), rng, tables))
    return SizedPlan(protocol, layouts, forms, by_size)


def _layout_plan(index: int, layout: SizedLayout, size_bytes: int) -> LayoutPlan:
    slots: list[Slot] = []
    offset, first = size_bytes, 0
    for f in layout.fields:
        count = f.count if isinstance(f, ir.ArrayField) else 1
        slots.append(Slot(f, offset, first, count, getattr(f, "enum", None)))
        offset += f.fixed_size
        first += count
    return LayoutPlan(index, layout, slots, first)


def choose(planned: SizedPlan, size: int, version: Optional[ir.Version]) -> Optional[Form]:
    """The same_size rule, as every target applies it (kept here for the generator's own tests and
    the reference): the form a packet of this size is read as."""
    candidates = [planned.forms[i] for i in planned.by_size.get(size, [])]
    if not candidates:
        return None
    if version is not None:
        number = ir.version_number(version)
        for form in candidates:
            if form.low <= number <= form.high:
                return form
    return candidates[-1]
