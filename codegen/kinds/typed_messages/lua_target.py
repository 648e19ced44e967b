"""Lua target of the typed-messages kind: the IR -> plain data -> templates/lua/typed_messages/ ->
generated/lua/<name>.lua, one Wireshark protocol that loads on its own, with the hand-written runtime
of runtime/lua/<name>_*.lua joined after the tables.

Every message field and every variable is one filterable field `<name>.<field>`; a name that two of
them share must have one Wireshark type, and the generator refuses the spec otherwise."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir
from ...emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ...errors import Problem, SpecError
from ...targets.lua import lua_literal, lua_str
from ...wrap import spread
from . import model

# Wireshark field constructors by scalar.
PROTOFIELD = {"bool": "bool", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double"}
# How the runtime reads a scalar from a TvbRange (runtime/lua/rtde_dissect.lua's READ table).
READER = {"bool": "uint", "int8": "int", "uint8": "uint", "int16": "int", "uint16": "uint", "int32": "int",
          "uint32": "uint", "int64": "int64", "uint64": "uint64", "float32": "float", "float64": "float"}
# Header fields and the fields the runtime adds itself; no message field or variable may take these names.
OWN_FIELDS = ("length", "type", "kind", "recipe_frame", "direction", "protocol", "unknown_variable")
# The fields of a value a setup reply types otherwise than the variable table, one per scalar of the
# value types: `value_<scalar>` (rtde.value_float64), also the dissector's own.


def value_field(scalar: ir.Scalar) -> str:
    return f"value_{scalar.name}"


def value_label(scalar: ir.Scalar) -> str:
    return f"Value of the setup reply's type ({scalar.name})"


def value_fields(interface: model.Interface) -> list[ir.Scalar]:
    """The scalars of the value types, once each, in the spec's order."""
    return list({t.scalar.name: t.scalar for t in interface.value_types}.values())


@dataclass
class FieldView:
    name: str
    call: str                # the ProtoField constructor
    label: str
    args: str                # what follows the label: base and value string, or a description
    prefix: str = ""

    @property
    def line(self) -> str:
        """Its entry of the F table, wrapped under its first argument when long."""
        return spread([f'"{self.prefix}.{self.name}"', lua_str(self.label), self.args],
                      f'["{self.name}"] = ProtoField.{self.call}(', "),", "    ")


def _field_args(scalar: ir.Scalar, unit: Optional[str], vs: Optional[str]) -> str:
    if scalar.is_float:
        return "nil"
    if scalar.is_bool:
        return "base.NONE"
    if unit:
        return f'base.UNIT_STRING, {{ {lua_str(" " + unit)} }}'
    return f"base.DEC, {vs}" if vs else "base.DEC"


class _Fields:
    """Every filterable field once, with one type per name."""

    def __init__(self, prefix: str):
        self.prefix = prefix
        self.by_name: dict[str, FieldView] = {}
        self.problems: list[Problem] = []

    def add(self, name: str, call: str, label: str, args: str, where: ir.Where) -> None:
        if name in OWN_FIELDS or name.startswith("value_"):
            self.problems.append(Problem(where.path, f"lua target: {self.prefix}.{name} is the dissector's own field",
                                         where.line))
            return
        known = self.by_name.get(name)
        if known is not None:
            if known.call != call:
                self.problems.append(Problem(where.path, f"lua target: {self.prefix}.{name} would be both a "
                                                         f"{known.call} and a {call} field", where.line))
            return
        self.by_name[name] = FieldView(name, call, label, args, self.prefix)


def _unit(unit: Optional[str]) -> Optional[str]:
    return lua_str(" " + unit) if unit else "nil"


def _step(f, enums: dict) -> str:
    """A field's step, as a Lua table the runtime's STEP functions read."""
    if isinstance(f, model.NamesField):
        return f'{{ kind = "names", name = "{f.name}", separator = {lua_str(f.separator)} }}'
    if isinstance(f, model.RecipeValuesField):
        return f'{{ kind = "values", name = "{f.name}" }}'
    if isinstance(f, ir.StringField):
        if f.length is None:
            return f'{{ kind = "rest_text", name = "{f.name}" }}'
        return f'{{ kind = "prefixed_text", name = "{f.name}", prefix = {f.length.size} }}'
    return (f'{{ kind = "scalar", name = "{f.name}", size = {f.scalar.size}, read = "{READER[f.scalar.name]}", '
            f'unit = {_unit(f.unit)} }}')


def render(interface: model.Interface, banner: list[str]) -> dict[str, str]:
    prefix = interface.name
    fields = _Fields(prefix)
    enums = {e.name: "VS_" + e.name.upper() for e in interface.enums}
    fields.add("recipe_id", "uint8", "Recipe id", "base.DEC", ir.NOWHERE)
    for m in interface.messages:
        for f in m.fields:
            if isinstance(f, model.NamesField):
                fields.add(f.name, "string", f.label, "base.NONE", f.where)
            elif isinstance(f, model.RecipeValuesField):
                continue
            elif isinstance(f, ir.StringField):
                fields.add(f.name, "string", f.label, "base.NONE", f.where)
            else:
                vs = enums[f.enum.name] if f.enum is not None else None
                fields.add(f.name, PROTOFIELD[f.scalar.name], f.label, _field_args(f.scalar, f.unit, vs), f.where)
    for v in interface.variables:
        s = v.value_type.scalar
        fields.add(v.name, PROTOFIELD[s.name], v.label, _field_args(s, v.unit if not s.is_float else None, None),
                   v.where)
    if fields.problems:
        raise SpecError(interface.name, fields.problems)

    messages = []
    for m in interface.messages:
        steps = [_step(f, enums) for f in m.fields]
        for p in m.protocols:
            messages.append({"key": f"{m.code}:{1 if m.from_robot else 0}:{p}", "name": m.name, "label": m.label,
                             "letter": m.letter, "steps": steps})
    value_types = [{"name": t.name, "size": t.scalar.size, "count": t.count, "read": READER[t.scalar.name],
                    "field": value_field(t.scalar)} for t in interface.value_types]
    own_values = [{"name": value_field(s), "call": PROTOFIELD[s.name], "label": value_label(s),
                   "args": _field_args(s, None, None)} for s in value_fields(interface)]
    variables = [{"name": v.name, "unit": _unit(v.unit if v.value_type.scalar.is_float else None),
                  "type": v.value_type.name}
                 for v in {v.name: v for v in interface.variables}.values()]
    kinds = [{"name": k.name, "from_robot": k.data_from_robot, "requests": [r.name for r in k.requests],
              "replies": [r.name for r in k.replies]} for k in interface.recipe_kinds]
    codes = sorted({(m.code, m.letter) for m in interface.messages} | {(u.code, chr(u.code)) for u in interface.undocumented})
    view = {
        "banner": banner, "p": interface, "prefix": prefix,
        "ports": ",".join(str(p) for p in interface.ports),
        "enums": [{"var": enums[e.name], "members": [(v.value, v.name) for v in e.values]} for e in interface.enums],
        "fields": list(fields.by_name.values()),
        "messages": messages, "value_types": value_types, "variables": variables, "kinds": kinds,
        "own_values": own_values,
        "refusals": [r.word for r in interface.refusals],
        "max_pending": interface.max_pending_setups,
        "codes": codes,
        "undocumented": [{"code": u.code, "name": u.name, "label": u.label} for u in interface.undocumented],
        "runtime": [runtime_section("lua", n) for n in runtime_files(prefix)],
    }
    env = environment("lua")
    env.filters["lua"] = lua_literal
    text = env.get_template("typed_messages/interface.lua.j2").render(**view)
    return {f"lua/{prefix}.lua": text}


def runtime_files(prefix: str) -> list[str]:
    """The interface's own runtime files (runtime/lua/<name>_*.lua): the state first, then the dissector."""
    found = sorted(p.name for p in (RUNTIME_FOLDER / "lua").glob(f"{prefix}_*.lua"))
    return sorted(found, key=lambda n: (not n.endswith("_state.lua"), n))
