"""Check that generated/ differs from an earlier revision in comments and layout only.

    python3 scripts/layout_only.py [REV]      # REV defaults to where this branch left main

C: every generated/c/*.c is compiled with -O2 (beside its revision's headers), every
generated/epan/*.c too with the Wireshark include flags (pkg-config wireshark, an empty config.h
as the native build writes one), and both revisions' object files (`objdump -d -s -r`: code, data
and relocations) must be equal. Lua: `luac -l -l` listings of every generated/lua/*.lua, with line
numbers and source names taken out, must be equal. Python: each generated module's syntax tree,
docstrings left out, must be equal. It prints one line per file and exits 1 when any file behaves
differently.
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


def files(rev: str, folder: str, suffix: str) -> list[str]:
    """The files of a generated folder that both this work tree and `rev` have."""
    def listed(*args: str) -> set[str]:
        out = subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        return {p for p in out.split() if p.endswith(suffix)}
    return sorted(listed("ls-files", folder) & listed("ls-tree", "-r", "--name-only", rev, folder))


def wireshark_flags() -> list[str]:
    out = subprocess.run(["pkg-config", "--cflags", "wireshark"], check=True, capture_output=True, text=True).stdout
    return out.split()


def c_object_code(source: Path, flags: list[str]) -> str:
    obj = source.with_suffix(".o")
    # Where a line is, and in which folder, is layout: Wireshark's assertions print both
    # (__LINE__, and __FILE__ named as if both revisions sat in one folder).
    subprocess.run(["gcc", "-std=gnu11", "-O2", *flags, f"-I{source.parent}", f"-ffile-prefix-map={source.parent}=.",
                    "-w", "-D__LINE__=0", "-c", str(source), "-o", str(obj)], check=True)
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


def same_c(rev: str, tmp: Path, folder: str, flags: list[str]) -> bool:
    """Every C file of a folder, each revision's beside that revision's headers."""
    same = True
    for side in ("old", "new"):
        (tmp / side / folder).mkdir(parents=True)
        (tmp / side / folder / "config.h").write_text("/* empty, as out of the Wireshark tree */\n")
        for path in files(rev, folder, ".h"):
            name = Path(path).name
            (tmp / side / folder / name).write_text(old_text(rev, path) if side == "old" else (ROOT / path).read_text())
    for path in files(rev, folder, ".c"):
        name = Path(path).name
        (tmp / "old" / folder / name).write_text(old_text(rev, path))
        shutil.copy(ROOT / path, tmp / "new" / folder / name)
        ok = c_object_code(tmp / "old" / folder / name, flags) == c_object_code(tmp / "new" / folder / name, flags)
        print(f"{path}: object file (gcc -O2) {'same' if ok else 'DIFFERS'}")
        same &= ok
    return same


def main(argv: list[str]) -> int:
    rev = argv[1] if len(argv) > 1 else subprocess.run(["git", "merge-base", "main", "HEAD"], cwd=ROOT, check=True,
                                                       capture_output=True, text=True).stdout.strip()
    same = True
    with tempfile.TemporaryDirectory() as name:
        tmp = Path(name)
        same &= same_c(rev, tmp, "generated/c", [])
        same &= same_c(rev, tmp, "generated/epan", wireshark_flags())
        for path in files(rev, "generated/lua", ".lua"):
            old, new = tmp / "old" / Path(path).name, tmp / "new" / Path(path).name
            old.write_text(old_text(rev, path))
            shutil.copy(ROOT / path, new)
            ok = lua_listing(old) == lua_listing(new)
            print(f"{path}: luac listing {'same' if ok else 'DIFFERS'}")
            same &= ok

    for path in files(rev, "generated/python", ".py"):
        ok = python_tree(old_text(rev, path)) == python_tree((ROOT / path).read_text())
        print(f"{path}: syntax tree without docstrings {'same' if ok else 'DIFFERS'}")
        same &= ok
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
