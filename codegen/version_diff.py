"""What changes from one software version to another, as `python -m codegen diff` prints it for
every interface. Each kind says what one version sends, in the terms here (Form: the layout a
packet, record or type code takes; offered names: commands, variables), and the comparison is
the same for all. The lines read: "+ what: ..." (new in the later version), "- what: ..." (gone),
"~ what: ..." (changed, with its changes indented below)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Hashable, Iterable, Mapping

from . import ir


@dataclass
class Form:
    """What one packet, record or type code looks like for one software version."""

    where: str                         # "robot_state 12", "packet", "reverse_command"
    layout: str
    fields: list[tuple[str, str]]      # (name, wire type) in wire order
    sizes: str                         # "47", "76 or 88 (with euromap67_interface_installed)", "at least 13"


def field_type(f: ir.AnyField) -> str:
    """A field's wire type as the diff and the protocol reference write it: "uint8 (robot_mode)",
    "float64[6]", "string (length name_length)"."""
    if isinstance(f, ir.ScalarField):
        return f.scalar.name + (f" ({f.enum.name})" if f.enum else "")
    if isinstance(f, ir.ArrayField):
        return f"{f.scalar.name}[{f.count}]"
    if isinstance(f, ir.GroupField):
        return f"{f.item.name}[{f.count if f.count is not None else '...'}]"
    if isinstance(f, ir.StringField):
        return f"string (length {f.length.name})" if f.length else "string (to the end)"
    if isinstance(f, ir.SwitchField):
        return f"by {f.selector.name}"
    if isinstance(f, ir.ValueListField):
        return "values (to the end)"
    return "bytes (to the end)" if isinstance(f, ir.BytesField) else "strings (to the end)"


def form_changes(old: Mapping[Hashable, Form], new: Mapping[Hashable, Form]) -> list[str]:
    """The forms one version sends against another's, key by key in key order: a form gone or
    new, another layout or size, and the fields left out, added or of another type."""
    lines = []
    for key in sorted(set(old) | set(new)):
        x, y = old.get(key), new.get(key)
        if x is None:
            lines.append(f"+ {y.where}: {y.layout} ({y.sizes} bytes)")
            continue
        if y is None:
            lines.append(f"- {x.where}: {x.layout} ({x.sizes} bytes)")
            continue
        xf, yf = dict(x.fields), dict(y.fields)
        changes = [f"  - {n}: {t}" for n, t in x.fields if n not in yf]
        changes += [f"  + {n}: {t}" for n, t in y.fields if n not in xf]
        changes += [f"  ~ {n}: {xf[n]} -> {t}" for n, t in y.fields if n in xf and xf[n] != t]
        if x.layout != y.layout:      # another layout: its fields against the old one's, by name
            lines.append(f"~ {y.where}: {x.layout} ({x.sizes} bytes) becomes {y.layout} ({y.sizes} bytes)")
            lines += changes
            continue
        if x.sizes != y.sizes:
            changes.insert(0, f"  size {x.sizes} -> {y.sizes}")
        if changes:
            lines.append(f"~ {y.where}: {y.layout}")
            lines += changes
    return lines


def enum_changes(enums: Iterable[ir.Enum], a: ir.Version, b: ir.Version) -> list[str]:
    """The enum members whose meaning differs between software `a` and `b`, code by code."""
    lines = []
    for e in enums:
        xa, xb = _names(e, a), _names(e, b)
        if xa == xb:
            continue
        lines.append(f"~ enum {e.name}")
        for code in sorted(set(xa) | set(xb)):
            if xa.get(code) != xb.get(code):
                lines.append(f"  {code}: {xa.get(code, '(none)')} -> {xb.get(code, '(none)')}")
    return lines


def _names(e: ir.Enum, version: ir.Version) -> dict[int, str]:
    return {m.value: m.name for m in e.table_for(version).values}


def offered_changes(what: str, old: Mapping[str, str], new: Mapping[str, str]) -> list[str]:
    """Names a version offers (a dashboard command, an RTDE variable), each with what a reader
    should know of it ("" or "(first version not known)"), against another version's, in the
    order given: "+ command power on", "- variable payload_inertia"."""
    lines = [f"- {what} {name}{_note(old[name])}" for name in old if name not in new]
    lines += [f"+ {what} {name}{_note(note)}" for name, note in new.items() if name not in old]
    lines += [f"~ {what} {name}: {old[name] or 'offered'} -> {note or 'offered'}"
              for name, note in new.items() if name in old and old[name] != note]
    return lines


def _note(note: str) -> str:
    return f" {note}" if note else ""
