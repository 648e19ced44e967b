"""Python target of the typed-messages kind: the plan -> a view model -> templates/python/typed_messages/
-> generated/python/urwire/generated/<name>.py, imported by the hand-written runtime
(python/urwire/rtde_records.py for the base classes, python/urwire/rtde.py for a connection).

The plan says how a message is read (runs of scalars, the fields between them); what is Python's
(each run's struct format, the enum conversions, the attributes' types) is decided here, and the
template only lays the strings out."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import field_text, value_text
from ...emit import environment
from ...items import Item, own_units
from ...lang.python import class_name, item_set_constant, item_set_constants, string, string_or_none
from ...view import one_line
from ...wrap import spread
from . import model
from .plan import MessagePlan, TypedPlan

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
    metadata = f'{{"label": {string(f.label)}, "unit": {string_or_none(f.unit or None)}}}'
    if isinstance(f, model.NamesField):
        return AttrView(f.name, "list[str]", "names", metadata, f.label + ".")
    if isinstance(f, model.RecipeValuesField):
        return AttrView(f.name, "Union[_r.Values, dict[str, Any]]", "values", metadata,
                        f.label + ": every one in recipe order, and by variable name (a Values; a dict when built).")
    doc = one_line(field_text([f], versions=False))
    if isinstance(f, ir.StringField):
        return AttrView(f.name, "str", "text", metadata, doc)
    if f.enum is not None:
        return AttrView(f.name, f"Union[{class_name(f.enum.name)}, int]", "int", metadata, doc)
    if f.scalar.is_bool:
        return AttrView(f.name, "Union[bool, int]", "bool", metadata, doc)
    if f.scalar.is_float:
        return AttrView(f.name, "float", "float", metadata, doc)
    return AttrView(f.name, "int", "int", metadata, doc)


def _steps(mp: MessagePlan) -> tuple[list[StepView], list[tuple[str, str]]]:
    """The plan's steps: each run one Struct, each prefixed text its prefix's Struct."""
    steps: list[StepView] = []
    structs: list[tuple[str, str]] = []
    for step in mp.steps:
        f = step.fields[0]
        if step.kind == "run":
            name = _struct_name(mp.message, len(structs))
            structs.append((name, ">" + "".join(STRUCT_CODES[g.scalar.name] for g in step.fields)))
            converts = tuple((g.name, class_name(g.enum.name) if g.enum else "_BOOL") for g in step.fields
                             if g.enum is not None or g.scalar.is_bool)
            steps.append(StepView("run", [g.name for g in step.fields], name, step.size, f.name, converts))
        elif step.kind == "prefixed_text":
            name = _struct_name(mp.message, len(structs))
            structs.append((name, ">" + STRUCT_CODES[f.length.name]))
            steps.append(StepView("prefixed_text", [f.name], name, path=f.name))
        elif step.kind == "names":
            steps.append(StepView("names", [f.name], separator=f.separator))
        else:
            steps.append(StepView(step.kind, [f.name]))
    return steps, structs


def _message(mp: MessagePlan) -> MessageView:
    m = mp.message
    steps, structs = _steps(mp)
    protocols = tuple_text([str(p) for p in m.protocols])
    doc = m.label + "." + (" " + m.doc if m.doc else "")
    return MessageView(class_name(m.name), m.name, m.code, m.letter, m.from_robot, protocols, m.label, doc,
                       [_attr(f, m) for f in m.fields], steps, structs)


def _enum(e: ir.Enum) -> dict:
    return {"cls": class_name(e.name), "doc": e.doc,
            "members": [{"name": v.name, "value": v.value, "doc": value_text(v)} for v in e.values]}


def _variable(v: model.Variable) -> dict:
    since = ", ".join(f"{string(g)}: {string(v.since_text(g))}" for g in v.since)
    return {"args": [string(v.name), string(v.value_type.name), string(v.direction),
                     string(v.label), string_or_none(v.unit or None), f"{{{since}}}", "COLUMNS"]
            + _item_args(v.items)}


def _item_args(named: tuple[Item, ...]) -> list[str]:
    if not named:
        return []
    units = own_units(named)
    args = [f"items={item_set_constant(named[0].set_name)}"]
    return args + [f"item_units={tuple_text([string(u) for u in units])}"] if units else args


def render(planned: TypedPlan, banner: list[str]) -> dict[str, str]:
    interface = planned.interface
    messages = [_message(mp) for mp in planned.messages]
    by_name = {m.name: m for m in messages}
    kinds = [{"name": k.name, "const": k.name.upper(), "from_robot": k.data_from_robot,
              "requests": tuple_text([by_name[r.name].cls for r in k.requests]),
              "replies": tuple_text([by_name[r.name].cls for r in k.replies])} for k in interface.recipe_kinds]
    dispatch = [{"code": mp.message.code, "letter": mp.message.letter, "from_robot": mp.message.from_robot,
                 "protocol": p, "cls": by_name[mp.message.name].cls} for mp, p in planned.dispatch]
    view = {
        "banner": banner,
        "p": interface,
        "ports": tuple_text([str(p) for p in interface.ports]),
        "protocol_versions": tuple_text([str(p) for p in interface.protocol_versions]),
        "max_pending": interface.max_pending_setups,
        "refusals": tuple_text([string(r.word) for r in interface.refusals]),
        "recipe_kinds": tuple_text([k.name.upper() for k in interface.recipe_kinds]),
        "header_format": ">" + STRUCT_CODES[interface.length.name] + STRUCT_CODES[interface.type.name],
        "enums": [_enum(e) for e in interface.enums],
        "item_sets": item_set_constants(v.items for v in interface.variables),
        "value_types": [{"name": t.name, "code": STRUCT_CODES[t.scalar.name], "count": t.count,
                         "kind": "bool" if t.scalar.is_bool else "float" if t.scalar.is_float else "int"}
                        for t in interface.value_types],
        "messages": messages,
        "columns": tuple_text([f"({string(g.name)}, {g.column_from!r})" for g in interface.generations]),
        "dispatch": dispatch,
        "undocumented": interface.undocumented,
        "kinds": kinds,
        "variables": [_variable(v) for v in interface.variables],
    }
    text = environment("python").get_template("typed_messages/interface.py.j2").render(**view)
    return {f"{PACKAGE}/{interface.name}.py": text}
