"""The dataset's columns (dataset.py): one schema per interface and kind, the same for every
software version, read from the generated classes.

A kind's columns are every field of any layout of it: the generated class of a primary kind holds
the union of its layouts (a version's missing fields being None), and the real-time `state` takes
the fields of every layout, oldest first. Fixed-count lists and groups take a column per item (the
count is in the field's metadata: `q_actual_0` ... `q_actual_5`, a group's name before it where a
kind has two); lists of a count only a record knows, name lists and global-variable values take
their canonical JSON text. Each column reads its values from a batch of records at a time.
"""
from __future__ import annotations

import dataclasses
import inspect
import json
import operator
from typing import Any, Callable, NamedTuple

from ..canonical import member_text, shown_text, to_dict, to_json_line
from ..generated import messages, ur_realtime
# pyarrow, an optional extra (urwire[parquet]), is imported by the function that makes the schema.

PRIMARY = "ur"
REALTIME = "ur_realtime"
REALTIME_STATE = "state"
LEAD = ("capture", "capture_file", "position", "capture_time", "conversation")
ERROR_KINDS = ("errors", "unknown")
ROBOT_STATE = "robot_state"


class Part(NamedTuple):
    """Rows of one kind, of one robot on one day, in the kind's schema (`dataset_schema`)."""

    interface: str
    kind: str
    robot: str
    date: str           # YYYY-MM-DD
    table: Any          # pyarrow.Table


_ARROW = {"int": "int64", "enum": "int64", "uint64": "uint64", "bool": "bool_", "f32": "float32",
          "f64": "float64", "text": "string", "hex": "binary", "texts": "string", "values": "string",
          "json": "string", "int|f32": "float64", "int|f64": "float64"}


class Column(NamedTuple):
    name: str
    kind: str                            # a key of _ARROW
    read: Callable[[list], list]         # a batch of records -> the column's values for them
    path: str = ""                       # where the value is in the record's canonical form: keys and
    #                                      array indexes joined by '/' ("joints/0/q_actual", "dh_a/3")


def _attr(name: str) -> Callable[[list], list]:
    get = operator.attrgetter(name)

    def read(objs: list) -> list:
        try:
            return list(map(get, objs))
        except (AttributeError, TypeError):  # a missing group, or a layout without the field
            return [None if o is None else getattr(o, name, None) for o in objs]
    return read


def _nth(j: int) -> Callable[[list], list]:
    get = operator.itemgetter(j)

    def read(lists: list) -> list:
        try:
            return list(map(get, lists))
        except (IndexError, TypeError):      # a list that is missing or shorter
            return [None if i is None or j >= len(i) else i[j] for i in lists]
    return read


def _then(first: Callable[[list], list], second: Callable[[list], list]) -> Callable[[list], list]:
    return lambda objs: second(first(objs))


def _plain(kind: str) -> Callable[[list], list]:
    """Values as `urwire decode` shows them, in the type their column takes (as export.py writes
    them): any nonzero bool byte as true, text with each invalid UTF-8 byte as U+FFFD, name lists
    and values as their JSON; numbers and enums go to Arrow as they are."""
    if kind == "bool":
        return lambda vs: [None if v is None else bool(v) for v in vs]
    if kind == "text":
        return lambda vs: [None if v is None else shown_text(v) for v in vs]
    if kind in ("texts", "values"):
        return lambda vs: [None if v is None else member_text(kind, v) for v in vs]
    if kind == "hex":
        return lambda vs: [None if v is None else bytes(v) for v in vs]
    return lambda vs: vs


def _as_json(name: str) -> Callable[[list], list]:
    return lambda objs: [None if getattr(o, name) is None else json.dumps(to_dict(o)[name], ensure_ascii=False)
                         for o in objs]


def class_columns(cls: type) -> list[Column]:
    """The columns of a generated class, in the order of its fields: a fixed-count group's fields
    per item (`q_actual_0` ..., prefixed with the group's name where a kind has two groups), a
    fixed-count list's items (`dh_a_0` ...), anything of a count only a record knows as JSON text."""
    meta = {f.name: f.metadata for f in dataclasses.fields(cls)}
    groups = [name for name, kind, _ in cls.JSON if kind == "items"]
    out: list[Column] = []
    for name, kind, _ in cls.JSON:
        count = meta[name].get("count")
        if meta[name].get("wire") == "uint64":
            kind = "list:uint64" if kind.startswith("list:") else "uint64"
        if kind == "items" and count is not None:
            prefix = f"{name}_" if len(groups) > 1 else ""
            for j in range(count):
                item = _then(_attr(name), _nth(j))
                out += [Column(f"{prefix}{c.name}_{j}", c.kind, _then(item, c.read), f"{name}/{j}/{c.path}")
                        for c in class_columns(cls.ITEMS[name])]
        elif kind.startswith("list:") and count is not None:
            item_kind = kind[len("list:"):]
            out += [Column(f"{name}_{j}", item_kind, _then(_then(_attr(name), _nth(j)), _plain(item_kind)),
                           f"{name}/{j}") for j in range(count)]
        elif kind == "items" or kind.startswith("list:"):
            out.append(Column(name, "json", _as_json(name), name))
        else:
            out.append(Column(name, kind, _then(_attr(name), _plain(kind)), name))
    return out


def _primary_classes() -> dict[str, type]:
    """Every kind of the primary interface that has a table: sub-packages and messages by TYPE."""
    return {cls.TYPE: cls for cls in vars(messages).values()
            if inspect.isclass(cls) and hasattr(cls, "JSON") and isinstance(getattr(cls, "TYPE", None), str)}


def _realtime_columns() -> list[Column]:
    """One real-time table for every layout: `type` names the layout, then the fields of every
    layout, oldest first, each once (a field that a layout lacks is null)."""
    seen: dict[str, Column] = {"type": Column("type", "text", lambda objs: [o.TYPE for o in objs], "type")}
    for forms in ur_realtime.FORMS_BY_SIZE.values():
        for *_, cls, _ in forms:
            for column in class_columns(cls):
                seen.setdefault(column.name, column)
    return list(seen.values())


_CLASSES = _primary_classes()
_APART = {kind: [Column("record", "text", lambda objs: [to_json_line(o) for o in objs], "record")]
          for kind in ERROR_KINDS}
# Each interface's kinds, each with the function that gives its columns.
_KINDS: dict[str, dict[str, Callable[[], list[Column]]]] = {
    PRIMARY: {**{kind: (lambda cls=cls: class_columns(cls)) for kind, cls in _CLASSES.items()},
              ROBOT_STATE: lambda: [Column("packages", "int", lambda objs: [len(o) for o in objs], "packages")],
              **{kind: (lambda kind=kind: _APART[kind]) for kind in ERROR_KINDS}},
    REALTIME: {REALTIME_STATE: _realtime_columns, **{kind: (lambda kind=kind: _APART[kind]) for kind in ERROR_KINDS}},
}
_COLUMNS: dict[tuple, list[Column]] = {}


def interfaces() -> list[str]:
    """The interfaces the dataset holds, each a folder `interface=<name>`."""
    return list(_KINDS)


def kinds(interface: str = PRIMARY) -> list[str]:
    """The kinds an interface's part of the dataset has, each a folder `kind=<name>`."""
    if interface not in _KINDS:
        raise ValueError(f"the dataset holds the interfaces {', '.join(_KINDS)}, not {interface!r}")
    return list(_KINDS[interface])


def columns_of(interface: str, kind: str) -> list[Column]:
    if (interface, kind) not in _COLUMNS:
        if kind not in kinds(interface):
            raise ValueError(f"no kind {kind!r} in interface {interface!r}")
        _COLUMNS[(interface, kind)] = _KINDS[interface][kind]()
    return _COLUMNS[(interface, kind)]


def dataset_schema(interface: str, kind: str):
    """The kind's pyarrow schema, the same for every capture and software version."""
    import pyarrow as pa
    lead = [pa.field("capture", pa.string(), nullable=False), pa.field("capture_file", pa.string()),
            pa.field("position", pa.int64(), nullable=False), pa.field("capture_time", pa.timestamp("us", "UTC")),
            pa.field("conversation", pa.string())]
    return pa.schema(lead + [pa.field(c.name, getattr(pa, _ARROW[c.kind])()) for c in columns_of(interface, kind)])
