#!/usr/bin/env python3
"""upstream-patch.py OUT [EPAN_DIR]: lay out under OUT exactly the files a Wireshark patch adding
the generated dissectors would carry, as they would sit in a Wireshark source tree:

    epan/dissectors/packet-*.c      the generated dissectors (generated/epan, or EPAN_DIR)
    tools/urwire2wireshark.py       regenerates them (dissector/native/urwire2wireshark.py)
    tools/urwire/codegen/           the generator
    tools/urwire/spec/*.yaml        one spec per interface
    tools/urwire/runtime/epan/      the hand-written C the dissectors join in

docs/wireshark-upstream.md says how the patch fits the tree (the CMakeLists.txt lines it adds,
the licence) and what review checks. OUT is emptied first.
"""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IGNORED = shutil.ignore_patterns("__pycache__", "*.pyc")


def lay_out(out: Path, epan_dir: Path) -> list[Path]:
    sources = sorted(epan_dir.glob("packet-*.c"))
    if not sources:
        sys.exit(f"upstream-patch: no packet-*.c under {epan_dir} (make generate)")
    shutil.rmtree(out, ignore_errors=True)
    dissectors = out / "epan" / "dissectors"
    dissectors.mkdir(parents=True)
    for source in sources:
        shutil.copy(source, dissectors / source.name)
    tools = out / "tools"
    generator = tools / "urwire"
    shutil.copytree(ROOT / "codegen", generator / "codegen", ignore=IGNORED)
    (generator / "spec").mkdir(parents=True)
    for spec in sorted((ROOT / "spec").glob("*.yaml")):
        shutil.copy(spec, generator / "spec" / spec.name)
    if (ROOT / "runtime" / "epan").is_dir():
        shutil.copytree(ROOT / "runtime" / "epan", generator / "runtime" / "epan", ignore=IGNORED)
    shutil.copy(ROOT / "dissector" / "native" / "urwire2wireshark.py", tools / "urwire2wireshark.py")
    return sorted(p for p in out.rglob("*") if p.is_file())


def main() -> int:
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out = Path(sys.argv[1]).resolve()
    epan_dir = Path(sys.argv[2]).resolve() if len(sys.argv) == 3 else ROOT / "generated" / "epan"
    files = lay_out(out, epan_dir)
    for path in files:
        print(path.relative_to(out))
    print(f"upstream-patch: {len(files)} files under {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
