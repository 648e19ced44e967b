"""epan target of the typed-messages kind: the dissector model (dissector.py) -> a view model ->
templates/epan/typed_messages/ ->
generated/epan/packet-<name>.c, a native Wireshark dissector as an upstream epan/dissectors file reads,
with the hand-written runtime of runtime/epan/<name>_*.{h,c} joined in (each section naming its file).

It is the twin of the Lua target (lua.py): both render one dissector model, so the protocol, fields,
labels, types and steps are the same. What is C's is decided here: each field's FT_ type, base and
value string, the unit strings, each message layout's steps as table rows, and what each message means
to the conversation's state (its role, read by runtime/epan/typed_messages/rtde_state.c as runtime/lua/typed_messages/state.lua
reads the names)."""
from __future__ import annotations

import re
from dataclasses import dataclass

from ... import exchanges
from ...emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ...epan_c import SHARED_HEADER, development_branch
from ...lang import c
from ...wrap import spread
from .dissector import TYPE_CODES, Dissector, Exchanges, Field, Message, Step, dissector, exchanges_of
from .plan import TypedPlan

FIELD_TYPES = {"bool": "FT_BOOLEAN", "int8": "FT_INT8", "uint8": "FT_UINT8", "int16": "FT_INT16",
               "uint16": "FT_UINT16", "int32": "FT_INT32", "uint32": "FT_UINT32", "int64": "FT_INT64",
               "uint64": "FT_UINT64", "float32": "FT_FLOAT", "float64": "FT_DOUBLE", "string": "FT_STRING",
               "framenum": "FT_FRAMENUM", "bytes": "FT_BYTES", "flag": "FT_BOOLEAN"}
# Scalars the state may read (runtime/epan/typed_messages/rtde_dissect.c reads 1, 2 or 4 bytes as an integer), as
# the Lua runtime keeps the values it reads with uint() and int().
INTEGER_SCALARS = ("bool", "int8", "uint8", "int16", "uint16", "int32", "uint32")
# Units are the dissector's own unit_name_strings, with the space before the unit that the Lua
# field's unit text has: Wireshark 4.0 writes its own (units_volt: "V") right after the value ("24V").
# A double's unit is appended to its item's text instead (runtime/epan/typed_messages/rtde_dissect.c), as the Lua
# dissector does: 4.0 shows no unit string for FT_DOUBLE.
# The runtime the dissector shares with others is not joined but called, from packet-ur-common.c
# (codegen/epan_c.py: the links of request/response tracking, and ur_tshark_fields_arguments(), which
# tells a tshark -T fields run, where no item's label is printed; the upstream copy reads no command
# line and tells no run, so every label is whole).
# The messages the state follows, by the names runtime/lua/typed_messages/state.lua follows too.
ROLE_OF_MESSAGE = {"request_protocol_version": "RTDE_ROLE_VERSION_REQUEST",
                   "request_protocol_version_reply": "RTDE_ROLE_VERSION_REPLY",
                   "start_reply": "RTDE_ROLE_START_REPLY"}
# The message fields the state reads, by name.
SLOT_OF_FIELD = {"protocol_version": "RTDE_SLOT_PROTOCOL_VERSION", "accepted": "RTDE_SLOT_ACCEPTED",
                 "recipe_id": "RTDE_SLOT_RECIPE_ID", "variables": "RTDE_SLOT_VARIABLES", "types": "RTDE_SLOT_TYPES"}


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
    mask: str = "0x0"
    blurb: str = ""            # its description (codegen/blurbs.py)

    @property
    def line(self) -> str:
        return spread([f"&hf_{self.prefix}[{self.enum}]", "{ " + c.string(self.label), c.string(self.abbrev),
                       self.ftype, self.base, self.strings, self.mask, c.string(self.blurb), "HFILL } }"],
                      "{ ", ",", "        ")


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


def _strings(f: Field, prefix: str, units: _Units) -> tuple[str, str]:
    """A field's base and value string."""
    if f.type == "flag":
        return str(f.width), "NULL"
    if not f.is_integer:
        return "BASE_NONE", "NULL"
    if f.unit:
        return "BASE_DEC|BASE_UNIT_STRING", f"&{units.of(f.unit)}"
    if f.enum:
        return "BASE_DEC", f"VALS({_vals(f.enum, prefix)})"
    return "BASE_DEC", "NULL"


def _vals(enum: str, prefix: str) -> str:
    return f"{prefix}_type_vals" if enum == TYPE_CODES else f"{prefix}_{enum}_vals"


def _hf(name: str, prefix: str) -> str:
    return f"{prefix.upper()}_HF_{re.sub('[^A-Z0-9]', '_', name.upper())}"


def _step(s: Step, prefix: str) -> str:
    """A layout step as a row of the runtime's rtde_step table."""
    if s.kind == "values":
        return f'{{ RTDE_STEP_VALUES, 0, 0, FALSE, RTDE_SLOT_NONE, {c.string(s.name)}, NULL }}'
    kind = {"names": "RTDE_STEP_NAMES", "rest_text": "RTDE_STEP_REST_TEXT",
            "prefixed_text": "RTDE_STEP_PREFIXED_TEXT", "scalar": "RTDE_STEP_SCALAR"}[s.kind]
    integer = s.kind == "scalar" and s.scalar.name in INTEGER_SCALARS
    unit = c.string(" " + s.unit) if s.kind == "scalar" and s.unit else "NULL"
    return (f'{{ {kind}, {_hf(s.name, prefix)}, {s.size}, {"TRUE" if integer else "FALSE"}, '
            f'{SLOT_OF_FIELD.get(s.name, "RTDE_SLOT_NONE")}, {c.string(s.name)}, {unit} }}')


def _role(m: Message) -> tuple[str, int]:
    mp = m.plan
    if mp.request_kind is not None:
        return "RTDE_ROLE_SETUP_REQUEST", mp.request_kind
    if mp.reply_kind is not None:
        return "RTDE_ROLE_SETUP_REPLY", mp.reply_kind
    if m.message.recipe_values is not None:
        return "RTDE_ROLE_DATA", -1
    return ROLE_OF_MESSAGE.get(m.message.name, "RTDE_ROLE_NONE"), -1


def view(d: Dissector, upstream: bool) -> dict:
    interface = d.plan.interface
    prefix = interface.name
    units = _Units(prefix)
    fields = []
    for f in d.all_fields:
        base, strings = _strings(f, prefix, units)
        fields.append(FieldView(prefix, f.name, _hf(f.name, prefix), f.label, f"{prefix}.{f.abbrev}",
                                FIELD_TYPES[f.type], base, strings,
                                f"0x{f.mask:0{f.width // 4}x}" if f.type == "flag" else "0x0", f.doc))
    layouts, steps, layout_of = [], [], {}
    for m in d.messages:
        steps.append({"name": f"{prefix}_steps_{m.message.name}", "rows": [_step(s, prefix) for s in m.steps]})
    for m, p in d.dispatch:
        role, kind = _role(m)
        name = m.message.name
        first = m.steps[0].name if m.steps else None
        layouts.append(spread([
            c.string(name), c.string(m.message.label), role, str(kind),
            "TRUE" if role == "RTDE_ROLE_DATA" and first == "recipe_id" else "FALSE",
            f"{prefix}_steps_{name}" if m.steps else "NULL",
            f"G_N_ELEMENTS({prefix}_steps_{name})" if m.steps else "0"], "{ ", " },", "    "))
        layout_of.setdefault(m.message.code, {}).setdefault(1 if m.message.from_robot else 0, {})[p] = len(layouts)
    max_protocol = max(interface.protocol_versions)
    index = [{"code": code, "letter": chr(code),
              "rows": ["{ " + ", ".join(str(by_dir.get(d, {}).get(p, 0)) for p in range(max_protocol + 1)) + " }"
                       for d in (0, 1)]}
             for code, by_dir in sorted(layout_of.items())]
    data_kind = {k.data_from_robot: i for i, k in enumerate(interface.recipe_kinds)}
    value_types = [t.name for t in d.value_types]
    return {
        "p": interface, "prefix": prefix,
        "ports": ",".join(str(port) for port in interface.ports),
        "fields": fields,
        "type_names": d.plan.codes,
        "enums": [{"var": _vals(e.name, prefix), "members": [(v.value, v.name) for v in e.values]} for e in d.enums],
        "own_units": [{"var": var, "text": c.string(" " + unit)} for unit, var in units.own.items()],
        "value_types": [{"name": c.string(t.name), "size": t.size, "count": t.count, "field": _hf(t.field, prefix)}
                        for t in d.value_types],
        "variables": [{"name": c.string(v.name), "field": _hf(v.items[0] if v.items else v.name, prefix),
                       "unit": c.string(" " + v.unit) if v.unit else "NULL", "type": value_types.index(v.value_type),
                       "n_flags": _flags_after(v, [f.name for f in d.all_fields]),
                       "group": c.string(v.group) if v.group else "NULL",
                       "units": _units_of(v, prefix) if any(v.item_units) else "NULL"}
                      for v in sorted(d.variables, key=lambda v: v.name.encode())],
        "item_units": [{"var": _units_of(v, prefix), "units": [c.string(" " + u) if u else "NULL" for u in v.item_units]}
                       for v in d.variables if any(v.item_units)],
        "steps": [s for s in steps if s["rows"]],
        "layouts": layouts, "index": index, "max_protocol": max_protocol,
        "codes": [code for code, _ in d.plan.codes],
        "undocumented": [{"code": u.code, "name": c.string(u.name), "label": c.string(u.label)}
                         for u in interface.undocumented],
        "data_kind": [data_kind[False], data_kind[True]],
        "n_kinds": len(interface.recipe_kinds),
        "refusals": [c.string(r.word) for r in interface.refusals],
        "runtime_types": _joined(prefix, ".h"),
        "shared_header": SHARED_HEADER,
        "runtime": _joined(prefix, ".c"),
    }


def render(planned: TypedPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """packet-<name>.c; `upstream`: the copy for Wireshark's tree, which reads no command line, in its
    development branch's style."""
    env = environment("epan")
    env.filters["c"] = c.string
    d = dissector(planned)
    text = env.get_template("typed_messages/packet.c.j2").render(
        banner=banner, **merged(view(d, upstream), exchanges_view(d, exchanges_of(planned))))
    return {f"epan/packet-{planned.interface.name.replace('_', '-')}.c":
            development_branch(text) if upstream else text}


def _flags_after(v, names: list[str]) -> int:
    """How many flag fields follow a variable's own in hf_rtde (the dissector model puts them there);
    a vector's named items' fields follow one another likewise."""
    if v.items:
        at = names.index(v.items[0])
        assert names[at:at + len(v.items)] == list(v.items), v.name
        return 0
    at = names.index(v.name)
    assert names[at + 1:at + 1 + len(v.flags)] == list(v.flags), v.name
    return len(v.flags)


def _units_of(v, prefix: str) -> str:
    """The array of a named vector's units, one per item."""
    return f"{prefix}_units_{v.name}"


def _joined(prefix: str, suffix: str) -> list[str]:
    """The interface's runtime files with this suffix (runtime/epan/typed_messages/<name>_*), the
    state first and the dissector, which uses the others, last."""
    names = sorted(p.name for p in (RUNTIME_FOLDER / "epan" / "typed_messages").glob(f"{prefix}_*{suffix}"))
    names.sort(key=lambda n: (n.endswith("_dissect.c"), not n.endswith("_state.c"), n))
    return [runtime_section("epan", f"typed_messages/{n}") for n in names]


# ---- request/response tracking (codegen/exchanges.py, runtime/epan/typed_messages/rtde_exchanges.c) ----

@dataclass
class ExchangeFieldView:
    """The hf_register_info entry of a link: a frame number of a request or reply, or a time."""
    enum: str
    line: str


def exchanges_view(d: Dissector, x: Exchanges) -> dict:
    """The links' fields (after the others in the hf array), each layout's role in the pairs in the
    order of rtde_layouts, and the pairs' sizes."""
    prefix = d.plan.interface.name
    fields = []
    for f in x.fields:
        ftype, display, strings = exchanges.epan_type(f)
        fields.append(ExchangeFieldView(_hf(f.name, prefix), spread(
            [f"&hf_{prefix}[{_hf(f.name, prefix)}]", "{ " + c.string(f.label), c.string(f"{prefix}.{f.name}"),
             ftype, display, strings, "0x0", c.string(f.doc), "HFILL } }"], "{ ", ",", "        ")))
    roles = []
    for m, _ in d.dispatch:
        pair, reply = x.role(m.message.name)
        roles.append(f"{{ {pair}, {'TRUE' if reply else 'FALSE'} }},   /* {m.message.name} */")
    return {"exchange_fields": fields, "exchange_roles": roles, "exchange_count": x.count,
            "exchange_max_pending": x.max_pending}


def merged(view_: dict, more: dict) -> dict:
    """The view with the links': their fields after the others."""
    return {**view_, **more, "fields": view_["fields"] + more["exchange_fields"]}
