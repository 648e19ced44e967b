#!/usr/bin/env python3
"""upstream-patch.py OUT [EPAN_DIR]: lay out under OUT exactly the files a Wireshark patch adding
the generated dissectors would carry, as they would sit in a Wireshark source tree:

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
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
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


def main() -> int:
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out = Path(sys.argv[1]).resolve()
    epan_dir = Path(sys.argv[2]).resolve() if len(sys.argv) == 3 else None
    files = lay_out(out, epan_dir)
    for path in files:
        print(path.relative_to(out))
    print(f"upstream-patch: {len(files)} files under {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
