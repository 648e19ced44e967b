"""Named items of a vector and named bits of a number, as the kinds of fixed vectors (sized_packets,
typed_messages) read them from their spec: one rule for both.

A spec's `item_names:` section names the items of its vectors once ("joints": Base, Shoulder, ...;
"pose": X, Y, Z, RX, RY, RZ), and a vector says which it takes (`item_names: joints`). A vector
whose unit names several units ("m, rad") keeps that one unit for the metadata and gives its parts
to its items in equal runs, in order: a pose's first three items are in m, its last three in rad.
A bit list (`bits:`) names one flag per bit, from bit 0, each read as its name in words."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Optional

from .naming import words
from .resolve import Resolver

UNIT_SEPARATOR = ", "               # between the parts of a unit of several ("m/s, rad/s")
FLAG_WIDTHS = (8, 16, 32, 64)       # the widths a flag of a number without one is shown in


@dataclass(frozen=True)
class ItemSet:
    name: str
    doc: str
    labels: tuple[str, ...]


@dataclass(frozen=True)
class Item:
    """One item of a vector: what the tree calls it, its unit, and the spec's name of its set."""
    label: str
    unit: Optional[str]
    set_name: str = ""


@dataclass(frozen=True)
class Bit:
    name: str                       # filtered as <field's filter name>.<name>
    label: str                      # its name in words: "Is power on"
    position: int

    @property
    def mask(self) -> int:
        return 1 << self.position


def item_sets(r: Resolver, raw: Optional[dict]) -> dict[str, ItemSet]:
    out = {}
    for name, entry in (raw or {}).items():
        labels = tuple(entry["items"])
        if len(set(labels)) != len(labels):
            r.fail(["item_names", name, "items"], "names an item twice")
        out[name] = ItemSet(name, entry.get("doc", ""), labels)
    return out


def item_set_names(vectors: Iterable[tuple[Item, ...]]) -> dict[str, tuple[str, ...]]:
    """The item sets the given vectors take, by the spec's name of each: their item names in order."""
    return {v[0].set_name: tuple(i.label for i in v) for v in vectors if v}


def own_units(named: tuple[Item, ...]) -> tuple[Optional[str], ...]:
    """Each item's unit where a vector's items differ in unit (a pose: m, then rad), else none:
    each item then has the vector's own unit."""
    units = tuple(i.unit for i in named)
    return units if len(set(units)) > 1 else ()


def titled(label: str, unit: Optional[str]) -> str:
    """A vector's subtree text: "Actual tool pose (m, rad)"."""
    return label + (f" ({unit})" if unit else "")


def unit_parts(unit: Optional[str]) -> list[str]:
    return unit.split(UNIT_SEPARATOR) if unit else []


def items_of(r: Resolver, parts: list, sets: dict[str, ItemSet], name: Optional[str], count: int,
             unit: Optional[str]) -> tuple[Item, ...]:
    """A vector's items, named by the set it takes (none: unnamed), each with its part of the unit;
    a problem where the set does not fit the vector or a unit of several parts has no items to share."""
    units = unit_parts(unit)
    if name is None:
        if len(units) > 1:
            r.fail(parts + ["unit"], f"a unit of {len(units)} parts needs item_names to share it among the items")
        return ()
    item_set = sets.get(name)
    if item_set is None:
        r.fail(parts + ["item_names"], f"unknown item names '{name}' (name them under item_names:)")
        return ()
    if len(item_set.labels) != count:
        r.fail(parts + ["item_names"], f"'{name}' names {len(item_set.labels)} items, the vector has {count}")
        return ()
    if units and count % len(units):
        r.fail(parts + ["unit"], f"its {len(units)} unit parts cannot share {count} items equally")
        return ()
    run = count // len(units) if units else count
    return tuple(Item(label, units[i // run] if units else None, name) for i, label in enumerate(item_set.labels))


def bits_of(names: list[str]) -> tuple[Bit, ...]:
    return tuple(Bit(name, words(name), i) for i, name in enumerate(names))


def flag_width(bits: tuple[Bit, ...]) -> int:
    """The width flags of a number without one (a double that carries bits) are shown in: the
    narrowest that holds them."""
    highest = max(b.position for b in bits) + 1
    return next(w for w in FLAG_WIDTHS if w >= highest)
