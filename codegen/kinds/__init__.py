"""Interface kinds: what `framing.kind` a spec declares decides which part of the spec language it
uses. Each kind is a package here with the same modules: its schema (a file under codegen/schema
that may $ref the shared definitions of spec.schema.json), `resolve.py` (LoadedSpec -> its IR,
model.py), `plan.py` (the IR -> its plan), one renderer per target, named after it (`c.py`,
`epan.py`, `lua.py`, `python.py`: plan -> {path under generated/: text}), and what changes from
one version to another (`python -m codegen diff`, in the terms of codegen/version_diff.py). The
primary interface is the kind `packages`: length-framed messages holding sub-packages, and a
spec that names no kind is one of those. A kind imports nothing from another kind.

Adding a kind is adding a package here whose __init__.py defines `KIND = define(...)`."""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass
from types import ModuleType
from typing import Callable, Optional

from ..ir import Version
from ..load import LoadedSpec

DEFAULT_KIND = "packages"

# Every kind renders every target, each with a module of this name (python -m codegen --target).
TARGETS = ("c", "epan", "lua", "python")


# Keyword arguments of some targets' renderers, by target: {"epan": {"upstream": True}} renders the
# copy of the dissectors for Wireshark's own tree (python -m codegen --upstream).
TargetOptions = dict[str, dict[str, object]]


@dataclass(frozen=True)
class Kind:
    name: str
    schema: str                                          # a file name under codegen/schema
    resolve: Callable[[LoadedSpec], object]              # raises SpecError with every problem
    plan: Callable[[object], object]                     # model -> plan
    diff: Callable[[object, Version, Version], list[str]]   # (plan, a, b) -> what changes from a to b
    # (model, banner lines, only these targets or None for all, options or None)
    #   -> {path under generated/: text}
    render: Callable[[object, list[str], Optional[list[str]], Optional[TargetOptions]], dict[str, str]]


def define(name: str, schema: str, resolve: ModuleType, plan: ModuleType, renderers: list[ModuleType],
           diff: Callable[[object, Version, Version], list[str]]) -> Kind:
    """A kind from its package's modules: resolve.resolve (LoadedSpec -> IR), plan.plan (IR ->
    plan), one module per target, named after it, with render(plan, banner, **options), and its
    diff (plan, version a, version b -> the lines that say what changes)."""
    targets = {module.__name__.rpartition(".")[2]: module.render for module in renderers}
    if sorted(targets) != sorted(TARGETS):
        raise ValueError(f"kind {name}: renderers for {sorted(targets)}, every kind has {sorted(TARGETS)}")

    def render(model: object, banner: list[str], only: Optional[list[str]] = None,
               options: Optional[TargetOptions] = None) -> dict[str, str]:
        return render_targets(targets, plan.plan(model), banner, only, options)

    return Kind(name=name, schema=schema, resolve=resolve.resolve, plan=plan.plan, diff=diff, render=render)


def render_targets(targets: dict[str, Callable[..., dict[str, str]]], model: object, banner: list[str],
                   only: Optional[list[str]], options: Optional[TargetOptions] = None) -> dict[str, str]:
    """The files of every chosen target ({"c": render, ...}; `only` None for all) for one model,
    each renderer given its target's options."""
    outputs: dict[str, str] = {}
    for name, render in targets.items():
        if only is None or name in only:
            outputs.update(render(model, banner, **(options or {}).get(name, {})))
    return outputs


def kind_name(data: object) -> str:
    """The kind a loaded spec declares (framing.kind), or the primary interface's."""
    framing = data.get("framing") if isinstance(data, dict) else None
    kind = framing.get("kind") if isinstance(framing, dict) else None
    return kind if isinstance(kind, str) else DEFAULT_KIND


def _discover() -> dict[str, Kind]:
    found = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        module = importlib.import_module(f"{__name__}.{info.name}")
        kind = getattr(module, "KIND", None)
        if isinstance(kind, Kind):
            found[kind.name] = kind
    return found


KINDS: dict[str, Kind] = _discover()
