"""The JSON Schema of a record kind's canonical JSON, made from its generated class: each field's
label and unit (the spec's, kept in the dataclass field's metadata) become its description, which
is what Foxglove shows beside a field in its message path pickers."""
from __future__ import annotations

import dataclasses
import functools
import json
import typing

# The envelope every record of a capture comes in (docs/canonical-json.md#records-of-a-capture).
_ENVELOPE = {
    "interface": {"type": "string", "description": "The interface, as its Wireshark protocol is named"},
    "direction": {"type": "string", "enum": ["from_robot", "to_robot"]},
    "conversation": {"type": "string", "description": "The TCP conversation: server-client"},
    "type": {"type": "string", "description": "The record kind"},
}

# A float field is null where the wire held NaN or an infinity (strict JSON has neither).
_NUMBER = {"type": ["number", "null"]}
_TYPES = {"int": {"type": "integer"}, "uint64": {"type": "integer"}, "enum": {"type": "integer"},
          "bool": {"type": "boolean"}, "f32": _NUMBER, "f64": _NUMBER, "float": _NUMBER, "int|f32": _NUMBER,
          "text": {"type": "string"}, "hex": {"type": "string", "description": "bytes as hexadecimal"},
          "bool|text": {"type": ["boolean", "string"]}, "names": {"type": "array", "items": {"type": "string"}},
          "texts": {"type": "array", "items": {"type": "string"}}}

# A record of no class the spec lays out (an error, an unknown message): any object.
ANY_RECORD = {"type": "object", "properties": _ENVELOPE}


def schema_text(cls: type, title: str) -> bytes:
    """The schema of a record class's canonical JSON, as the bytes an MCAP schema record holds."""
    schema = {"$schema": "https://json-schema.org/draft/2020-12/schema", "title": title,
              **_object_of(cls, _ENVELOPE)}
    return json.dumps(schema, ensure_ascii=False).encode()


@functools.lru_cache(maxsize=None)
def _hints(cls: type) -> dict:
    try:
        return typing.get_type_hints(cls)
    except Exception:   # an annotation that does not resolve: its items stay plain objects
        return {}


def _object_of(cls: type, first: dict = {}) -> dict:
    """An object schema of a generated class: its JSON fields, each described by its label and unit."""
    out = {"type": "object", "properties": dict(first)}
    label = getattr(cls, "LABEL", None)
    if label:
        out["description"] = label
    if not dataclasses.is_dataclass(cls) or not hasattr(cls, "JSON"):
        return out
    fields = {f.name: f for f in dataclasses.fields(cls)}
    for name, kind, _ in cls.JSON:
        field = fields.get(name)
        meta = field.metadata if field is not None else {}
        if kind == "values":    # an RTDE recipe's variables, each at the top under its own name
            out["description"] = f"{label or name}; the recipe's variables are fields of their own"
            continue
        prop = _member(cls, name, kind)
        text = meta.get("label")
        if text and meta.get("unit"):
            text = f"{text} [{meta['unit']}]"
        if text:
            prop = {**prop, "description": text}
        out["properties"][name] = prop
    return out


def _member(cls: type, name: str, kind: str) -> dict:
    if kind.startswith("list:"):
        return {"type": "array", "items": _member(cls, name, kind[len("list:"):])}
    if kind == "items":
        item = _item_class(cls, name)
        return {"type": "array", "items": _object_of(item) if item else {"type": "object"}}
    if kind == "values":
        return {"type": "object"}
    return dict(_TYPES.get(kind, {}))


def _item_class(cls: type, name: str):
    """The class of a list's items (joints: list[Joint]), from the field's annotation."""
    for arg in typing.get_args(_hints(cls).get(name)):
        if isinstance(arg, type) and dataclasses.is_dataclass(arg):
            return arg
        for inner in typing.get_args(arg):   # Optional[list[X]]
            if isinstance(inner, type) and dataclasses.is_dataclass(inner):
                return inner
    return None
