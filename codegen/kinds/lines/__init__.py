"""The kind `lines`: interfaces that speak in text lines (the dashboard server, port 29999).

A client's commands and the server's replies are lines ending in a newline; the spec lists
every command with its replies (patterns with placeholders), which say an error, and the
software versions that have each command (spec/ur_dashboard.yaml)."""
from __future__ import annotations

from typing import Optional

from .. import Kind, TargetOptions, render_targets
from . import c, epan, lua, python
from .model import LinesProtocol
from .plan import plan
from .resolve import resolve

_TARGETS = {"c": c.render, "epan": epan.render, "lua": lua.render, "python": python.render}


def render(model: LinesProtocol, banner: list[str], only: Optional[list[str]] = None,
           options: Optional[TargetOptions] = None) -> dict[str, str]:
    return render_targets(_TARGETS, plan(model), banner, only, options)


KIND = Kind(name="lines", schema="lines.schema.json", resolve=resolve, render=render)
