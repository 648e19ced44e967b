"""The Python package in floors, read from its import graph with `ast` (nothing is imported):

    command   urwire.cli, urwire.__main__            the `urwire` command: may import any floor
    live      urwire.live.*    data   urwire.data.*  the live tools; the data tools: the core only
    core      urwire.*, urwire.generated.*           what `import urwire` gives: imports itself only

No module imports a floor above its own or a floor beside it, no imports go round in a circle, no
module imports urwire code from inside a function (where a circle would hide), and none imports
`*`, hand-written or generated. A function may import only an optional extra (OPTIONAL), so that
`import urwire` and the commands start without it.
"""
from __future__ import annotations

import ast
import dataclasses
import typing
from pathlib import Path

import pytest

import urwire
from urwire.generated import enums, messages

ROOT = Path(__file__).resolve().parents[2]
SOURCES = {"urwire": ROOT / "python" / "urwire",
           "urwire.generated": ROOT / "generated" / "python" / "urwire" / "generated"}

COMMAND = {"urwire.cli", "urwire.__main__"}
EXTENSIONS = {"urwire._ccore"}   # compiled, with no Python source: imports nothing of the package
# Which floors each floor may import.
MAY_IMPORT = {"core": {"core"}, "live": {"core", "live"}, "data": {"core", "data"},
              "command": {"core", "live", "data", "command"}}
# What a function may import when it runs: third-party extras (and a module only some platforms
# have) that the package must start without.
OPTIONAL = {"dpkt", "tqdm", "pyarrow", "pyspark", "matplotlib", "mcap", "websockets", "resource"}


def module_files() -> dict[str, Path]:
    """Every module of the package and its generated subpackage, by dotted name."""
    files = {}
    for package, folder in SOURCES.items():
        for path in sorted(folder.rglob("*.py")):
            parts = list(path.relative_to(folder).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            files[".".join([package, *parts])] = path
    return files


@dataclasses.dataclass(frozen=True)
class Import:
    module: str          # the importing module
    target: str          # what it imports: a module of the package, or another top-level name
    line: int
    in_function: bool
    star: bool


def imports_of(name: str, path: Path, modules: set[str]) -> list[Import]:
    """The imports of one module, each resolved to the package module it loads (a name imported
    from a package is that package's module where it is one) or to a top-level name outside."""
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            inner = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.Import):
                for alias in child.names:
                    found.append(Import(name, alias.name, child.lineno, in_function, False))
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    anchor = package.split(".")[:len(package.split(".")) - child.level + 1]
                    base = ".".join(anchor + ([child.module] if child.module else []))
                for alias in child.names:
                    sub = f"{base}.{alias.name}"
                    target = sub if sub in modules else base
                    found.append(Import(name, target, child.lineno, in_function, alias.name == "*"))
            visit(child, inner)

    visit(tree, False)
    return found


def floor(module: str) -> str:
    if module in COMMAND:
        return "command"
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in ("live", "data") else "core"


FILES = module_files()
MODULES = set(FILES) | EXTENSIONS
IMPORTS = [imp for name, path in FILES.items() for imp in imports_of(name, path, MODULES)]
OWN = [imp for imp in IMPORTS if imp.target.split(".")[0] == "urwire"]


def graph() -> dict[str, set[str]]:
    edges: dict[str, set[str]] = {name: set() for name in MODULES}
    for imp in OWN:
        if imp.target in MODULES:
            edges[imp.module].add(imp.target)
    return edges


def test_the_graph_is_read():
    """The reader finds the package's floors and resolves relative, absolute and submodule imports."""
    assert {"urwire", "urwire.cli", "urwire.framer", "urwire.live.serve", "urwire.data.export",
            "urwire.generated.messages"} <= MODULES
    edges = graph()
    assert "urwire.live.serve" in edges["urwire.cli"] and "urwire.data.spark" in edges["urwire.cli"]
    assert "urwire.framer" in edges["urwire"] and "urwire.generated.messages" in edges["urwire.decoding"]
    assert "urwire.message_kinds" in edges["urwire.generated.messages"]
    assert "urwire.data.dataset" in edges["urwire.data.spark"]       # an absolute import
    assert {floor(m) for m in MODULES} == set(MAY_IMPORT)


def test_no_module_imports_a_floor_above_or_beside_its_own():
    wrong = sorted(f"{imp.module} ({floor(imp.module)}) imports {imp.target} ({floor(imp.target)}), line {imp.line}"
                   for imp in OWN if floor(imp.target) not in MAY_IMPORT[floor(imp.module)])
    assert not wrong, "\n".join(wrong)


def test_every_import_of_the_package_names_one_of_its_modules():
    unknown = sorted(f"{imp.module} line {imp.line}: {imp.target}" for imp in OWN if imp.target not in MODULES)
    assert not unknown, "\n".join(unknown)


def test_no_import_goes_round_in_a_circle():
    edges, circles = graph(), []
    state: dict[str, int] = {}   # 1 on the path being walked, 2 done

    def walk(module: str, path: list[str]) -> None:
        state[module] = 1
        for target in sorted(edges[module]):
            if state.get(target) == 1:
                circles.append(" -> ".join(path[path.index(target):] + [target]))
            elif target not in state:
                walk(target, path + [target])
        state[module] = 2

    for module in sorted(edges):
        if module not in state:
            walk(module, [module])
    assert not circles, "\n".join(circles)


def test_functions_import_only_optional_extras():
    hidden = sorted(f"{imp.module} line {imp.line}: {imp.target}" for imp in IMPORTS
                    if imp.in_function and imp.target.split(".")[0] not in OPTIONAL)
    assert not hidden, "\n".join(hidden)


def test_no_module_imports_star():
    """Each name a module uses is imported by name, in the generated modules too (messages.py
    imports the enum classes its attributes are annotated with), so that what a module offers is
    what it defines or names."""
    assert {"urwire", "urwire.generated.messages", "urwire.generated.enums"} <= set(FILES)
    stars = sorted(f"{imp.module} line {imp.line}: from {imp.target} import *" for imp in IMPORTS if imp.star)
    assert not stars, "\n".join(stars)


def test_every_record_annotation_names_what_its_module_imports():
    """The enum classes the records' attributes are annotated with are imported by name: every
    annotation of generated.messages resolves there (`RobotMode`, `JointModeUpTo1_8`, ...)."""
    classes = [c for c in vars(messages).values()
               if isinstance(c, type) and dataclasses.is_dataclass(c) and c.__module__ == messages.__name__]
    assert len(classes) > 20
    hints = {c.__name__: typing.get_type_hints(c) for c in classes}
    assert enums.RobotMode in typing.get_args(hints["RobotModeData"]["robot_mode"])


@pytest.mark.parametrize("module", [messages, enums], ids=lambda m: m.__name__)
def test_the_package_offers_every_record_class_and_enum(module):
    """`urwire.RobotStateMessage`, `urwire.RobotMode`: each class the spec gives, by name."""
    classes = {n: v for n, v in vars(module).items()
               if isinstance(v, type) and v.__module__ == module.__name__ and not n.startswith("_")}
    assert len(classes) > 20
    missing = sorted(n for n, v in classes.items() if getattr(urwire, n, None) is not v)
    assert not missing, missing
