"""Check that generated/ differs from an earlier revision in comments and layout only.

    python3 scripts/layout_only.py [REV]      # REV defaults to where this branch left main

C: both revisions' urwire.c are compiled with -O2 and their object files (`objdump -d -s -r`:
code, data and relocations) must be equal. Lua: `luac -l -l` listings of each generated/lua/*.lua
that both revisions have, with line numbers and source names taken out, must be equal. Python: each generated module's syntax tree, docstrings left out, must be
equal. It prints one line per file and exits 1 when any file behaves differently.
"""
from __future__ import annotations

import ast
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def old_text(rev: str, path: str) -> str:
    return subprocess.run(["git", "show", f"{rev}:{path}"], cwd=ROOT, check=True,
                          capture_output=True, text=True).stdout


def generated_files(rev: str, folder: str, suffix: str) -> list[str]:
    """The generated files of `folder` ending in `suffix` that both this work tree and `rev` have."""
    def listed(*args: str) -> set[str]:
        out = subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        return {p for p in out.split() if p.endswith(suffix)}
    return sorted(listed("ls-files", folder) & listed("ls-tree", "-r", "--name-only", rev, folder))


def python_modules(rev: str) -> list[str]:
    """The generated Python modules that both this work tree and `rev` have."""
    return generated_files(rev, "generated/python", ".py")


def c_object_code(source_dir: Path) -> str:
    obj = source_dir / "urwire.o"
    subprocess.run(["gcc", "-std=c99", "-O2", "-c", str(source_dir / "urwire.c"), "-o", str(obj)], check=True)
    # Code (-d), every section's bytes (-s: the tables are data) and the relocations (-r: what
    # the tables' pointers point at).
    listing = subprocess.run(["objdump", "-d", "-s", "-r", "--no-show-raw-insn", str(obj)], check=True,
                             capture_output=True, text=True).stdout
    return listing.split("\n", 2)[2]   # past the line that names the object file


def lua_listing(source: Path) -> str:
    listing = subprocess.run(["luac5.4", "-p", "-l", "-l", str(source)], check=True,
                             capture_output=True, text=True).stdout
    listing = re.sub(r"<[^>]*:\d+,\d+>", "<function>", listing)   # where each function starts
    listing = re.sub(r"0x[0-9a-f]+", "0x?", listing)   # addresses in memory
    listing = re.sub(r"^(\s*\d+\s+)\[\d+\]", r"\1", listing, flags=re.M)   # each instruction's line
    return listing


class _NoDocstrings(ast.NodeTransformer):
    def _strip(self, node):
        self.generic_visit(node)
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str):
            node.body = body[1:] or [ast.Pass()]
        # An attribute's docstring (a string statement after it) is documentation too.
        node.body = [s for s in node.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant)
                                                 and isinstance(s.value.value, str))] or [ast.Pass()]
        return node

    visit_Module = visit_ClassDef = visit_FunctionDef = visit_AsyncFunctionDef = _strip


def python_tree(text: str) -> str:
    return ast.dump(_NoDocstrings().visit(ast.parse(text)))


def main(argv: list[str]) -> int:
    rev = argv[1] if len(argv) > 1 else subprocess.run(["git", "merge-base", "main", "HEAD"], cwd=ROOT, check=True,
                                                       capture_output=True, text=True).stdout.strip()
    same = True
    with tempfile.TemporaryDirectory() as tmp:
        old, new = Path(tmp, "old"), Path(tmp, "new")
        for d in (old, new):
            d.mkdir()
        for name in ("urwire.c", "urwire.h"):
            (old / name).write_text(old_text(rev, f"generated/c/{name}"))
            shutil.copy(ROOT / "generated/c" / name, new / name)
        ok = c_object_code(old) == c_object_code(new)
        print(f"generated/c/urwire.c: object file (gcc -O2) {'same' if ok else 'DIFFERS'}")
        same &= ok

        for path in generated_files(rev, "generated/lua", ".lua"):
            name = Path(path).name
            (old / name).write_text(old_text(rev, path))
            shutil.copy(ROOT / path, new / name)
            ok = lua_listing(old / name) == lua_listing(new / name)
            print(f"{path}: luac listing {'same' if ok else 'DIFFERS'}")
            same &= ok

    for path in python_modules(rev):
        ok = python_tree(old_text(rev, path)) == python_tree((ROOT / path).read_text())
        print(f"{path}: syntax tree without docstrings {'same' if ok else 'DIFFERS'}")
        same &= ok
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
