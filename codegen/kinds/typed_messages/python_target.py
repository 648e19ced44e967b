"""Python target of the typed-messages kind: the IR -> a view model -> templates/python/typed_messages/
-> generated/python/urwire/generated/<name>.py, imported by the hand-written runtime
(python/urwire/rtde_records.py for the base classes, python/urwire/rtde.py for a connection).

Every decision (struct formats, the step of each field, enum conversions) is made here; the
template only lays the strings out."""
from __future__ import annotations

import json
from dataclasses import dataclass

from ... import ir
from ...comments import field_text, value_text
from ...emit import environment
from ...lang.python import class_name as camel
from ...view import one_line
from ...wrap import spread
from . import model

PACKAGE = "python/urwire/generated"
STRUCT_CODES = {"bool": "B", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i",
                "uint32": "I", "int64": "q", "uint64": "Q", "float32": "f", "float64": "d"}


@dataclass
class AttrView:
    name: str
    annotation: str
    json_kind: str           # int | bool | float | enum | text | names | values
    metadata: str
    doc: str


@dataclass
class StepView:
    kind: str                # run | prefixed_text | rest_text | names | values
    names: list[str]         # the attributes it reads, in order
    struct: str = ""         # run: the module-level Struct; prefixed_text: the prefix's Struct
    size: int = 0
    path: str = ""           # the field named when bytes run short
    converts: tuple = ()     # run: (attribute, conversion) after unpacking: ("level", "MessageLevel")
    separator: str = ""

    @property
    def targets(self) -> str:
        """The left side of an unpacking: "a," or "a, b"."""
        return self.names[0] + "," if len(self.names) == 1 else ", ".join(self.names)

    @property
    def self_args(self) -> str:
        return ", ".join(f"self.{n}" for n in self.names)


@dataclass
class MessageView:
    cls: str
    name: str
    code: int
    letter: str
    from_robot: bool
    protocols: str
    label: str
    doc: str
    attrs: list[AttrView]
    steps: list[StepView]
    structs: list[tuple[str, str]]      # (module-level name, format)

    @property
    def ctor_args(self) -> str:
        return ", ".join(a.name for a in self.attrs)

    @property
    def json(self) -> str:
        """The class's JSON table, `    JSON: ClassVar[tuple] = (...)`, wrapped under its first entry."""
        entries = [f'("{a.name}", "{a.json_kind}", False)' for a in self.attrs]
        if len(entries) == 1:
            entries[0] += ","
        return spread(entries, "JSON: ClassVar[tuple] = (", ")", "    ")


def tuple_text(items: list[str]) -> str:
    """A Python tuple display: "()", "(a,)", "(a, b)"."""
    return "(" + items[0] + ",)" if len(items) == 1 else "(" + ", ".join(items) + ")"


def _struct_name(message: model.Message, index: int) -> str:
    return f"_{message.name.upper()}_{index}"


def _attr(f, message: model.Message) -> AttrView:
    unit = json.dumps(f.unit, ensure_ascii=False) if f.unit else "None"
    metadata = f'{{"label": {json.dumps(f.label, ensure_ascii=False)}, "unit": {unit}}}'
    if isinstance(f, model.NamesField):
        return AttrView(f.name, "list[str]", "names", metadata, f.label + ".")
    if isinstance(f, model.RecipeValuesField):
        return AttrView(f.name, "Union[_r.Values, dict[str, Any]]", "values", metadata,
                        f.label + ": every one in recipe order, and by variable name (a Values; a dict when built).")
    doc = one_line(field_text([f], versions=False))
    if isinstance(f, ir.StringField):
        return AttrView(f.name, "str", "text", metadata, doc)
    if f.enum is not None:
        return AttrView(f.name, f"Union[{camel(f.enum.name)}, int]", "int", metadata, doc)
    if f.scalar.is_bool:
        return AttrView(f.name, "Union[bool, int]", "bool", metadata, doc)
    if f.scalar.is_float:
        return AttrView(f.name, "float", "float", metadata, doc)
    return AttrView(f.name, "int", "int", metadata, doc)


def _steps(message: model.Message) -> tuple[list[StepView], list[tuple[str, str]]]:
    """Consecutive scalars become one Struct; every other field is a step of its own."""
    steps: list[StepView] = []
    structs: list[tuple[str, str]] = []
    run: list[ir.ScalarField] = []

    def close_run():
        if not run:
            return
        name = _struct_name(message, len(structs))
        structs.append((name, ">" + "".join(STRUCT_CODES[f.scalar.name] for f in run)))
        converts = tuple((f.name, camel(f.enum.name) if f.enum else "_BOOL") for f in run
                         if f.enum is not None or f.scalar.is_bool)
        steps.append(StepView("run", [f.name for f in run], name, sum(f.scalar.size for f in run),
                              run[0].name, converts))
        run.clear()

    for f in message.fields:
        if isinstance(f, ir.ScalarField):
            run.append(f)
            continue
        close_run()
        if isinstance(f, model.NamesField):
            steps.append(StepView("names", [f.name], separator=f.separator))
        elif isinstance(f, model.RecipeValuesField):
            steps.append(StepView("values", [f.name]))
        elif f.length is not None:
            name = _struct_name(message, len(structs))
            structs.append((name, ">" + STRUCT_CODES[f.length.name]))
            steps.append(StepView("prefixed_text", [f.name], name, path=f.name))
        else:
            steps.append(StepView("rest_text", [f.name]))
    close_run()
    return steps, structs


def _message(m: model.Message) -> MessageView:
    steps, structs = _steps(m)
    protocols = tuple_text([str(p) for p in m.protocols])
    doc = m.label + "." + (" " + m.doc if m.doc else "")
    return MessageView(camel(m.name), m.name, m.code, m.letter, m.from_robot, protocols, m.label, doc,
                       [_attr(f, m) for f in m.fields], steps, structs)


def _enum(e: ir.Enum) -> dict:
    return {"cls": camel(e.name), "doc": e.doc,
            "members": [{"name": v.name, "value": v.value, "doc": value_text(v)} for v in e.values]}


def _variable(v: model.Variable) -> dict:
    since = ", ".join(f'"{g}": "{v.since_text(g)}"' for g in v.since)
    unit = json.dumps(v.unit, ensure_ascii=False) if v.unit else "None"
    return {"args": [f'"{v.name}"', f'"{v.value_type.name}"', f'"{v.direction}"',
                     json.dumps(v.label, ensure_ascii=False), unit, f"{{{since}}}"]}


def render(interface: model.Interface, banner: list[str]) -> dict[str, str]:
    messages = [_message(m) for m in interface.messages]
    by_name = {m.name: m for m in messages}
    kinds = [{"name": k.name, "const": k.name.upper(), "from_robot": k.data_from_robot,
              "requests": tuple_text([by_name[r.name].cls for r in k.requests]),
              "replies": tuple_text([by_name[r.name].cls for r in k.replies])} for k in interface.recipe_kinds]
    dispatch = [{"code": m.code, "letter": m.letter, "from_robot": m.from_robot, "protocol": p,
                 "cls": camel(m.name)} for m in interface.messages for p in m.protocols]
    view = {
        "banner": banner,
        "p": interface,
        "ports": tuple_text([str(p) for p in interface.ports]),
        "protocol_versions": tuple_text([str(p) for p in interface.protocol_versions]),
        "max_pending": interface.max_pending_setups,
        "refusals": tuple_text([f'"{r.word}"' for r in interface.refusals]),
        "recipe_kinds": tuple_text([k.name.upper() for k in interface.recipe_kinds]),
        "header_format": ">" + STRUCT_CODES[interface.length.name] + STRUCT_CODES[interface.type.name],
        "enums": [_enum(e) for e in interface.enums],
        "value_types": [{"name": t.name, "code": STRUCT_CODES[t.scalar.name], "count": t.count,
                         "kind": "bool" if t.scalar.is_bool else "float" if t.scalar.is_float else "int"}
                        for t in interface.value_types],
        "messages": messages,
        "dispatch": dispatch,
        "undocumented": interface.undocumented,
        "kinds": kinds,
        "variables": [_variable(v) for v in interface.variables],
    }
    text = environment("python").get_template("typed_messages/interface.py.j2").render(**view)
    return {f"{PACKAGE}/{interface.name}.py": text}
