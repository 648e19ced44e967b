"""The whole urwire package of a git revision (python/urwire with its generated subpackage),
unpacked for a benchmark to run it beside this tree's."""
from __future__ import annotations

import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def unpack_package(revision: str, root: Path) -> Path:
    """python/urwire and its generated subpackage of `revision`, as root/urwire (unpacked once)."""
    if not (root / "urwire" / "generated" / "__init__.py").is_file():
        root.mkdir(parents=True, exist_ok=True)
        for folder, strip in (("python/urwire", 1), ("generated/python/urwire/generated", 2)):
            archive = subprocess.run(["git", "-C", str(ROOT), "archive", revision, folder], capture_output=True,
                                     check=True)
            subprocess.run(["tar", "-x", f"--strip-components={strip}", "-C", str(root)], input=archive.stdout,
                           check=True)
    return root
