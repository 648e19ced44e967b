"""A field's description in the dissectors (its blurb: `tshark -G fields`, the display-filter
dialog, the status bar): one rule for every kind, so that no hf entry and no ProtoField goes
without one. The spec's doc where it has one, else what the spec knows of the field: its label,
then its unit, the meaning of its bit or enum, and the versions that send it."""
from __future__ import annotations

from typing import Optional

from . import view


def one_line(*texts: Optional[str]) -> str:
    """Texts joined into one line (view.one_line), kept as they are: a blurb is always a quoted literal."""
    return view.one_line(*(t or "" for t in texts), quote="")


def sentence(text: str) -> str:
    """A text as a sentence: a full stop last (its first word is kept: it may be an identifier)."""
    text = text.strip()
    return text if not text or text[-1] in ".!?" else text + "."


def blurb(doc: str, label: str, unit: Optional[str] = None, meaning: str = "", sent: str = "") -> str:
    """`doc` if the spec gives one, else `label`; then `unit`, `meaning` (what a bit or a code
    says) and `sent` ("3.0 and later": the versions that send it, empty for all)."""
    return one_line(sentence(doc) if doc else sentence(label), f"In {unit}." if unit else "",
                    sentence(meaning) if meaning else "", f"Sent by software {sent}." if sent else "")
