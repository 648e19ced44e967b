#!/usr/bin/env python3
"""upstream-patch.py OUT [EPAN_DIR] [--against WIRESHARK_SRC --patch FILE]: lay out under OUT exactly
the files a Wireshark patch adding the generated dissectors would carry, as they would sit in a
Wireshark source tree:

    epan/dissectors/packet-*.[ch]   the dissectors and the helpers they share (packet-ur-common.h
                                    and .c), as the patch's own tools/urwire2wireshark.py renders
                                    them (or copied from EPAN_DIR)
    tools/urwire2wireshark.py       regenerates them (dissector/native/urwire2wireshark.py)
    tools/urwire/codegen/           the generator
    tools/urwire/spec/*.yaml        one spec per interface
    tools/urwire/runtime/epan/      the hand-written C the dissectors join in
    tools/urwire/runtime/c/         the C library's runtime files a dissector joins too (lines/match.c)

The dissectors are the generator's upstream copy (python -m codegen --target epan --upstream),
which reads no command line, unlike urwire's own plugin (generated/epan): the runtime files only
urwire's plugin joins (COMMAND_LINE_RUNTIME) stay out of the patch. docs/wireshark-upstream.md says
how the patch fits the tree (the CMakeLists.txt lines it adds, the licence) and what review checks.
OUT is emptied first.

With --against, the patch itself (git's format, binary capture included) against that Wireshark
source tree is written to FILE: the files above, the dissectors' sources in epan/dissectors/
CMakeLists.txt's DISSECTOR_SRC and the shared header in its list of private headers (each in sorted
place, spelled as the list spells its entries), the protocols' words in tools/wireshark_words.txt
(dissector/native/wireshark_words.txt), the cell capture as test/captures/
ur-cell-session.pcapng and its test (dissector/native/suite_dissection_ur.py) at the end of
test/suite_dissection.py. `make upstream-build` applies it (mk/upstream.mk).
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IGNORED = shutil.ignore_patterns("__pycache__", "*.pyc")
# Read tshark's command line (a speed workaround for tshark -T fields): urwire's plugin only.
COMMAND_LINE_RUNTIME = ("tshark_fields.c", "ur_wanted.c")


def lay_out_tools(out: Path) -> None:
    tools = out / "tools"
    generator = tools / "urwire"
    shutil.copytree(ROOT / "codegen", generator / "codegen", ignore=IGNORED)
    (generator / "spec").mkdir(parents=True)
    for spec in sorted((ROOT / "spec").glob("*.yaml")):
        shutil.copy(spec, generator / "spec" / spec.name)
    if (ROOT / "runtime" / "epan").is_dir():
        shutil.copytree(ROOT / "runtime" / "epan", generator / "runtime" / "epan",
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc", *COMMAND_LINE_RUNTIME))
    # The C library's runtime files a dissector joins too (where the rule is the same: the lines
    # matcher), as its sections name them.
    for name in sorted({n for p in (ROOT / "generated" / "epan").glob("packet-*.c")
                        for n in re.findall(r"^/\* ---- runtime/c/(\S+) ---- \*/$", p.read_text(), re.M)}):
        (generator / "runtime" / "c" / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(ROOT / "runtime" / "c" / name, generator / "runtime" / "c" / name)
    shutil.copy(ROOT / "dissector" / "native" / "urwire2wireshark.py", tools / "urwire2wireshark.py")


def copy_dissectors(epan_dir: Path, dissectors: Path) -> None:
    sources = sorted(epan_dir.glob("packet-*.[ch]"))
    if not sources:
        sys.exit(f"upstream-patch: no packet-*.c under {epan_dir}")
    for source in sources:
        shutil.copy(source, dissectors / source.name)


def render_dissectors(out: Path) -> None:
    """The patch's tools/urwire2wireshark.py writes them, from the patch's generator and runtime."""
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "1"}     # no __pycache__ left in the patch
    result = subprocess.run([sys.executable, str(out / "tools" / "urwire2wireshark.py")], capture_output=True,
                            text=True, env=env)
    if result.returncode != 0:
        sys.exit(f"upstream-patch: tools/urwire2wireshark.py failed:\n{result.stdout}{result.stderr}")


def lay_out(out: Path, epan_dir: Path | None) -> list[Path]:
    shutil.rmtree(out, ignore_errors=True)
    dissectors = out / "epan" / "dissectors"
    dissectors.mkdir(parents=True)
    lay_out_tools(out)
    if epan_dir is None:
        render_dissectors(out)
    else:
        copy_dissectors(epan_dir, dissectors)
    return sorted(p for p in out.rglob("*") if p.is_file())


# ---- the patch against a Wireshark source tree ----

CMAKELISTS = "epan/dissectors/CMakeLists.txt"
SUITE = "test/suite_dissection.py"
CAPTURE = ROOT / "dissector" / "samples" / "cell_session.pcapng"
TREE_CAPTURE = "test/captures/ur-cell-session.pcapng"
SUITE_PART = ROOT / "dissector" / "native" / "suite_dissection_ur.py"
SOURCE_LIST = "DISSECTOR_SRC"
WORDS = "tools/wireshark_words.txt"
OUR_WORDS = ROOT / "dissector" / "native" / "wireshark_words.txt"
# A header that exports nothing is private: DISSECTOR_PUBLIC_HEADERS holds only the headers
# tools/generate-dissector-lists.py finds exporting something (WS_DLL_PUBLIC).
PRIVATE_HEADER_LISTS = ("DISSECTOR_HEADERS", "DISSECTOR_PRIVATE_HEADERS")


def cmake_list(text: str, name: str) -> tuple[int, int] | None:
    """The lines [first entry, closing parenthesis) of `set(name` in a CMakeLists.txt, or None."""
    lines = text.split("\n")
    for at, line in enumerate(lines):
        if re.match(rf"^\s*set\s*\(\s*{name}\s*$", line):
            end = next(i for i in range(at + 1, len(lines)) if re.match(r"^\s*\)", lines[i]))
            return at + 1, end
    return None


def into_list(text: str, name: str, files: list[str]) -> str:
    """`files` added to the CMake list `name` where the sorted order puts them (case folded, as
    generate-dissector-lists.py sorts), each spelled as the list's packet-* entries are."""
    found = cmake_list(text, name)
    if found is None:
        sys.exit(f"upstream-patch: no set({name} in {CMAKELISTS}")
    lines = text.split("\n")
    first, end = found
    entry = re.compile(r"^(\s*\S*?)((?:packet|file)-[^/\s]+)\s*$")
    names = {i: m.group(2) for i in range(first, end) if (m := entry.match(lines[i]))}
    if not names:
        sys.exit(f"upstream-patch: set({name} in {CMAKELISTS} has no packet-* entry to spell ours after")
    prefix = entry.match(lines[min(names)]).group(1)
    for file in sorted(set(files) - set(names.values()), key=str.lower):
        at = min((i for i, n in names.items() if n.lower() > file.lower()), default=end)
        lines.insert(at, prefix + file)
        names = {(i + 1 if i >= at else i): n for i, n in names.items()} | {at: file}
        end += 1
    return "\n".join(lines)


def our_words() -> list[str]:
    """The protocols' words Wireshark's spelling check must know (dissector/native/wireshark_words.txt)."""
    return [w for w in OUR_WORDS.read_text(encoding="utf-8").split("\n") if w and not w.startswith("#")]


def with_our_words(words: str) -> str:
    """A tools/wireshark_words.txt with each of ours it lacks inserted before the first word that
    sorts after it; its own lines stay as they are."""
    lines = words.rstrip("\n").split("\n")
    for word in sorted(set(our_words()) - set(lines)):
        at = next((i for i, line in enumerate(lines) if line > word), len(lines))
        lines.insert(at, word)
    return "\n".join(lines) + "\n"


def tree_edits(tree: Path, dissectors: list[str]) -> dict[str, bytes]:
    """The tree's files the patch changes or adds beside the laid-out ones, as it leaves them."""
    cmake = (tree / CMAKELISTS).read_text(encoding="utf-8")
    cmake = into_list(cmake, SOURCE_LIST, [n for n in dissectors if n.endswith(".c")])
    headers = [n for n in dissectors if n.endswith(".h")]
    private = next((name for name in PRIVATE_HEADER_LISTS if cmake_list(cmake, name)), None)
    if headers and private:
        cmake = into_list(cmake, private, headers)
    elif headers:
        print(f"upstream-patch: {CMAKELISTS} has no list of private headers ({', '.join(PRIVATE_HEADER_LISTS)}):"
              f" {', '.join(headers)} listed nowhere, as the tree's other private headers", file=sys.stderr)
    suite = (tree / SUITE).read_text(encoding="utf-8")
    if not re.search(r"^import subprocess$", suite, re.M):
        sys.exit(f"upstream-patch: {SUITE} does not import subprocess, as the test it is given needs")
    part = SUITE_PART.read_text(encoding="utf-8")
    if part.strip() not in suite:
        suite = suite.rstrip("\n") + "\n" + part
    edits = {CMAKELISTS: cmake.encode(), SUITE: suite.encode(), TREE_CAPTURE: CAPTURE.read_bytes()}
    if (tree / WORDS).is_file():
        edits[WORDS] = with_our_words((tree / WORDS).read_text(encoding="utf-8")).encode()
    return edits


def write_patch(out: Path, tree: Path, patch: Path) -> None:
    """The laid-out files and the tree's edits as one patch (git diff --binary) against `tree`."""
    added = {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}
    clashes = [name for name in added if (tree / name).exists()]
    if clashes:
        sys.exit(f"upstream-patch: {tree} has {', '.join(clashes[:3])} already: the patch adds them")
    dissectors = [Path(name).name for name in added if name.startswith("epan/dissectors/")]
    changed = {**added, **tree_edits(tree, dissectors)}
    git = ["git", "-c", "user.name=urwire", "-c", "user.email=dev@urwire.invalid", "-c", "core.autocrlf=false"]
    with tempfile.TemporaryDirectory() as work:
        repo = Path(work)
        subprocess.run([*git, "init", "-q", str(repo)], check=True)
        for name in (n for n in (CMAKELISTS, SUITE, WORDS) if (tree / n).is_file()):
            (repo / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(tree / name, repo / name)
        subprocess.run([*git, "-C", str(repo), "add", "-A"], check=True)
        subprocess.run([*git, "-C", str(repo), "commit", "-qm", "tree"], check=True)
        for name, data in changed.items():
            (repo / name).parent.mkdir(parents=True, exist_ok=True)
            (repo / name).write_bytes(data)
        subprocess.run([*git, "-C", str(repo), "add", "-A"], check=True)
        diff = subprocess.run([*git, "-C", str(repo), "diff", "--cached", "--binary"], check=True,
                              capture_output=True).stdout
    patch.parent.mkdir(parents=True, exist_ok=True)
    patch.write_bytes(diff)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", type=Path)
    parser.add_argument("epan_dir", type=Path, nargs="?")
    parser.add_argument("--against", type=Path, metavar="WIRESHARK_SRC", help="a Wireshark source tree")
    parser.add_argument("--patch", type=Path, metavar="FILE", help="with --against: where the patch goes")
    args = parser.parse_args()
    if bool(args.against) != bool(args.patch):
        parser.error("--against and --patch go together")
    out = args.out.resolve()
    files = lay_out(out, args.epan_dir.resolve() if args.epan_dir else None)
    for path in files:
        print(path.relative_to(out))
    print(f"upstream-patch: {len(files)} files under {out}")
    if args.against:
        write_patch(out, args.against.resolve(), args.patch.resolve())
        print(f"upstream-patch: the patch against {args.against} is {args.patch}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
