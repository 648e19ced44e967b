"""The kind `typed_messages`: length-framed messages whose type code means one layout per direction
and negotiated protocol version, with state kept per connection (RTDE's recipes). The spec language
part is codegen/schema/typed_messages.schema.json; `resolve` makes the IR (model.py); each target
renders it (python_target.py, lua_target.py, c_target.py, epan_target.py)."""
from __future__ import annotations

from typing import Optional

from .. import Kind, TargetOptions, render_targets
from . import c_target, epan_target, lua_target, python_target
from .model import Interface
from .resolve import resolve


_TARGETS = {"c": c_target.render, "epan": epan_target.render, "lua": lua_target.render,
            "python": python_target.render}


def render(interface: Interface, banner: list[str], only_targets: Optional[list[str]],
           options: Optional[TargetOptions] = None) -> dict[str, str]:
    return render_targets(_TARGETS, interface, banner, only_targets, options)


KIND = Kind(name="typed_messages", schema="typed_messages.schema.json", resolve=resolve, render=render)
