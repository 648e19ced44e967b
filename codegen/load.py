"""Pass 1: read the spec YAML, remembering the line of every node so errors can point at it."""
from __future__ import annotations

from pathlib import Path

import yaml

from .errors import Problem, SpecError, format_path


class LoadedSpec:
    def __init__(self, source: str, data: object, lines: dict[str, int]):
        self.source = source
        self.data = data
        self.lines = lines

    def line_of(self, path: str) -> int | None:
        # Walk up until a node with a known line: the closest enclosing one.
        while path:
            if path in self.lines:
                return self.lines[path]
            cut = max(path.rfind("."), path.rfind("["))
            path = path[:cut] if cut > 0 else ""
        return None

    def problem(self, parts, message: str) -> Problem:
        path = parts if isinstance(parts, str) else format_path(parts)
        return Problem(path, message, self.line_of(path))


def _index_lines(node, parts, lines: dict[str, int]) -> None:
    lines[format_path(parts)] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        for key, value in node.value:
            _index_lines(value, parts + [key.value], lines)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _index_lines(item, parts + [i], lines)


def load_text(text: str, source: str = "<spec>") -> LoadedSpec:
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark else None
        raise SpecError(source, [Problem("(yaml)", str(exc).replace("\n", " "), line)]) from None
    lines: dict[str, int] = {}
    if node is not None:
        _index_lines(node, [], lines)
    return LoadedSpec(source, data, lines)


def load_file(path: Path) -> LoadedSpec:
    return load_text(Path(path).read_text(encoding="utf-8"), str(path))
