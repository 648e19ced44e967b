"""The targets: each module here with a `render(plan, banner) -> {path: text}` function turns
the planned IR (codegen/plan.py) into files under generated/<target>/; a target may take keyword
options of its own (epan's `upstream`). Adding a target is adding a module and its templates."""
from __future__ import annotations

import importlib
import pkgutil
from typing import TYPE_CHECKING, Callable, Optional

from .. import ir
from ..plan import ProtocolPlan, plan

if TYPE_CHECKING:
    from ..kinds import TargetOptions

Render = Callable[[ProtocolPlan, list[str]], dict[str, str]]


def _discover() -> dict[str, Render]:
    found = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        if callable(getattr(module, "render", None)):
            found[info.name] = module.render
    return found


TARGETS: dict[str, Render] = _discover()


def render_all(protocol: ir.Protocol, spec_path: str, spec_text: str,
               only: Optional[list[str]] = None) -> dict[str, str]:
    from ..emit import banner_lines

    return render_protocol(protocol, banner_lines(spec_path, spec_text), only)


def render_protocol(protocol: ir.Protocol, banner: list[str], only: Optional[list[str]] = None,
                    options: Optional[TargetOptions] = None) -> dict[str, str]:
    """Every target's files for a primary-interface protocol."""
    from ..kinds import render_targets

    return render_targets(TARGETS, plan(protocol), banner, only, options)
