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


def _values(values, recipe) -> list[str]:
    """Every value under its variable's name, in recipe order: a name the recipe repeats is printed
    once per value, as the C writer prints it."""
    if recipe is not None:
        in_order = values.in_order() if getattr(values, "names", None) == recipe.names \
            else [values[name] for name in recipe.names]            # a dict a caller built
        return [f"{_text(name)}: {_value(value, shape.kind)}"
                for (name, shape), value in zip(recipe.json_kinds(), in_order)]
    pairs = values.pairs() if hasattr(values, "pairs") else values.items()
    return [f"{_text(name)}: {_by_python_type(value)}" for name, value in pairs]


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
    if "error" in notes:
        parts.append(f'"error": {_text(notes["error"])}')
    return "{" + ", ".join(parts) + "}"


def raw_json(obj) -> str:
    parts = [f'"type": "{obj.type}"', f'"message_type": {obj.code}']
    if obj.recipe_id is not None:
        parts.append(f'"recipe_id": {obj.recipe_id}')
    if obj.error is not None:
        parts.append(f'"error": {_text(obj.error)}')
    parts.append(f'"raw": "{obj.raw.hex()}"')
    return "{" + ", ".join(parts) + "}"
