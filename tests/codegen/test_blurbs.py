"""Every field of the native dissectors has a description (its blurb: `tshark -G fields`, the
display-filter dialog), from the spec's doc or built from what the spec knows of the field
(codegen/blurbs.py); Wireshark's reviewers ask for one, and NULL shows nothing."""
from __future__ import annotations

import re
from pathlib import Path

from codegen.blurbs import blurb
from codegen.epan_c import SHARED_STEM

EPAN = Path(__file__).resolve().parents[2] / "generated" / "epan"
# An hf_register_info entry's last two members: its blurb (a literal, adjacent literals, or NULL)
# and HFILL.
BLURB = re.compile(r'(NULL|"(?:[^"\\]|\\.)*"(?:\s*"(?:[^"\\]|\\.)*")*)\s*,\s*HFILL')


def entries(path: Path) -> list[str]:
    return BLURB.findall(path.read_text(encoding="utf-8"))


def test_every_generated_hf_entry_has_a_blurb():
    files = sorted(p for p in EPAN.glob("packet-*.c") if p.stem != SHARED_STEM)    # the helpers register no field
    assert files
    counted = {p.name: entries(p) for p in files}
    assert all(counted.values()), [name for name, found in counted.items() if not found]
    missing = {name: sum(b == "NULL" for b in found) for name, found in counted.items()}
    assert not any(missing.values()), missing


def test_a_blurb_takes_the_doc_else_the_label():
    assert blurb("Time elapsed since start", "Time", "s") == "Time elapsed since start. In s."
    assert blurb("", "Robot mode", meaning="Robot mode codes, as from 3.0") == "Robot mode. Robot mode codes, as from 3.0."
    assert blurb("Speed.", "Speed", sent="3.0 and later") == "Speed. Sent by software 3.0 and later."
