"""Python spelled once: class names and string literals of generated modules."""
from __future__ import annotations

import json
from typing import Optional


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
