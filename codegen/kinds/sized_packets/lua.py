"""Lua (Wireshark) target of a sized-packets interface: the dissector model (dissector.py) -> a
view model -> generated/lua/<name>.lua, a dissector that loads on its own beside urwire.lua. The
generated part declares the protocol, one field per spec field (filterable as <name>.<field>), the
enum name tables, the layouts' slots and the forms by size; the hand-written runtime
(runtime/lua/sized_packets, joined after it) frames the TCP stream by the size field and walks them."""
from __future__ import annotations

from ...comments import node_text
from ...emit import environment, runtime_section
from ...lang.lua import field, literal, string, text
from .dissector import Dissector, dissector, item_blurb
from .plan import SizedPlan

# The runtime joined after the tables, in order (runtime/lua/common, then this kind's own).
RUNTIME = ("common/register.lua", "common/guard.lua", "common/dotted_version.lua", "common/info_column.lua",
           "common/wanted.lua", "sized_packets/dissect.lua")


def view(d: Dissector) -> dict:
    protocol = d.plan.protocol
    name = protocol.name
    layouts = [dict(name=lay.name, label=lay.label, size=lay.size, versions=lay.versions,
                    slots=[f"{{{string(s.field.name)}, {s.offset}, {s.count}}}" for s in lay.slots])
               for lay in d.layouts]
    tables = [dict(ident=t.ident, entries=[f"[{value}] = {string(text)}" for value, text, _ in t.entries])
              for t in d.tables]
    forms = [(size, [dict(low=f.low, high=f.high, layout=f.layout + 1, versions=f.versions,
                          names=[f"{t.enum} = NAMES.{t.ident}" for t in f.tables if t is not None])
                     for f in row])
             for size, row in d.by_size]
    items = [(f.name, [_item(name, f, i) for i in f.items]) for f in d.fields if f.items]
    flags = [(f.name, [[string(f"{name}.{f.name}.{g.name}"), string(g.label), str(f.flag_width), "nil",
                        f"0x{g.mask:0{f.flag_width // 4}x}", string(g.comment)] for g in f.flags])
             for f in d.fields if f.flags]
    return dict(
        protocol=protocol, name=name, doc=node_text(protocol), fields=d.fields, size_field=d.size_field,
        size_line=field(f"ProtoField.int32({string(name + '.' + d.size_field.name)}, {string(d.size_field.label)}, "
                        "base.DEC, nil, nil", string(d.size_field.name), d.size_field.doc),
        plain_lines=[field(f"ProtoField.double({string(name + '.' + f.name)}, {string(f.label)}", string(f.name), f.doc)
                     for f in d.fields if not f.items],
        items=items, flags=flags,
        enum_of=[(f.name, f.enum) for f in d.fields if f.enum is not None],
        layouts=layouts, tables=tables, forms=forms, min_size=protocol.size_field_bytes + 8,
        same_size=protocol.same_size,
        runtime=[runtime_section("lua", part) for part in RUNTIME])


def render(planned: SizedPlan, banner: list[str]) -> dict[str, str]:
    env = environment("lua")
    env.filters["lua"] = literal
    text = env.get_template("sized_packets/dissector.lua.j2").render(
        banner=banner, **view(dissector(planned)))
    return {f"lua/{planned.protocol.name}.lua": text}


ITEM_INDENT = " " * 12          # a named item's description, under its ProtoField


def _item(name: str, f, item) -> str:
    """A named item's entry of ITEMS: its field, its description under it, and its unit."""
    unit = string(" " + item.unit) if item.unit else "nil"
    return (f"        {{ProtoField.double({string(name + '.' + f.name)}, {string(item.label)},\n"
            f"{ITEM_INDENT}{text(item_blurb(f, item), ITEM_INDENT, len(ITEM_INDENT))}), {unit}}},")
