"""The IR of a typed-messages interface (RTDE): messages per direction and protocol version, the
value types a recipe names, how setup exchanges make recipes, and the variable table.

Fields of a message body are the primary interface's `ir` fields (scalars, strings) plus the two
this kind adds: a separated list of names, and the values of a recipe."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Union

from ... import exchanges, ir
from ...items import Bit, Item
# A first version the sources do not give (UNKNOWN), and not in that generation at all (NONE): one
# spelling for every table with a column per series.
from ...series import NONE, UNKNOWN  # noqa: F401


@dataclass(frozen=True)
class ValueType:
    """An RTDE type name (VECTOR6D) and how one value of it is laid out: count scalars."""
    name: str
    scalar: ir.Scalar
    count: int
    doc: str = ""

    @property
    def size(self) -> int:
        return self.scalar.size * self.count


@dataclass
class NamesField:
    """Names or type names joined by a separator, running to the end of the message."""
    name: str
    label: str
    separator: str
    role: Optional[str] = None          # "variables" (a setup request) or "types" (its reply)
    doc: str = ""
    where: ir.Where = ir.NOWHERE
    unit: Optional[str] = None


@dataclass
class RecipeValuesField:
    """The values of a data package, laid out by the package's recipe; runs to the end."""
    name: str
    label: str
    doc: str = ""
    where: ir.Where = ir.NOWHERE
    unit: Optional[str] = None


BodyField = Union[ir.ScalarField, ir.StringField, NamesField, RecipeValuesField]

# Every message field and every variable is one filterable field `<protocol>.<name>` in the
# dissectors. These names are the dissectors' own: the header's fields, those the state adds, and
# value_<scalar> (a value a setup reply types otherwise than the variable table).
OWN_FIELDS = ("length", "type", "kind", "direction", "recipe_frame", "protocol", "unknown_variable", "variable")
# The request/response links' fields are the dissectors' own too (rtde.response_in, rtde.time).
LINK_FIELDS = exchanges.NAMES
VALUE_FIELD_PREFIX = "value_"
# Declared by the dissectors whether a message has it or not, with this type.
RECIPE_ID = ("recipe_id", "uint8")


def filter_type(f: Union[BodyField, "Variable"]) -> Optional[str]:
    """The type of the filterable field a message field or variable is: its scalar's name, or
    string; None for a recipe's values, which show under each variable's own field."""
    if isinstance(f, Variable):
        return f.value_type.scalar.name
    if isinstance(f, RecipeValuesField):
        return None
    if isinstance(f, (NamesField, ir.StringField)):
        return "string"
    return f.scalar.name


@dataclass
class Message:
    name: str
    code: int                           # the header's type byte: an ASCII letter
    from_robot: bool
    protocols: tuple[int, ...]          # the negotiated protocol versions that send this layout
    label: str
    doc: str
    field_note: str
    fields: list[BodyField]
    where: ir.Where = ir.NOWHERE

    @property
    def letter(self) -> str:
        return chr(self.code)

    @property
    def recipe_values(self) -> Optional[RecipeValuesField]:
        return next((f for f in self.fields if isinstance(f, RecipeValuesField)), None)

    def field_named(self, name: str) -> Optional[BodyField]:
        return next((f for f in self.fields if f.name == name), None)


@dataclass
class RawMessage:
    """A type code the spec names but no public document lays out: kept whole."""
    name: str
    code: int
    label: str
    doc: str


@dataclass
class RecipeKind:
    name: str                           # "outputs" or "inputs"
    data_from_robot: bool               # which direction's data packages follow these recipes
    requests: list[Message]
    replies: list[Message]
    doc: str


@dataclass
class Exchange:
    """Requests and the replies that answer them, in order (the spec's exchanges.pairs): what the
    dissectors link (rtde.response_in, rtde.response_to, rtde.time)."""
    requests: list[Message]
    replies: list[Message]


@dataclass
class Refusal:
    word: str                           # what a setup reply says in place of a type: NOT_FOUND
    doc: str




@dataclass
class Variable:
    name: str
    value_type: ValueType
    direction: str                      # "input" (the client writes it) or "output"
    label: str
    unit: Optional[str]
    doc: str
    since: dict[str, Union[ir.Version, str]]   # generation -> first version, UNKNOWN or NONE
    where: ir.Where = ir.NOWHERE
    enum: Optional[ir.Enum] = None      # the names of an integer's codes
    bits: tuple[Bit, ...] = ()          # the flags an integer carries
    items: tuple[Item, ...] = ()        # a vector's named items (codegen/items.py)

    def since_text(self, generation: str) -> str:
        first = self.since[generation]
        return first if isinstance(first, str) else ir.version_text(first)


@dataclass
class Generation:
    name: str
    label: str
    first: ir.Version                   # the first version RTDE has in this generation
    column_from: ir.Version             # the first software version read from its column of the table


@dataclass
class Interface:
    """Everything a target needs about one typed-messages interface."""
    name: str
    title: str
    doc: str
    ports: tuple[int, ...]
    protocol_versions: tuple[int, ...]
    default_protocol_version: int
    length: ir.Scalar
    type: ir.Scalar
    length_counts_header: bool
    enums: list[ir.Enum]
    value_types: list[ValueType]
    messages: list[Message]
    undocumented: list[RawMessage]
    recipe_kinds: list[RecipeKind]
    refusals: list[Refusal]
    generations: list[Generation]
    max_pending_setups: int = 1         # setup requests of one kind a connection keeps awaiting replies
    max_pending_version_requests: int = 1   # protocol version requests a connection keeps awaiting replies
    variables: list[Variable] = field(default_factory=list)
    exchanges: list[Exchange] = field(default_factory=list)
    max_pending_requests: int = 1       # requests of one exchange a connection keeps awaiting replies

    @property
    def header_size(self) -> int:
        return self.length.size + self.type.size

    @property
    def max_message_length(self) -> int:
        return self.length.max

    def recipe_kind_of_data(self, from_robot: bool) -> RecipeKind:
        return next(k for k in self.recipe_kinds if k.data_from_robot == from_robot)
