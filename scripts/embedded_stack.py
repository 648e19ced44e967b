"""Worst-case stack from gcc's call graph: the .ci files `-fcallgraph-info=su` writes (a node per
function with its frame from -fstack-usage, an edge per call), summed along the deepest path.

An indirect call counts as the deepest function it may reach: those whose address the calling
function takes, itself or through the tables it reads (the relocations of its code and of those
tables, which are not calls, name them); when it takes none (the pointer came from its caller),
every function whose address some code takes. A callback of yours (a visitor's) is not in the
graph. A cycle is recursion, whose depth no graph bounds: it is refused (Recursion), as is a
frame gcc could not bound (a variable-length array or alloca). Functions the graph does not hold
(the C library's and the compiler's helpers: memcpy, memmove, division, soft float) count 0 and
are named beside the figure.
"""
from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

INDIRECT = "__indirect_call"
NODE = re.compile(r'^node: \{ title: "([^"]*)" label: "([^"]*)"')
EDGE = re.compile(r'^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"')
FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")
# Relocations that call or jump: every other relocation naming a function takes its address.
CALLS = re.compile(r"R_ARM_(THM_)?(CALL|JUMP\d*)|R_RISCV_(CALL|CALL_PLT|JAL|BRANCH|RVC_JUMP|RVC_BRANCH|RELAX|ALIGN)")


class Recursion(Exception):
    """The call graph has a cycle: no stack bound."""


class Unbounded(Exception):
    """A frame of dynamic size that gcc could not bound."""


@dataclass
class CallGraph:
    frames: dict[str, int] = field(default_factory=dict)        # function -> its own frame
    calls: dict[str, set[str]] = field(default_factory=dict)    # function -> what it calls
    refs: dict[str, set[str]] = field(default_factory=dict)     # function or table -> what it points at
    unknown: set[str] = field(default_factory=set)              # called, not in the graph

    def add_ci(self, path: Path) -> None:
        """The nodes and edges of one .ci file. A node is keyed by its name: the functions of a
        program are linked by name, and a static one keeps its file's name beside (file:name)."""
        names: dict[str, str] = {}
        edges = []
        for line in path.read_text().splitlines():
            node = NODE.match(line)
            if node:
                title, label = node.groups()
                names[title] = title if title == INDIRECT else label.split("\\n")[0]
                frame = FRAME.search(label)
                if frame:
                    if frame.group(2) == "dynamic":
                        raise Unbounded(f"{names[title]} ({path.name}): a frame of dynamic size")
                    self.frames[names[title]] = int(frame.group(1))
                continue
            edge = EDGE.match(line)
            if edge:
                edges.append(edge.groups())
        for source, target in edges:
            self.calls.setdefault(names.get(source, source), set()).add(names.get(target, target))

    def add_relocations(self, readelf: str, obj: Path) -> None:
        """What each function and table of the object points at, from its relocations other than
        calls (each is in a section of its own, -ffunction-sections -fdata-sections, so a section
        names one)."""
        out = subprocess.run([readelf, "-rW", str(obj)], capture_output=True, text=True, check=True).stdout
        owner = None
        for line in out.splitlines():
            if line.startswith("Relocation section"):
                owner = _base(line.split("'")[1].removeprefix(".rela").removeprefix(".rel"))
                continue
            parts = line.split()
            if owner is None or len(parts) < 5 or not parts[2].startswith("R_") or CALLS.fullmatch(parts[2]):
                continue
            target = _base(parts[4])
            if target != owner:     # a function's own code: its jump tables (.rodata.<function>)
                self.refs.setdefault(owner, set()).add(target)

    def _pointed(self, name: str) -> set[str]:
        """The functions `name` points at, itself or through the tables it points at."""
        found, seen, todo = set(), {name}, [name]
        while todo:
            for ref in self.refs.get(todo.pop(), ()):
                if ref in self.frames:
                    found.add(ref)
                elif ref not in seen:
                    seen.add(ref)
                    todo.append(ref)
        return found

    def deepest(self, root: str) -> tuple[int, list[str]]:
        """The stack `root` needs at most, and the path that needs it."""
        memo: dict[str, tuple[int, list[str]]] = {}
        code_taken = {ref for name in self.frames for ref in self.refs.get(name, ()) if ref in self.frames}

        def walk(name: str, stack: list[str]) -> tuple[int, list[str]]:
            if name in memo:
                return memo[name]
            if name in stack:
                raise Recursion(" -> ".join(stack[stack.index(name):] + [name]))
            callees = self.calls.get(name, set())
            if INDIRECT in callees:
                callees = (callees - {INDIRECT}) | (self._pointed(name) or code_taken)
            best: tuple[int, list[str]] = (0, [])
            for callee in sorted(callees):
                if callee not in self.frames:
                    self.unknown.add(callee)
                    continue
                depth = walk(callee, stack + [name])
                if depth[0] > best[0]:
                    best = depth
            memo[name] = (self.frames[name] + best[0], [name] + best[1])
            return memo[name]

        return walk(root, [])


SECTIONS = (".text.", ".rodata.", ".srodata.", ".data.rel.ro.local.", ".data.rel.ro.", ".data.", ".sdata.",
            ".bss.", ".sbss.")


def _base(name: str) -> str:
    """A function's or a table's name from its section's (.text.urwire_decode_message) or its own."""
    for prefix in SECTIONS:
        if name.startswith(prefix):
            return name[len(prefix):]
    return name
