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


_ITEM = {"bool": lambda v: "true" if v else "false", "float": f64_text, "int": lambda v: "%d" % int(v)}


def _vector_writer(item):
    return lambda values: "[" + ", ".join(map(item, values)) + "]"


def value_writers(names, shapes) -> tuple:
    """A recipe's values in JSON, worked out once per recipe: for each value in order, the text
    before it ('"actual_q": ') and the function that writes it by its type's shape (a vector's
    items each as its kind). What _value writes of a decoded package, without asking each value."""
    return tuple((f"{_text(name)}: ", _vector_writer(_ITEM[shape.kind]) if shape.count > 1 else _ITEM[shape.kind])
                 for name, shape in zip(names, shapes))


def _values(values, recipe) -> list[str]:
    """Every value under its variable's name, in recipe order: a name the recipe repeats is printed
    once per value, as the C writer prints it."""
    if recipe is not None:
        if getattr(values, "names", None) == recipe.names:         # decoded, or in the recipe's order
            return [key + write(value) for (key, write), value in zip(recipe.json_writers, values.in_order())]
        in_order = [values[name] for name in recipe.names]            # a dict a caller built
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
