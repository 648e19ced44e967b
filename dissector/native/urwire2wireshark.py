#!/usr/bin/env python3
"""urwire2wireshark.py: writes Wireshark's dissectors of the interfaces of a Universal Robots cell
(epan/dissectors/packet-ur.c, packet-rtde.c, packet-ur-realtime.c, ..., and the helpers they share,
packet-ur-common.h and packet-ur-common.c) from their specs.

In a Wireshark source tree this file is tools/urwire2wireshark.py, beside the generator it runs
(tools/urwire/: the codegen package, one YAML spec per interface under spec/, and the hand-written
C every dissector joins in, runtime/epan/). The generated files say at their top that they are
generated and must not be edited by hand; change a spec or the generator, then run

    python3 tools/urwire2wireshark.py            # rewrite epan/dissectors/packet-*.[ch]
    python3 tools/urwire2wireshark.py --check    # exit 1 if they are not what the specs give

It runs the generator's epan target with --upstream: the copy of the dissectors for Wireshark's
tree, which reads no command line (urwire's own plugin reads tshark's to build less for a `tshark
-T fields` run; here such a run builds the whole tree, as for any other dissector). It needs
Python 3.10 or later with PyYAML, Jinja2 and jsonschema. The generator comes from the urwire
project, where the same specs also give Lua dissectors and C and Python decoders.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

TOOLS = Path(__file__).resolve().parent
GENERATOR = TOOLS / "urwire"
DISSECTORS = TOOLS.parent / "epan" / "dissectors"


def generated(folder: Path) -> dict[str, bytes]:
    """The generator's epan target, Wireshark's copy, written into `folder`: {file name: its bytes}."""
    result = subprocess.run([sys.executable, "-m", "codegen", "--target", "epan", "--upstream", "--out", str(folder)],
                            cwd=GENERATOR, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"urwire2wireshark: the generator failed:\n{result.stderr}")
    return {p.name: p.read_bytes() for p in sorted((folder / "epan").glob("packet-*.[ch]"))}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=DISSECTORS, help="where the packet-*.[ch] go (epan/dissectors)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if a file differs")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        files = generated(Path(tmp))
    stale = [name for name, text in files.items()
             if not (args.out / name).is_file() or (args.out / name).read_bytes() != text]
    if args.check:
        for name in stale:
            print(f"urwire2wireshark: {args.out / name} is not what the specs give", file=sys.stderr)
        return 1 if stale else 0
    for name in stale:
        (args.out / name).write_bytes(files[name])
        print(f"urwire2wireshark: wrote {args.out / name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
