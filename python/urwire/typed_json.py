"""Canonical JSON (docs/canonical-json.md) of the typed-messages records (RTDE): a message's members
in layout order, a data package's values by variable name, then what the connection noted."""
from __future__ import annotations

from typing import Any

from .canonical import f64_text, _text


def _value(value: Any, kind: str) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_value(v, kind) for v in value) + "]"
    if kind == "bool":
        return "true" if value else "false"
    if kind == "float":
        return f64_text(value)
    return "%d" % int(value)


def _by_python_type(value: Any) -> str:
    first = value[0] if isinstance(value, list) and value else value
    kind = "bool" if isinstance(first, bool) else "float" if isinstance(first, float) else "int"
    return _value(value, kind)


def _values(values: dict, recipe) -> list[str]:
    if recipe is not None:
        return [f"{_text(name)}: {_value(values[name], shape.kind)}" for name, shape in recipe.json_kinds()]
    return [f"{_text(name)}: {_by_python_type(value)}" for name, value in values.items()]


def message_json(obj) -> str:
    parts = [f'"type": "{obj.NAME}"']
    notes = obj.notes
    for name, kind, _ in obj.JSON:
        value = getattr(obj, name)
        if kind == "values":
            parts += _values(value, notes.get("recipe"))
        elif kind == "names":
            parts.append(f'"{name}": [' + ", ".join(map(_text, value)) + "]")
        elif kind == "text":
            parts.append(f'"{name}": {_text(value)}')
        else:
            parts.append(f'"{name}": {_value(value, kind)}')
    if "refused" in notes:
        parts.append('"refused": {' + ", ".join(f"{_text(n)}: {_text(w)}" for n, w in notes["refused"]) + "}")
    if "warning" in notes:
        parts.append(f'"warning": {_text(notes["warning"])}')
    return "{" + ", ".join(parts) + "}"


def raw_json(obj) -> str:
    parts = [f'"type": "{obj.type}"', f'"message_type": {obj.code}']
    if obj.recipe_id is not None:
        parts.append(f'"recipe_id": {obj.recipe_id}')
    if obj.error is not None:
        parts.append(f'"error": {_text(obj.error)}')
    parts.append(f'"raw": "{obj.raw.hex()}"')
    return "{" + ", ".join(parts) + "}"
