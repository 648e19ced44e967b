"""The kind `sized_packets`: an interface of fixed packets, each opened by an int32 size that
chooses its layout (the real-time interface, 30003). Its layouts are gated by software version
like the primary interface's, and layouts that share a size are told apart by the rule the spec
states (framing.same_size), rendered from the plan in every target.

model.py holds its IR, resolve.py makes it, plan.py lays out offsets and the forms by size, and
one module per target renders them."""
from __future__ import annotations

from typing import Optional

from .. import Kind, TargetOptions, render_targets
from . import c, epan, lua, python
from .plan import plan
from .resolve import resolve

_TARGETS = {"c": c.render, "epan": epan.render, "lua": lua.render, "python": python.render}


def render(model, banner: list[str], only_targets: Optional[list[str]] = None,
           options: Optional[TargetOptions] = None) -> dict[str, str]:
    return render_targets(_TARGETS, plan(model), banner, only_targets, options)


KIND = Kind(name="sized_packets", schema="sized_packets.schema.json", resolve=resolve, render=render)
