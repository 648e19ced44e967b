"""The pictures of dissector/README.md (`make screenshots`, scripts/screenshots.py): each one the
script takes is committed and shown in the README, and the rows each tree picture opens and selects
are still in the tree tshark prints of its frame (a renamed label would make the script walk to
another row, or fail)."""
from __future__ import annotations

import importlib.util
import re
import sys

import pytest

from tests.lua.harness import ROOT

IMAGES = ROOT / "dissector" / "images"
README = ROOT / "dissector" / "README.md"


def load_script():
    spec = importlib.util.spec_from_file_location("screenshots", ROOT / "scripts" / "screenshots.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module      # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


SCRIPT = load_script()


def test_every_picture_is_committed_and_shown():
    shown = set(re.findall(r"!\[[^\]]*\]\(images/([^)]+)\)", README.read_text(encoding="utf-8")))
    taken = set(SCRIPT.SHOTS)
    assert taken == shown
    assert taken == {p.name for p in IMAGES.glob("*.png")}


@pytest.mark.parametrize("shot", SCRIPT.TREE_SHOTS, ids=lambda s: s.image)
def test_the_rows_a_picture_opens_are_in_its_frame(shot):
    pane, keys = SCRIPT.walk(shot)       # LookupError: a row is gone; ValueError: its parent is shut
    assert pane.shown[pane.at].text.startswith(shot.select[-1])
    assert keys[0] == "Home" and len(keys) < 200
