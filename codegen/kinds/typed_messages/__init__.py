"""The kind `typed_messages`: length-framed messages whose type code means one layout per direction
and negotiated protocol version, with state kept per connection (RTDE's recipes). The spec language
part is codegen/schema/typed_messages.schema.json; `resolve` makes the IR (model.py), `plan` the
decisions every target shares (plan.py); each target renders the plan (c.py, epan.py, lua.py,
python.py)."""
from __future__ import annotations

from typing import Optional

from .. import Kind, TargetOptions, render_targets
from . import c, epan, lua, python
from .model import Interface
from .plan import plan
from .resolve import resolve

_TARGETS = {"c": c.render, "epan": epan.render, "lua": lua.render, "python": python.render}


def render(interface: Interface, banner: list[str], only_targets: Optional[list[str]],
           options: Optional[TargetOptions] = None) -> dict[str, str]:
    return render_targets(_TARGETS, plan(interface), banner, only_targets, options)


KIND = Kind(name="typed_messages", schema="typed_messages.schema.json", resolve=resolve, render=render)
