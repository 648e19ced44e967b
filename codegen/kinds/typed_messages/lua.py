"""Lua target of the typed-messages kind: the dissector model (dissector.py) -> plain data ->
templates/lua/typed_messages/ -> generated/lua/<name>.lua, one Wireshark protocol that loads on its
own, with the hand-written runtime of runtime/lua/common and runtime/lua/typed_messages joined after the tables."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import exchanges
from ...emit import environment, runtime_section
from ...lang import lua as lang
from .dissector import TYPE_CODES, Dissector, Exchanges, Field, Step, dissector, exchanges_of
from .plan import TypedPlan

# Wireshark field constructors by field type.
PROTOFIELD = {"bool": "bool", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double", "string": "string", "framenum": "framenum", "bytes": "bytes",
              "flag": "bool"}
# How the runtime reads a scalar from a TvbRange (runtime/lua/typed_messages/dissect.lua's READ table).
READER = {"bool": "uint", "int8": "int", "uint8": "uint", "int16": "int", "uint16": "uint", "int32": "int",
          "uint32": "uint", "int64": "int64", "uint64": "uint64", "float32": "float", "float64": "float"}
# The runtime joined after the tables, in order (runtime/lua/common, then this kind's own: the
# state first, then the dissector).
RUNTIME = ("common/register.lua", "common/guard.lua", "common/tcp_stream.lua", "common/bytes.lua",
           "common/pending.lua", "common/exchange.lua", "common/wanted.lua", "typed_messages/state.lua",
           "typed_messages/exchanges.lua", "typed_messages/dissect.lua")
TYPE_NAMES = "TYPE_NAMES"               # the Lua table of the type codes' letters


@dataclass
class FieldView:
    name: str
    call: str                # the ProtoField constructor
    label: str
    args: tuple[str, ...]    # what follows the label and comes before the description: base, value string
    prefix: str = ""
    abbrev: str = ""         # the filter name after the prefix
    doc: str = ""            # its description (codegen/blurbs.py)

    @property
    def line(self) -> str:
        """Its entry of the F table, the description wrapped under it when long."""
        call = ",\n".join([f"ProtoField.{self.call}({lang.string(f'{self.prefix}.{self.abbrev}')}",
                           lang.string(self.label), *self.args])
        return lang.field(call, lang.string(self.name), self.doc)


def _enum_table(name: str) -> str:
    return TYPE_NAMES if name == TYPE_CODES else "VS_" + name.upper()


def _args(f: Field) -> tuple[str, ...]:
    """Display, value string and mask as each ProtoField takes them, up to its description."""
    if f.type == "flag":
        return str(f.width), "nil", f"0x{f.mask:0{f.width // 4}x}"
    if f.is_float:
        return ()
    if f.type in ("string", "bytes"):
        return ("base.NONE",)
    if not f.is_integer:
        return "base.NONE", "nil", "nil"
    if f.unit:
        return "base.UNIT_STRING", f'{{ {lang.string(" " + f.unit)} }}', "nil"
    return "base.DEC", _enum_table(f.enum) if f.enum else "nil", "nil"


def _field(f: Field, prefix: str) -> FieldView:
    return FieldView(f.name, PROTOFIELD[f.type], f.label, _args(f), prefix, f.abbrev, f.doc)


def _unit(unit: Optional[str]) -> str:
    return lang.string(" " + unit) if unit else "nil"


def _step(s: Step) -> str:
    """A field's step, as a Lua table the runtime's STEP functions read."""
    name = lang.string(s.name)
    if s.kind == "names":
        return f'{{ kind = "names", name = {name}, separator = {lang.string(s.separator)} }}'
    if s.kind == "prefixed_text":
        return f'{{ kind = "prefixed_text", name = {name}, prefix = {s.size} }}'
    if s.kind == "scalar":
        return (f'{{ kind = "scalar", name = {name}, size = {s.size}, read = "{READER[s.scalar.name]}", '
                f'unit = {_unit(s.unit)} }}')
    return f'{{ kind = "{s.kind}", name = {name} }}'


def view(d: Dissector) -> dict:
    interface = d.plan.interface
    prefix = interface.name
    messages = [{"key": f"{m.message.code}:{1 if m.message.from_robot else 0}:{p}", "name": m.message.name,
                 "label": m.message.label, "letter": m.message.letter, "steps": [_step(s) for s in m.steps]}
                for m, p in d.dispatch]
    kinds = [{"name": k.name, "from_robot": k.data_from_robot, "requests": [r.name for r in k.requests],
              "replies": [r.name for r in k.replies]} for k in interface.recipe_kinds]
    return {
        "p": interface, "prefix": prefix,
        "ports": ",".join(str(p) for p in interface.ports),
        "enums": [{"var": _enum_table(e.name), "members": [(v.value, v.name) for v in e.values]} for e in d.enums],
        "header": [_field(f, prefix) for f in d.header], "own_values": [_field(f, prefix) for f in d.values],
        "fields": [_field(f, prefix) for f in d.fields],
        "messages": messages, "kinds": kinds,
        "value_types": [{"name": t.name, "size": t.size, "count": t.count, "read": READER[t.scalar.name],
                         "field": t.field} for t in d.value_types],
        "variables": [{"name": v.name, "unit": _unit(v.unit), "type": v.value_type} for v in d.variables],
        "flags": [(v.name, [f"F[{lang.string(f)}]" for f in v.flags]) for v in d.variables if v.flags],
        "items": [(v.name, lang.string(v.group), [f"{{ F[{lang.string(f)}], {_unit(u)} }}"
                                                  for f, u in zip(v.items, v.item_units)])
                  for v in d.variables if v.items],
        "refusals": [r.word for r in interface.refusals],
        "max_pending": interface.max_pending_setups,
        "codes": d.plan.codes,
        "undocumented": [{"code": u.code, "name": u.name, "label": u.label} for u in interface.undocumented],
        "runtime": [runtime_section("lua", n) for n in RUNTIME],
    }


def exchanges_view(x: Exchanges, prefix: str) -> dict:
    """The fields of the request/response links, and each pair's messages by name (pairs from 1)."""
    return {"exchange_fields": [exchanges.lua_field(f, prefix, f.name, "    ") for f in x.fields],
            "exchange_requests": [f"{name} = {i + 1}" for name, i in x.requests.items()],
            "exchange_replies": [f"{name} = {i + 1}" for name, i in x.replies.items()],
            "exchange_count": x.count, "exchange_max_pending": x.max_pending}


def render(planned: TypedPlan, banner: list[str]) -> dict[str, str]:
    env = environment("lua")
    env.filters["lua"] = lang.literal
    text = env.get_template("typed_messages/interface.lua.j2").render(
        banner=banner, **view(dissector(planned)), **exchanges_view(exchanges_of(planned), planned.interface.name))
    return {f"lua/{planned.interface.name}.lua": text}
