"""Check that generated/ differs from an earlier revision in comments and layout only.

    python3 scripts/layout_only.py [REV]      # REV defaults to where this branch left main

C: both revisions' generated/c/*.c, and generated/epan/*.c against Wireshark's headers
(`pkg-config --cflags wireshark`, as the native plugin builds), are compiled with -O2 and their
object files (`objdump -d -s -r`: code, data and relocations) must be equal. Lua: the
`luac -l -l` listings of both revisions' generated/lua/*.lua, with line numbers and source names
taken out, must be equal. Python: each generated module's syntax tree, docstrings left out, must
be equal. It prints one line per file and exits 1 when any file behaves differently.
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


def python_modules(rev: str) -> list[str]:
    """The generated Python modules that both this work tree and `rev` have."""
    def listed(*args: str) -> set[str]:
        out = subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        return {p for p in out.split() if p.endswith(".py")}
    return sorted(listed("ls-files", "generated/python") & listed("ls-tree", "-r", "--name-only", rev, "generated/python"))


def c_object_code(source_dir: Path, name: str = "urwire.c", flags: tuple[str, ...] = ()) -> str:
    obj = source_dir / (name + ".o")
    # Where a line is, and in which folder, is layout: assertions print both (__LINE__, __FILE__).
    where = ["-w", "-D__LINE__=0", f'-D__FILE__="{name}"']
    subprocess.run(["gcc", "-std=c99", "-O2", *flags, *where, "-c", str(source_dir / name), "-o", str(obj)],
                   check=True)
    # Code (-d), every section's bytes (-s: the tables are data) and the relocations (-r: what
    # the tables' pointers point at).
    listing = subprocess.run(["objdump", "-d", "-s", "-r", "--no-show-raw-insn", str(obj)], check=True,
                             capture_output=True, text=True).stdout
    return listing.split("\n", 2)[2]   # past the line that names the object file


def wireshark_flags() -> list[str]:
    """What the native plugin compiles its dissectors with (Wireshark's and GLib's headers)."""
    flags = subprocess.run(["pkg-config", "--cflags", "wireshark"], check=True, capture_output=True, text=True)
    return ["-std=gnu11", *flags.stdout.split(), "-I/usr/include/wireshark/epan/dissectors"]


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
        for folder, flags in (("c", ()), ("epan", tuple(wireshark_flags()))):
            names = sorted(p.name for p in (ROOT / "generated" / folder).iterdir())
            (old / "config.h").write_text("")   # empty out of Wireshark's tree (dissector/native)
            (new / "config.h").write_text("")
            for name in names:
                (old / name).write_text(old_text(rev, f"generated/{folder}/{name}"))
                shutil.copy(ROOT / "generated" / folder / name, new / name)
            for name in (n for n in names if n.endswith(".c")):
                ok = c_object_code(old, name, flags) == c_object_code(new, name, flags)
                print(f"generated/{folder}/{name}: object file (gcc -O2) {'same' if ok else 'DIFFERS'}")
                same &= ok

        for path in sorted((ROOT / "generated" / "lua").glob("*.lua")):
            (old / path.name).write_text(old_text(rev, f"generated/lua/{path.name}"))
            shutil.copy(path, new / path.name)
            ok = lua_listing(old / path.name) == lua_listing(new / path.name)
            print(f"generated/lua/{path.name}: luac listing {'same' if ok else 'DIFFERS'}")
            same &= ok

    for path in python_modules(rev):
        ok = python_tree(old_text(rev, path)) == python_tree((ROOT / path).read_text())
        print(f"{path}: syntax tree without docstrings {'same' if ok else 'DIFFERS'}")
        same &= ok
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
