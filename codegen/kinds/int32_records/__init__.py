"""The kind `int32_records`: interfaces whose records are fixed runs of big-endian int32 with no
length header, values scaled by powers of ten, layouts gated by driver release (the ROS driver's
reverse, trajectory and script command sockets: spec/ur_reverse.yaml and its siblings)."""
from __future__ import annotations

from typing import Optional

from .. import Kind, TargetOptions, render_targets
from . import c, epan, lua, python
from .model import RecordsProtocol
from .plan import plan
from .resolve import resolve

_TARGETS = {"c": c.render, "epan": epan.render, "lua": lua.render, "python": python.render}


def render(model: RecordsProtocol, banner: list[str], only: Optional[list[str]] = None,
           options: Optional[TargetOptions] = None) -> dict[str, str]:
    return render_targets(_TARGETS, plan(model), banner, only, options)


KIND = Kind(name="int32_records", schema="int32_records.schema.json", resolve=resolve, render=render)
