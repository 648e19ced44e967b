"""The kind `typed_messages`: length-framed messages whose type code means one layout per direction
and negotiated protocol version, with state kept per connection (RTDE's recipes). The spec language
part is codegen/schema/typed_messages.schema.json; `resolve` makes the IR (model.py); each target
renders it (python.py, lua.py, c.py)."""
from __future__ import annotations

from typing import Optional

from .. import Kind
from . import c_target, lua_target, python_target
from .model import Interface
from .resolve import resolve


def render(interface: Interface, banner: list[str], only_targets: Optional[list[str]]) -> dict[str, str]:
    targets = {"c": c_target.render, "lua": lua_target.render, "python": python_target.render}
    return {path: text for name, render_target in targets.items()
            if only_targets is None or name in only_targets
            for path, text in render_target(interface, banner).items()}


KIND = Kind(name="typed_messages", schema="typed_messages.schema.json", resolve=resolve, render=render)
