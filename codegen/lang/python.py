"""Python spelled once: class names, string literals and item metadata of generated modules."""
from __future__ import annotations

import json
from typing import Iterable, Optional

from ..items import Item, item_set_names, own_units
from ..wrap import spread


def class_name(name: str) -> str:
    """A spec name as a class name: robot_mode_data -> RobotModeData, rt_3_10 -> Rt3_10 (a
    version's numbers stay apart)."""
    out = ""
    for part in name.split("_"):
        out += ("_" if out[-1:].isdigit() and part[:1].isdigit() else "") + part[:1].upper() + part[1:]
    return out


def string(text: str) -> str:
    """A Python string literal (UTF-8 kept as it is)."""
    return json.dumps(text, ensure_ascii=False)


def string_or_none(text: Optional[str]) -> str:
    return "None" if text is None else string(text)


def item_set_constant(set_name: str) -> str:
    """The module constant that holds an item set's names: JOINTS for the spec's "joints"."""
    return set_name.upper()


def item_metadata(named: tuple[Item, ...]) -> list[str]:
    """A vector's named items in its metadata: its set's names, and each item's unit where they differ."""
    if not named:
        return []
    units = own_units(named)
    return [f'"items": {item_set_constant(named[0].set_name)}'] + \
        ([f'"item_units": ({", ".join(string(u) for u in units)})'] if units else [])


def item_set_constants(vectors: Iterable[tuple[Item, ...]]) -> list[str]:
    """One module constant per item set the vectors take: `JOINTS = ("Base", "Shoulder", ...)`."""
    return [spread([string(label) for label in labels], f"{item_set_constant(name)} = (", ")")
            for name, labels in sorted(item_set_names(vectors).items())]
