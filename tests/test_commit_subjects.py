"""Commit subjects say what changed in at most 72 characters (the why and the figures go in the
body), from the commit that introduced codegen/lang onwards: git log --oneline stays readable."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SINCE_SUBJECT = "codegen/lang: C, Lua and Python spelling in one module each"
LIMIT = 72


def _log() -> list[tuple[str, str]]:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout (an unpacked release has no history)")
    out = subprocess.run(["git", "log", "--format=%h%x09%s"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout
    return [tuple(line.split("\t", 1)) for line in out.splitlines()]


def test_subjects_since_the_rule_fit_72_characters():
    commits = _log()
    subjects = [s for _, s in commits]
    assert SINCE_SUBJECT in subjects, "the commit the rule starts from is not in this history"
    recent = commits[:subjects.index(SINCE_SUBJECT) + 1]
    long = [f"{h} ({len(s)}): {s}" for h, s in recent if len(s) > LIMIT]
    assert not long, "subjects over 72 characters:\n" + "\n".join(long)
