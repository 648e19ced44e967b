"""An optional pass between resolve (and --pin) and plan: only the parts a firmware reads.

A selection names, per interface, the parts to decode; every target then renders the IR with only
those, and the rest of the stream is still framed and skipped by its declared length:

    python -m codegen --select ur:robot_state.joint_data,robot_state.tool_data --target c --out build/subset
    python -m codegen --select firmware.yaml --target c --out build/subset

An interface is named as `urwire decode --protocol` names it (the spec's `protocol.name`: `ur`,
`rtde`) or by its spec file (`ur_primary`). What each kind takes is its own `select.py`
(`kinds/<kind>/select.py`: `select(model, picks, where) -> (model, problems)`); a kind without
one takes no selection. A selection file is a YAML mapping of interface to names, checked
against codegen/schema/select.schema.json:

    ur: [robot_state.joint_data, robot_state.tool_data]
    rtde: [actual_q, actual_TCP_pose]

Every problem names the selection's entry (a file's YAML path and line) and what is wrong,
all of them before it stops, as a spec's problems do (docs/generator.md#subsets).
"""
from __future__ import annotations

import difflib
import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable

from . import ir
from .errors import Problem, SpecError
from .load import LoadedSpec, load_file, load_text
from .validate import schema_problems

SCHEMA = "select.schema.json"
OPTION = "--select"


@dataclass(frozen=True)
class Pick:
    """One name of a selection, and where it was written (a file's line, or the option)."""
    name: str
    where: ir.Where


@dataclass(frozen=True)
class Selection:
    """The names picked per interface key (`ur`, `rtde`, `ur_primary`), and where each key was given."""
    picks: dict[str, tuple[Pick, ...]]
    keys: dict[str, ir.Where]

    def key_of(self, names: Iterable[str]) -> str | None:
        """The key that names an interface known by any of `names`, if the selection has one."""
        return next((k for k in self.picks if k in set(names)), None)


class SelectionError(SpecError):
    """A selection that cannot be applied: every problem, at the selection's entry."""

    def __init__(self, source: str, problems: list[Problem]):
        super().__init__(source, problems)
        lines = "\n".join(f"  {p}" for p in problems)
        self.args = (f"{source}: {len(problems)} problem(s) in the selection:\n{lines}",)


def parse(values: list[str]) -> Selection:
    """The selection of every `--select` value: `interface:name,name` or a selection file's path.
    Raises SelectionError with every problem of every value."""
    picks: dict[str, list[Pick]] = {}
    keys: dict[str, ir.Where] = {}
    problems: list[Problem] = []
    for value in values:
        try:
            one = _file(Path(value)) if _is_file(value) else _option(value)
        except SelectionError as exc:
            problems += exc.problems
            continue
        for key, names in one.picks.items():
            picks.setdefault(key, []).extend(names)
            keys.setdefault(key, one.keys[key])
    if problems:
        raise SelectionError(OPTION, problems)
    return Selection({k: tuple(v) for k, v in picks.items()}, keys)


def _is_file(value: str) -> bool:
    return value.endswith((".yaml", ".yml")) or (":" not in value and Path(value).is_file())


def _file(path: Path) -> Selection:
    if not path.is_file():
        raise SelectionError(OPTION, [Problem(str(path), "no such selection file")])
    return _checked(load_file(path))


def _option(value: str) -> Selection:
    """`ur:robot_state.joint_data,robot_state.tool_data`, checked as a file of one entry is."""
    key, colon, names = value.partition(":")
    if not colon:
        raise SelectionError(OPTION, [Problem(value, "write interface:name,name (ur:robot_state.joint_data) "
                                                    "or the path of a selection file (.yaml)")])
    spec = LoadedSpec(value, {key: [n.strip() for n in names.split(",")]}, {})
    return _checked(spec)


def _checked(spec: LoadedSpec) -> Selection:
    problems = schema_problems(spec, SCHEMA)
    if problems:
        raise SelectionError(OPTION, [Problem(f"{spec.source}: {p.path}", p.message, p.line) for p in problems])
    picks, keys = {}, {}
    for key, names in spec.data.items():
        keys[key] = _where(spec, key)
        picks[key] = tuple(Pick(name, _where(spec, f"{key}[{i}]")) for i, name in enumerate(names))
    return Selection(picks, keys)


def _where(spec: LoadedSpec, path: str) -> ir.Where:
    # A name in a file: the file, its YAML path and line. On the command line: the interface.
    if spec.lines:
        return ir.Where(f"{spec.source}: {path}", spec.line_of(path))
    return ir.Where(path.partition("[")[0])


def names_of(spec: Path, data: object) -> set[str]:
    """What a selection may call an interface: its protocol name (`ur`) or its spec file's (`ur_primary`)."""
    protocol = data.get("protocol") if isinstance(data, dict) else None
    name = protocol.get("name") if isinstance(protocol, dict) else None
    return {spec.stem} | ({name} if isinstance(name, str) else set())


def specs_for(selection: Selection, specs: list[Path]) -> list[Path]:
    """The specs of the interfaces the selection names, or SelectionError for a name no spec has."""
    named = {spec: names_of(spec, load_file(spec).data) for spec in specs}
    chosen = [spec for spec, names in named.items() if selection.key_of(names)]
    known = sorted(n for names in named.values() for n in names)
    problems = [selection.keys[key].problem(unknown(key, "interface", "the cell", known)) for key in selection.picks
                if not any(key in names for names in named.values())]
    if problems:
        raise SelectionError(OPTION, problems)
    return chosen


def apply(kind: str, model: object, picks: tuple[Pick, ...], where: ir.Where) -> object:
    """The model with only the picked parts (the kind's select.py), or SelectionError."""
    try:
        module = importlib.import_module(f"{__package__}.kinds.{kind}.select")
    except ModuleNotFoundError:
        takers = ", ".join(sorted(k for k in _kinds_that_select()))
        raise SelectionError(OPTION, [where.problem(f"an interface of kind {kind} takes no selection "
                                                    f"(kinds that do: {takers})")]) from None
    selected, problems = module.select(model, picks, where)
    if problems:
        raise SelectionError(OPTION, problems)
    return selected


def _kinds_that_select() -> list[str]:
    from .kinds import KINDS
    root = Path(__file__).parent / "kinds"
    return [k for k in KINDS if (root / k / "select.py").is_file()]


def unknown(name: str, what: str, place: str, known: Iterable[str]) -> str:
    """What a problem says of a name that is not there: the closest names, or all when few."""
    known = list(known)
    close = difflib.get_close_matches(name, known, n=3)
    if close:
        return f"{place} has no {what} '{name}' (did you mean {', '.join(close)}?)"
    if len(known) <= 20:
        return f"{place} has no {what} '{name}'; it has: {', '.join(known)}"
    return f"{place} has no {what} '{name}'"


def banner(picks: tuple[Pick, ...]) -> list[str]:
    """What a generated file of a selection says about it, after the usual banner."""
    lines, line = [], "Only these parts (python -m codegen --select):"
    for pick in picks:
        if len(line) + len(pick.name) > 96:
            lines.append(line)
            line = " "
        line += f" {pick.name}"
    return lines + [line, "What becomes of the rest of the stream: docs/generator.md#subsets."]


def load_selection_text(text: str, source: str = "<selection>") -> Selection:
    """A selection file's text (tests, tools)."""
    return _checked(load_text(text, source))
