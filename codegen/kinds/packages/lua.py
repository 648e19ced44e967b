"""Lua target: the dissector model (dissector.py) -> templates/lua/packages/urwire.lua.j2 + runtime/lua/{common,packages},
one Wireshark dissector in one self-contained file.

The model decides every field, value string, descriptor and form; this module only spells them in
Lua: the ProtoField constructor and base of each field, and the tables' names (VS.<ENUM> value
strings, NAMES.<ENUM> names by version, L.<layout>, PART.<part>). The template writes each
descriptor kind and each ProtoField shape with a macro of its own. The code that walks the
descriptors is hand-written Lua in runtime/lua/packages (and runtime/lua/common), joined after the generated tables.
"""
from __future__ import annotations

import textwrap
from typing import Optional

from ... import ir
from ...emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ...lang.lua import field as lua_field, literal as lua_literal, string as lua_str, text as lua_text
from .dissector import EnumStrings, Field, ValueStrings, dissector

OUT = "lua/urwire.lua"

# The hand-written runtime, in the order it is joined: the files every kind's dissector shares
# (runtime/lua/common), then this kind's own (runtime/lua/packages). Each file is a chunk that
# receives (spec, rt): `spec` is the generated data, `rt` what earlier runtime files export.
COMMON = ("register.lua", "guard.lua", "tcp_stream.lua", "bytes.lua", "info_column.lua", "wanted.lua")
RUNTIME = ("declare.lua", "read_faults.lua", "versions.lua", "items.lua", "collector.lua", "walk.lua", "values.lua",
           "info.lua", "messages.lua", "wanted.lua", "carry.lua", "stream.lua", "framing.lua", "preferences.lua")

# ProtoField constructor per scalar (integers take base and value strings, floats do not).
PROTOFIELD = {"bool": "bool", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double"}


def value_strings(enum: EnumStrings, table: Optional[ValueStrings] = None) -> str:
    """VS.ROBOT_MODE, the newest table (the field's value string); VS.ROBOT_MODE_UpTo3_2 an older one."""
    table = table or enum.newest
    return f"VS.{enum.name.upper()}" + (f"_{table.suffix}" if table.suffix else "")


def names_by_version(enum: EnumStrings) -> str:
    """NAMES.VALUE_TYPE: an enum's tables by version, for an enum whose codes depend on it; else nil."""
    return f"NAMES.{enum.name.upper()}" if enum.versioned else "nil"


def protofield(f: Field) -> str:
    """The ProtoField constructor of a field of one scalar."""
    return PROTOFIELD[f.scalar]


def base(f: Field) -> str:
    """base.<this> of an integer or text field."""
    if f.shape == "text":
        return "ASCII" if f.ascii else "UNICODE"
    return "UNIT_STRING" if f.unit else "HEX" if f.hex else "DEC"


def strings(f: Field) -> str:
    """An integer field's value strings: its unit (base.UNIT_STRING), its enum's newest, or nil."""
    if f.unit:
        return "{ " + lua_str(f" {f.unit}") + " }"
    return value_strings(f.enum) if f.enum is not None else "nil"


FILTERS = {"lua": lua_literal, "lua_text": lua_text, "lua_field": lua_field, "value_strings": value_strings,
           "names_by_version": names_by_version, "protofield": protofield, "base": base, "strings": strings,
           "layout": lambda name: f"L.{name}", "part": lambda name: f"PART.{name}",
           "forms_table": str.upper, "version_text": ir.version_text}


def runtime() -> list[str]:
    """The runtime files in joining order, as joined (emit.runtime_section)."""
    folder = RUNTIME_FOLDER / "lua" / "packages"
    found = sorted(p.name for p in folder.glob("*.lua"))
    if sorted(RUNTIME) != found:
        raise ValueError(f"lua target: runtime files {found} differ from the joining order {list(RUNTIME)}")
    names = [f"common/{name}" for name in COMMON] + [f"packages/{name}" for name in RUNTIME]
    return [runtime_section("lua", name) for name in names]


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    env = environment("lua")
    env.filters.update(FILTERS)
    d = dissector(protocol_plan)
    segment_lines = textwrap.wrap(", ".join(lua_str(ir.version_text(v)) for v in d.segment_starts), 100)
    ctx = dict(banner=banner, model=d, segment_lines=segment_lines, runtime=runtime())
    return {OUT: env.get_template("packages/urwire.lua.j2").render(**ctx)}
