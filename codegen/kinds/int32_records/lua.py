"""The Lua target of an int32-record interface: generated/lua/<name>.lua, a Wireshark dissector
that loads on its own: the tables of the plan, then runtime/lua/int32_records.lua joined in."""
from __future__ import annotations

import json

from ... import ir
from ...emit import environment, runtime_section
from ...naming import column_name
from .model import FROM_ROBOT
from .plan import RecordsPlan


def _lua(value) -> str:
    if value is None:
        return "nil"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    return str(value)


def view(p: RecordsPlan) -> dict:
    m = p.model
    seen, fields = set(), []
    for r in p.records:
        for f in r.fields:
            if f.name in seen:
                continue
            seen.add(f.name)
            fields.append(dict(name=_lua(f.name), label=_lua(f.label), scaled=_lua(f.scaled), unit=_lua(f.unit),
                               enum=_lua(f.enum.name if f.enum else None)))
    records = {}
    for r in p.records:
        layouts = [dict(describe=lay.describe(), size=4 * lay.size,
                        slots=[f"{{field = {_lua(s.field.name)}, index = {s.index}, count = {s.count}, "
                               f"scale = {_lua(s.scale)}, scale_name = {_lua(s.scale_name or None)}}}"
                               for s in lay.slots])
                   for lay in r.layouts]
        records["from_robot" if r.record.direction == FROM_ROBOT else "to_robot"] = dict(
            label=_lua(r.record.label), starts=", ".join(str(ir.version_number(s)) for s in r.starts), layouts=layouts)
    enums = [dict(name=e.name, members=[f"[{v.value}] = {_lua(v.name)}" for v in e.values]) for e in m.enums.values()]
    return dict(name=_lua(m.name), title=_lua(m.title), doc=f"{m.title}: {m.doc}", short=_lua(column_name(m.name)),
                ports=", ".join(map(str, m.ports)), default_release=ir.version_number(m.default_release),
                default_text=_lua(ir.version_text(m.default_release)), fields=fields, records=records, enums=enums,
                filter_example=f"{m.name}.{p.records[0].fields[-1].name}",
                runtime=runtime_section("lua", "int32_records.lua"))


def render(p: RecordsPlan, banner: list[str]) -> dict[str, str]:
    text = environment("lua").get_template("int32_records/records.lua.j2").render(banner=banner, **view(p))
    return {f"lua/{p.model.name}.lua": text}
