"""Lua (Wireshark) target of a sized-packets interface: the plan -> a view model ->
generated/lua/<name>.lua, a dissector that loads on its own beside urwire.lua. The generated part
declares the protocol, one field per spec field (filterable as <name>.<field>), the enum name
tables, the layouts' slots and the forms by size; the hand-written runtime
(runtime/lua/<name>_*.lua, joined after it) frames the TCP stream by the size field and walks them."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import field_text, node_text
from ...emit import environment, runtime_section
from .plan import SizedPlan

RUNTIME = ["dissect.lua"]   # runtime/lua/<name>_dissect.lua


@dataclass
class LuaField:
    name: str
    label: str
    unit: str
    comment: str


@dataclass
class LuaLayout:
    name: str
    label: str
    size: int
    versions: str
    slots: list[str]                 # '{"q_actual", 252, 6}'


@dataclass
class LuaTable:
    ident: str
    entries: list[str]               # '[7] = "RUNNING"' 


@dataclass
class LuaForm:
    low: int
    high: int
    layout: int                      # 1-based index into LAYOUTS
    versions: str
    names: list[str]                 # 'robot_mode = NAMES.robot_mode_1'


def render(planned: SizedPlan, banner: list[str]) -> dict[str, str]:
    protocol = planned.protocol
    name = protocol.name
    fields = [LuaField(f.name, f.label, f.unit or "", field_text([f], versions=False)) for f in protocol.catalogue]
    enum_of = [(f.name, f.enum.name) for f in protocol.catalogue if getattr(f, "enum", None) is not None]
    layouts = [LuaLayout(lp.layout.name, lp.layout.label, lp.layout.size, lp.layout.describe(),
                         [f'{{"{s.field.name}", {s.offset}, {s.count}}}' for s in lp.slots])
               for lp in planned.layouts]
    tables = []
    for e in planned.enums:
        for i, table in enumerate(e.tables):
            tables.append(LuaTable(f"{e.name}_{i}", [f'[{v.value}] = "{v.name}"' for v in table.values]))
    forms = []
    for size in planned.sizes:
        row = []
        for index in planned.by_size[size]:
            form = planned.forms[index]
            names = [f"{e.name} = NAMES.{e.name}_{e.tables.index(form.tables[e.name])}"
                     for e in planned.enums if e.name in form.tables]
            row.append(LuaForm(form.low, form.high, form.layout + 1, form.describe(), names))
        forms.append((size, row))
    runtime = [runtime_section("lua", f"{name}_{part}") for part in RUNTIME]
    text = environment("lua").get_template("sized_packets/dissector.lua.j2").render(
        banner=banner, protocol=protocol, name=name, doc=node_text(protocol), fields=fields, enum_of=enum_of,
        layouts=layouts, tables=tables, forms=forms, size_field=protocol.size_field,
        min_size=protocol.size_field_bytes + 8, same_size=protocol.same_size, runtime=runtime)
    return {f"lua/{name}.lua": text}
