"""The Lua target of an int32-record interface: generated/lua/<name>.lua, a Wireshark dissector
that loads on its own: the dissector model (dissector.py), then runtime/lua/common and
runtime/lua/int32_records joined in."""
from __future__ import annotations

from ... import ir
from ...emit import environment, runtime_section
from ...lang.lua import literal, text
from ...naming import column_name
from .dissector import Dissector, dissector
from .plan import RecordsPlan

DESC_INDENT = " " * 9          # a field's descriptions in the spec table, under its name

# The runtime joined after the tables, in order (runtime/lua/common, then this kind's own).
RUNTIME = ("common/register.lua", "common/guard.lua", "common/dotted_version.lua", "int32_records/dissect.lua")


def view(d: Dissector) -> dict:
    m = d.plan.model
    fields = [dict(name=literal(f.name), label=literal(f.label), scaled=literal(f.scaled), unit=literal(f.unit),
                   enum=literal(f.enum), desc=text(f.blurb, DESC_INDENT, len(DESC_INDENT) + len("desc = ")),
                   raw_desc=text(f.raw_blurb, DESC_INDENT, len(DESC_INDENT) + len("raw_desc = ")) if f.scaled else None)
              for f in d.fields]
    records = {}
    for r in d.records:
        layouts = [dict(describe=lay.describe, size=lay.size,
                        slots=[f"{{field = {literal(s.field.name)}, index = {s.index}, count = {s.count}, "
                               f"scale = {literal(s.scale)}, scale_name = {literal(s.scale_name or None)}}}"
                               for s in lay.slots])
                   for lay in r.layouts]
        records[r.direction] = dict(label=literal(r.label), starts=", ".join(map(str, r.starts)), layouts=layouts)
    enums = [dict(name=e.name, members=[f"[{v.value}] = {literal(v.name)}" for v in e.values]) for e in d.enums]
    return dict(name=literal(m.name), title=literal(m.title), doc=f"{m.title}: {m.doc}",
                short=literal(column_name(m.name)), ports=", ".join(map(str, m.ports)),
                default_release=ir.version_number(m.default_release),
                default_text=literal(ir.version_text(m.default_release)), fields=fields, records=records, enums=enums,
                filter_example=f"{m.name}.{d.plan.records[0].fields[-1].name}",
                runtime=[runtime_section("lua", name) for name in RUNTIME])


def render(p: RecordsPlan, banner: list[str]) -> dict[str, str]:
    text = environment("lua").get_template("int32_records/records.lua.j2").render(banner=banner, **view(dissector(p)))
    return {f"lua/{p.model.name}.lua": text}
