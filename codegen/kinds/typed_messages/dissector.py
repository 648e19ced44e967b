"""The Wireshark model of a typed-messages interface, computed once from the plan: every field a
dissector declares (its filter name, label, type, unit and value names), each message's steps,
the variable table and the value types, as plain data that lua.py and epan.py both render.

Every message field and every variable is one filterable field `<name>.<field>`, first come first
kept (its label is the first one's); resolve.py has checked that each name has one type and is
none of the dissector's own (model.OWN_FIELDS, value_<scalar>)."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

from ... import exchanges, ir
from ...blurbs import blurb, one_line, sentence
from ...items import titled
from . import model
from .plan import MessagePlan, TypedPlan


@dataclass(frozen=True)
class Field:
    name: str                          # filtered as <protocol>.<name>, unless `filter` says otherwise
    label: str
    type: str                          # a scalar's name (uint8, float64), or string, framenum, bytes or flag
    unit: Optional[str] = None         # an integer's unit, shown after its value
    enum: Optional[str] = None         # the enum whose names an integer shows; TYPE_CODES: the type codes
    width: int = 0                     # a flag's: the bits of the integer it is one of
    mask: int = 0                      # a flag's bit
    filter: str = ""                   # a named item's: its vector's name, which filters every item
    doc: str = ""                      # its description (codegen/blurbs.py)

    @property
    def abbrev(self) -> str:
        """The filter name after <protocol>."""
        return self.filter or self.name

    @property
    def is_float(self) -> bool:
        return self.type in ("float32", "float64")

    @property
    def is_integer(self) -> bool:
        return self.type in ir.SCALARS and not self.is_float and self.type != "bool"


TYPE_CODES = "type"                    # Field.enum of the header's type: the letters of the type codes


@dataclass(frozen=True)
class Step:
    """How the dissector shows one field of a message."""
    kind: str                          # scalar | names | values | prefixed_text | rest_text
    name: str
    scalar: Optional[ir.Scalar] = None
    size: int = 0                      # a scalar's bytes; a prefixed text's prefix bytes
    separator: str = ""
    unit: Optional[str] = None         # what a scalar's item shows after its value


@dataclass(frozen=True)
class Message:
    plan: MessagePlan
    steps: tuple[Step, ...]

    @property
    def message(self) -> model.Message:
        return self.plan.message


@dataclass(frozen=True)
class Variable:
    """A row of the variable table: its field is the one named like it; its flags' fields are
    named <name>.<bit>, in bit order."""
    name: str
    value_type: str
    unit: Optional[str]                # a double's unit, shown after its value (integers' is their field's)
    flags: tuple[str, ...] = ()
    items: tuple[str, ...] = ()        # a vector's named items: their fields, in order (none for the vector)
    item_units: tuple[Optional[str], ...] = ()   # each double item's unit
    group: str = ""                    # a named vector's subtree text: its label and unit


@dataclass(frozen=True)
class ValueType:
    name: str
    scalar: ir.Scalar
    size: int                          # an item's bytes
    count: int
    field: str                         # the field a value of this type shows in when a reply retypes it


@dataclass(frozen=True)
class Dissector:
    plan: TypedPlan
    header: tuple[Field, ...]          # the header's fields and the dissector's own
    values: tuple[Field, ...]          # value_<scalar>: a value the setup reply types otherwise
    fields: tuple[Field, ...]          # the message fields and the variables, one per name
    enums: tuple[ir.Enum, ...]
    messages: tuple[Message, ...]      # spec order
    dispatch: tuple[tuple[Message, int], ...]   # each message in each protocol version it is sent in
    variables: tuple[Variable, ...]    # one per name, spec order
    value_types: tuple[ValueType, ...]

    @property
    def all_fields(self) -> tuple[Field, ...]:
        return self.header + self.values + self.fields


def value_field(scalar: ir.Scalar) -> str:
    return f"{model.VALUE_FIELD_PREFIX}{scalar.name}"


def _header() -> tuple[Field, ...]:
    """model.OWN_FIELDS, labelled and typed."""
    return (Field("length", "Size", "uint16", doc="Size of the message, its 3 header bytes included."),
            Field("type", "Type", "uint8", enum=TYPE_CODES, doc="Message type: an ASCII letter."),
            Field("kind", "Message", "string", doc="The message's name, by its type and direction."),
            Field("direction", "Direction", "string", doc="Whether the robot or the client sent the message."),
            Field("recipe_frame", "Recipe set up in frame", "framenum",
                  doc="The frame of the setup reply that laid out this data package's recipe."),
            Field("protocol", "Protocol version in force", "uint8",
                  doc="The protocol version the connection agreed on, or the one assumed."),
            Field("unknown_variable", "Variable not in the table", "bytes",
                  doc="The bytes of a variable the variable table does not name."),
            Field("variable", "Variable a setup reply types", "string",
                  doc="The variable of the setup request that a setup reply's type is for."))


def _scalar(name: str, label: str, scalar: ir.Scalar, unit: Optional[str], enum: Optional[ir.Enum],
            doc: str = "") -> Field:
    integer = not (scalar.is_float or scalar.is_bool)
    return Field(name, label, scalar.name, unit if integer else None, enum.name if enum and integer else None,
                 doc=blurb(doc, label, unit, enum.doc if enum and not doc else ""))


def item_field(variable: str, index: int) -> str:
    """The key of a named item's field: not a filter name (the item filters as its vector)."""
    return f"{variable}:{index}"


def _variable_fields(v: model.Variable) -> list[Field]:
    """A variable's field, then one per flag (a bit of the same bytes); a vector with named items
    one field per item instead, each filtered by the vector's name."""
    scalar = v.value_type.scalar
    sent = "Written by the client." if v.direction == "input" else "Sent by the robot."
    if v.items:
        return [replace(_scalar(item_field(v.name, k), i.label, scalar, i.unit, v.enum,
                                one_line(f"{i.label} of {v.label}.", sentence(v.doc), sent)), filter=v.name)
                for k, i in enumerate(v.items)]
    return [_scalar(v.name, v.label, scalar, v.unit, v.enum, one_line(sentence(v.doc) or sentence(v.label), sent))] + [
        Field(f"{v.name}.{b.name}", b.label, "flag", width=scalar.bits, mask=b.mask,
              doc=blurb("", b.label, meaning=f"Bit {b.position} of {v.name}"))
        for b in v.bits]


def _variable(v: model.Variable) -> Variable:
    double = v.value_type.scalar.is_float
    return Variable(v.name, v.value_type.name, v.unit if double else None, tuple(f"{v.name}.{b.name}" for b in v.bits),
                    tuple(item_field(v.name, k) for k in range(len(v.items))),
                    tuple(i.unit if double else None for i in v.items),
                    titled(v.label, v.unit) if v.items else "")


def _body_field(f) -> Optional[Field]:
    kind = model.filter_type(f)
    if kind is None:
        return None
    if kind == "string":
        return Field(f.name, f.label, kind, doc=blurb(f.doc, f.label, f.unit))
    return _scalar(f.name, f.label, f.scalar, f.unit, f.enum, f.doc)


def _step(f) -> Step:
    if isinstance(f, model.NamesField):
        return Step("names", f.name, separator=f.separator)
    if isinstance(f, model.RecipeValuesField):
        return Step("values", f.name)
    if isinstance(f, ir.StringField):
        return Step("rest_text", f.name) if f.length is None else Step("prefixed_text", f.name, size=f.length.size)
    return Step("scalar", f.name, f.scalar, f.scalar.size, unit=f.unit)


def dissector(planned: TypedPlan) -> Dissector:
    interface = planned.interface
    header = _header()
    values = tuple(Field(value_field(s), f"Value of the setup reply's type ({s.name})", s.name,
                         doc=f"A value of type {s.name}, which the setup reply gives otherwise than the table.")
                   for s in planned.value_scalars)
    fields: dict[str, Field] = {model.RECIPE_ID[0]: Field(model.RECIPE_ID[0], "Recipe id", model.RECIPE_ID[1],
                                                          doc="The recipe a data package or setup reply is for.")}
    for f in [_body_field(f) for m in interface.messages for f in m.fields] \
            + [g for v in interface.variables for g in _variable_fields(v)]:
        if f is not None:
            fields.setdefault(f.name, f)
    messages = tuple(Message(mp, tuple(_step(f) for f in mp.message.fields)) for mp in planned.messages)
    by_name = {m.message.name: m for m in messages}
    variables = tuple(_variable(v) for v in {v.name: v for v in interface.variables}.values())
    value_types = tuple(ValueType(t.name, t.scalar, t.scalar.size, t.count, value_field(t.scalar))
                        for t in interface.value_types)
    return Dissector(planned, header, values, tuple(fields.values()), tuple(interface.enums), messages,
                     tuple((by_name[mp.message.name], p) for mp, p in planned.dispatch), variables, value_types)


# ---- request/response tracking (codegen/exchanges.py) ----

@dataclass(frozen=True)
class Exchanges:
    """What the dissectors link: each message of a pair by name, as the request or reply of pair
    `index` (the spec's exchanges.pairs), the requests a connection keeps per pair, the fields."""
    requests: dict[str, int]
    replies: dict[str, int]
    count: int
    max_pending: int
    fields: tuple[exchanges.ExchangeField, ...] = exchanges.FIELDS

    def role(self, name: str) -> tuple[int, bool]:
        """The pair a message is in (-1: none) and whether it is the reply."""
        if name in self.replies:
            return self.replies[name], True
        return self.requests.get(name, -1), False


def exchanges_of(planned: TypedPlan) -> Exchanges:
    pairs = planned.interface.exchanges
    return Exchanges({m.name: i for i, e in enumerate(pairs) for m in e.requests},
                     {m.name: i for i, e in enumerate(pairs) for m in e.replies}, len(pairs),
                     planned.interface.max_pending_requests)
