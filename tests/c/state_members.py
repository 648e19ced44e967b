"""Writes state_members.h for tests/c/driver.c: STATE_MEMBERS(X), X(layout constant, member) for
every member of urwire_robot_state, read from a generated urwire.h (a member is named as its
layout). With it the driver sets each member of a robot state beside the package that the
iterator read, and checks that the one-pass decoder filled it alike.

    python3 tests/c/state_members.py generated/c/urwire.h OUT_FOLDER
"""
from __future__ import annotations

import re
import sys
from pathlib import Path


def write(header: Path, folder: Path) -> Path:
    """state_members.h in folder, from header; the folder (for -I)."""
    text = header.read_text()
    struct = text[text.index("typedef struct urwire_robot_state {"):]
    struct = struct[:struct.index("} urwire_robot_state;")]
    members = [member for kind, member in re.findall(r"^\s+urwire_(\w+) (\w+);", struct, re.M) if kind == member]
    lines = " \\\n".join(f"    X(URWIRE_LAYOUT_{member.upper()}, {member})" for member in members)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "state_members.h").write_text(
        f"/* Written by tests/c/state_members.py from {header.name}. */\n#define STATE_MEMBERS(X) \\\n{lines}\n")
    return folder


if __name__ == "__main__":
    write(Path(sys.argv[1]), Path(sys.argv[2]))
