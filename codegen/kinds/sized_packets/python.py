"""Python target of a sized-packets interface: the plan -> a view model -> one module,
generated/python/urwire/generated/<name>.py. A class per layout reads and writes all its doubles
with one precompiled struct.Struct; the forms table renders the spec's same_size rule. The
framing (sizes, unknown sizes, streams) is hand-written in python/urwire/realtime.py."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import field_text, node_text, value_text
from ...emit import environment
from ...items import Item
from ...lang.python import class_name, item_metadata, item_set_constants, string
from .plan import Form, LayoutPlan, SizedPlan

PACKAGE = "python/urwire/generated"


@dataclass
class PyAttr:
    name: str
    annotation: str
    doc: str
    json_kind: str
    metadata: list[str]                   # its entries, "key": value
    start: int                 # index of its first value in the struct's tuple
    stop: int                  # one past its last; None-like for a scalar is start + 1
    is_array: bool


@dataclass
class PyLayout:
    name: str
    class_name: str
    struct_name: str
    fmt: str
    label: str
    doc: str
    size: int
    attrs: list[PyAttr]


@dataclass
class PyTable:
    const: str
    entries: list[tuple[int, str, str]]    # value, name, comment


@dataclass
class PyEnum:
    class_name: str
    doc: str
    newest: PyTable
    tables: list[tuple[str, PyTable]]      # the versions it holds for, its table


@dataclass
class PyForm:
    low: int
    high: int
    class_name: str
    versions: str
    tables: list[str]                      # '"enum name": ITS_TABLE', the items of a dict display


def _metadata(f: ir.AnyField, count: int = 0, named: tuple[Item, ...] = ()) -> list[str]:
    """The entries of a field's metadata: the label and unit, and an array's count, so that a table
    can give each item a column before any packet is seen (dataset.py); a vector of named items
    names them as the tree does."""
    return [f'"label": {f.label!r}', f'"unit": {f.unit!r}'] + ([f'"count": {count}'] if count else []) \
        + item_metadata(named)


def _layout(lp: LayoutPlan, size_field: ir.ScalarField, named: dict[str, tuple[Item, ...]]) -> PyLayout:
    layout = lp.layout
    attrs = [PyAttr(size_field.name, "int", field_text([size_field], versions=False), "int",
                    _metadata(size_field), 0, 1, False)]
    for s in lp.slots:
        start = s.first + 1
        attrs.append(PyAttr(s.field.name, "tuple[float, ...]" if s.is_array else "float",
                            field_text([s.field], versions=False), "list:f64" if s.is_array else "f64",
                            _metadata(s.field, s.count if s.is_array else 0, named.get(s.field.name, ())), start, start + s.count, s.is_array))
    doc = f"{layout.label}: sent by software {layout.describe()}."
    if node_text(layout):
        doc += " " + node_text(layout)
    return PyLayout(layout.name, class_name(layout.name), f"_{layout.name.upper()}", f">i{lp.doubles}d",
                    layout.label, doc, layout.size, attrs)


def _table_const(enum: ir.Enum, index: int) -> str:
    return f"{enum.name.upper()}_NAMES" if len(enum.tables) == 1 else f"{enum.name.upper()}_NAMES_{index}"


def _enum(enum: ir.Enum) -> PyEnum:
    tables = []
    for i, table in enumerate(enum.tables):
        entries = [(v.value, v.name, value_text(v)) for v in table.values]
        tables.append((table.versions.describe(), PyTable(_table_const(enum, i), entries)))
    return PyEnum(class_name(enum.name), node_text(enum), tables[-1][1], tables)


def _form(planned: SizedPlan, form: Form) -> PyForm:
    names = {e.name: _table_const(e, e.tables.index(form.tables[e.name])) for e in planned.enums
             if e.name in form.tables}
    return PyForm(form.low, form.high, class_name(planned.layouts[form.layout].layout.name), form.describe(),
                  [f"{string(k)}: {v}" for k, v in names.items()])


def render(planned: SizedPlan, banner: list[str]) -> dict[str, str]:
    protocol = planned.protocol
    env = environment("python")
    text = env.get_template("sized_packets/module.py.j2").render(
        banner=banner,
        protocol=protocol,
        size_bytes=protocol.size_field_bytes,
        enums=[_enum(e) for e in planned.enums],
        item_sets=item_set_constants(protocol.items.values()),
        layouts=[_layout(lp, protocol.size_field, protocol.items) for lp in planned.layouts],
        by_size=[(size, [_form(planned, planned.forms[i]) for i in planned.by_size[size]]) for size in planned.sizes],
    )
    return {f"{PACKAGE}/{protocol.name}.py": text}
