"""epan target of the typed-messages kind: the IR -> a view model -> templates/epan/typed_messages/ ->
generated/epan/packet-<name>.c, a native Wireshark dissector as an upstream epan/dissectors file reads,
with the hand-written runtime of runtime/epan/typed_messages/<name>_*.{h,c} joined in (each section naming its file).

It is the twin of the Lua target (lua_target.py): the same protocol, field abbrevs, names, types and
bases, preference and experts. Every decision is made here: each field's FT_ type, base, value string
and unit; each message layout's steps as table rows; what each message means to the conversation's
state (its role, read by runtime/epan/typed_messages/rtde_state.c as runtime/lua/rtde_state.lua reads the names)."""
from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Optional

from ... import ir
from ...emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ...errors import Problem, SpecError
from ...wrap import spread
from . import model
from .lua_target import OWN_FIELDS, value_field, value_fields, value_label

FIELD_TYPES = {"bool": "FT_BOOLEAN", "int8": "FT_INT8", "uint8": "FT_UINT8", "int16": "FT_INT16",
               "uint16": "FT_UINT16", "int32": "FT_INT32", "uint32": "FT_UINT32", "int64": "FT_INT64",
               "uint64": "FT_UINT64", "float32": "FT_FLOAT", "float64": "FT_DOUBLE"}
# Scalars the state may read (runtime/epan/typed_messages/rtde_dissect.c reads 1, 2 or 4 bytes as an integer), as
# the Lua runtime keeps the values it reads with uint() and int().
INTEGER_SCALARS = ("bool", "int8", "uint8", "int16", "uint16", "int32", "uint32")
# Units are the dissector's own unit_name_strings, with the space before the unit that the Lua
# field's unit text has: Wireshark 4.0 writes its own (units_volt: "V") right after the value ("24V").
# A double's unit is appended to its item's text instead (runtime/epan/typed_messages/rtde_dissect.c), as the Lua
# dissector does: 4.0 shows no unit string for FT_DOUBLE.
# Runtime files the dissector shares with others, joined before its own: tshark_fields.c tells a
# tshark -T fields run, where no item's label is printed. The upstream copy (Wireshark's own tree)
# reads no command line: tshark_fields_upstream.c tells no run, so every label is whole.
SHARED_CODE = ("tshark_fields.c",)
UPSTREAM_SHARED_CODE = ("tshark_fields_upstream.c",)
# The messages the state follows, by the names runtime/lua/rtde_state.lua follows too.
ROLE_OF_MESSAGE = {"request_protocol_version": "RTDE_ROLE_VERSION_REQUEST",
                   "request_protocol_version_reply": "RTDE_ROLE_VERSION_REPLY",
                   "start_reply": "RTDE_ROLE_START_REPLY"}
# The message fields the state reads, by name.
SLOT_OF_FIELD = {"protocol_version": "RTDE_SLOT_PROTOCOL_VERSION", "accepted": "RTDE_SLOT_ACCEPTED",
                 "recipe_id": "RTDE_SLOT_RECIPE_ID", "variables": "RTDE_SLOT_VARIABLES", "types": "RTDE_SLOT_TYPES"}


def c_string(text: Optional[str]) -> str:
    return "NULL" if text is None else json.dumps(text, ensure_ascii=False)


@dataclass
class FieldView:
    """One hf_register_info entry."""
    prefix: str                # the protocol's filter name: the hf array is hf_<prefix>
    name: str
    enum: str                  # its index into the hf array
    label: str
    abbrev: str
    ftype: str
    base: str
    strings: str               # VALS(...), UNS(&...) or NULL

    @property
    def line(self) -> str:
        return spread([f"&hf_{self.prefix}[{self.enum}]", "{ " + c_string(self.label),
                       c_string(self.abbrev), self.ftype, self.base, self.strings, "0x0", "NULL", "HFILL } }"],
                      "{ ", ",", "        ")


class _Fields:
    """Every filterable field once, with one type per name, as the Lua target keeps them."""

    def __init__(self, prefix: str, units: "_Units"):
        self.prefix = prefix
        self.units = units
        self.by_name: dict[str, FieldView] = {}
        self.problems: list[Problem] = []

    def enum_of(self, name: str) -> str:
        return f"{self.prefix.upper()}_HF_{name.upper()}"

    def add(self, name: str, label: str, ftype: str, base: str, strings: str = "NULL",
            where: ir.Where = ir.NOWHERE, own: bool = False) -> None:
        if (name in OWN_FIELDS or name.startswith("value_")) and not own:
            self.problems.append(Problem(where.path, f"epan target: {self.prefix}.{name} is the dissector's own field",
                                         where.line))
            return
        known = self.by_name.get(name)
        if known is not None:
            if known.ftype != ftype:
                self.problems.append(Problem(where.path, f"epan target: {self.prefix}.{name} would be both a "
                                                         f"{known.ftype} and a {ftype} field", where.line))
            return
        enum = self.enum_of(name)
        if any(f.enum == enum for f in self.by_name.values()):
            self.problems.append(Problem(where.path, f"epan target: {self.prefix}.{name} and another field are "
                                                     f"both {enum} in C", where.line))
            return
        self.by_name[name] = FieldView(self.prefix, name, enum, label, f"{self.prefix}.{name}", ftype, base, strings)

    def scalar(self, name: str, label: str, scalar: ir.Scalar, unit: Optional[str], vs: Optional[str],
               where: ir.Where) -> None:
        ftype = FIELD_TYPES[scalar.name]
        if scalar.is_bool:
            self.add(name, label, ftype, "BASE_NONE", where=where)
        elif scalar.is_float:
            self.add(name, label, ftype, "BASE_NONE", where=where)
        elif unit:
            self.add(name, label, ftype, "BASE_DEC|BASE_UNIT_STRING", f"&{self.units.of(unit)}", where)
        else:
            self.add(name, label, ftype, "BASE_DEC", f"VALS({vs})" if vs else "NULL", where)


class _Units:
    """The unit_name_string of each unit text."""

    def __init__(self, prefix: str):
        self.prefix = prefix
        self.own: dict[str, str] = {}

    def of(self, unit: str) -> str:
        if unit not in self.own:
            name = f"{self.prefix}_unit_" + re.sub(r"[^A-Za-z0-9]+", "_", unit).strip("_")
            while name in self.own.values():
                name += "_"
            self.own[unit] = name
        return self.own[unit]


def _step(f, fields: _Fields) -> str:
    """A layout step as a row of the runtime's rtde_step table."""
    slot = SLOT_OF_FIELD.get(f.name, "RTDE_SLOT_NONE")
    if isinstance(f, model.NamesField):
        kind, size, integer = "RTDE_STEP_NAMES", 0, False
    elif isinstance(f, model.RecipeValuesField):
        return f'{{ RTDE_STEP_VALUES, 0, 0, FALSE, RTDE_SLOT_NONE, "{f.name}", NULL }}'
    elif isinstance(f, ir.StringField):
        kind, size, integer = (("RTDE_STEP_REST_TEXT", 0, False) if f.length is None
                               else ("RTDE_STEP_PREFIXED_TEXT", f.length.size, False))
    else:
        kind, size, integer = "RTDE_STEP_SCALAR", f.scalar.size, f.scalar.name in INTEGER_SCALARS
    unit = c_string(" " + f.unit) if kind == "RTDE_STEP_SCALAR" and f.unit else "NULL"
    return (f'{{ {kind}, {fields.enum_of(f.name)}, {size}, {"TRUE" if integer else "FALSE"}, {slot}, '
            f'"{f.name}", {unit} }}')


def _role(m: model.Message, interface: model.Interface) -> tuple[str, int]:
    for index, kind in enumerate(interface.recipe_kinds):
        if any(r.name == m.name for r in kind.requests):
            return "RTDE_ROLE_SETUP_REQUEST", index
        if any(r.name == m.name for r in kind.replies):
            return "RTDE_ROLE_SETUP_REPLY", index
    if m.recipe_values is not None:
        return "RTDE_ROLE_DATA", -1
    return ROLE_OF_MESSAGE.get(m.name, "RTDE_ROLE_NONE"), -1


def render(interface: model.Interface, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """packet-<name>.c; `upstream`: the copy for Wireshark's tree, which reads no command line."""
    prefix = interface.name
    units = _Units(prefix)
    fields = _Fields(prefix, units)
    enums = {e.name: f"{prefix}_{e.name}_vals" for e in interface.enums}
    fields.add("length", "Size", "FT_UINT16", "BASE_DEC", own=True)
    fields.add("type", "Type", "FT_UINT8", "BASE_DEC", f"VALS({prefix}_type_vals)", own=True)
    fields.add("kind", "Message", "FT_STRING", "BASE_NONE", own=True)
    fields.add("direction", "Direction", "FT_STRING", "BASE_NONE", own=True)
    fields.add("recipe_frame", "Recipe set up in frame", "FT_FRAMENUM", "BASE_NONE", own=True)
    fields.add("protocol", "Protocol version in force", "FT_UINT8", "BASE_DEC", own=True)
    fields.add("unknown_variable", "Variable not in the table", "FT_BYTES", "BASE_NONE", own=True)
    for scalar in value_fields(interface):
        fields.add(value_field(scalar), value_label(scalar), FIELD_TYPES[scalar.name],
                   "BASE_DEC" if not (scalar.is_bool or scalar.is_float) else "BASE_NONE", own=True)
    fields.add("recipe_id", "Recipe id", "FT_UINT8", "BASE_DEC")
    for m in interface.messages:
        for f in m.fields:
            if isinstance(f, model.RecipeValuesField):
                continue
            if isinstance(f, (model.NamesField, ir.StringField)):
                fields.add(f.name, f.label, "FT_STRING", "BASE_NONE", where=f.where)
            else:
                fields.scalar(f.name, f.label, f.scalar, f.unit, enums[f.enum.name] if f.enum else None, f.where)
    for v in interface.variables:
        fields.scalar(v.name, v.label, v.value_type.scalar, v.unit, None, v.where)
    if fields.problems:
        raise SpecError(interface.name, fields.problems)

    layouts, steps, layout_of = [], [], {}
    for m in interface.messages:
        role, kind = _role(m, interface)
        first = m.fields[0].name if m.fields else None
        steps.append({"name": f"{prefix}_steps_{m.name}", "rows": [_step(f, fields) for f in m.fields]})
        for p in m.protocols:
            layouts.append(spread([
                c_string(m.name), c_string(m.label), role, str(kind),
                "TRUE" if role == "RTDE_ROLE_DATA" and first == "recipe_id" else "FALSE",
                f"{prefix}_steps_{m.name}" if m.fields else "NULL",
                f"G_N_ELEMENTS({prefix}_steps_{m.name})" if m.fields else "0"], "{ ", " },", "    "))
            layout_of.setdefault(m.code, {}).setdefault(1 if m.from_robot else 0, {})[p] = len(layouts)
    max_protocol = max(interface.protocol_versions)
    index = [{"code": code, "letter": chr(code),
              "rows": ["{ " + ", ".join(str(by_dir.get(d, {}).get(p, 0)) for p in range(max_protocol + 1)) + " }"
                       for d in (0, 1)]}
             for code, by_dir in sorted(layout_of.items())]
    codes = sorted({m.code for m in interface.messages} | {u.code for u in interface.undocumented})
    data_kind = {k.data_from_robot: i for i, k in enumerate(interface.recipe_kinds)}
    variables = sorted({v.name: v for v in interface.variables}.values(), key=lambda v: v.name.encode())
    view = {
        "banner": banner, "p": interface, "prefix": prefix,
        "ports": ",".join(str(port) for port in interface.ports),
        "fields": list(fields.by_name.values()),
        "type_names": [(code, chr(code)) for code in codes],
        "enums": [{"var": enums[e.name], "members": [(v.value, v.name) for v in e.values]} for e in interface.enums],
        "own_units": [{"var": var, "text": c_string(" " + unit)} for unit, var in units.own.items()],
        "value_types": [{"name": c_string(t.name), "size": t.scalar.size, "count": t.count,
                         "field": fields.enum_of(value_field(t.scalar))} for t in interface.value_types],
        "variables": [{"name": c_string(v.name), "field": fields.enum_of(v.name),
                       "unit": c_string(" " + v.unit) if v.unit and v.value_type.scalar.is_float else "NULL",
                       "type": [t.name for t in interface.value_types].index(v.value_type.name)}
                      for v in variables],
        "steps": [s for s in steps if s["rows"]],
        "layouts": layouts, "index": index, "max_protocol": max_protocol, "codes": codes,
        "undocumented": [{"code": u.code, "name": c_string(u.name), "label": c_string(u.label)}
                         for u in interface.undocumented],
        "data_kind": [data_kind[False], data_kind[True]],
        "n_kinds": len(interface.recipe_kinds),
        "refusals": [c_string(r.word) for r in interface.refusals],
        "runtime_types": _joined(prefix, ".h"),
        "runtime": [_shared(name) for name in (UPSTREAM_SHARED_CODE if upstream else SHARED_CODE)]
                   + _joined(prefix, ".c"),
    }
    text = environment("epan").get_template("typed_messages/packet.c.j2").render(**view)
    return {f"epan/packet-{prefix.replace('_', '-')}.c": text}


def _shared(name: str) -> str:
    return runtime_section("epan", f"common/{name}")


def _joined(prefix: str, suffix: str) -> list[str]:
    """The interface's runtime files with this suffix (runtime/epan/typed_messages/<name>_*), the
    state before the dissector that uses it."""
    names = sorted(p.name for p in (RUNTIME_FOLDER / "epan" / "typed_messages").glob(f"{prefix}_*{suffix}"))
    names.sort(key=lambda n: (not n.endswith("_state.c"), n))
    return [runtime_section("epan", f"typed_messages/{n}") for n in names]
