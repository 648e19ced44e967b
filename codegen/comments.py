"""What the generated code's API comments say, in every target (C comments, Lua blurbs, Python
docstrings): the user-facing text of a spec node, never its `field_note:`.

A user reads a field's label and unit, what it means (`doc:`) and which software versions send
it. The spec's `field_note:` holds research notes (sources, line numbers, confidence): those
belong to docs/ (docs/protocol.md, docs/firmware-history.md), not to an API."""
from __future__ import annotations

import re
from typing import Sequence

from . import ir


def _words(text: str) -> str:
    return re.sub(r"[^a-z0-9]+", " ", text.lower()).strip()


def repeats(label: str, doc: str) -> bool:
    """True when a doc says no more than the label ("Safety mode." under "Safety mode")."""
    return bool(doc) and _words(doc) == _words(label)


def node_text(node) -> str:
    """A layout's, message's or enum's doc: what it is, for a user."""
    return node.doc.strip()


def field_text(entries: Sequence[ir.Field], versions: bool = True) -> str:
    """A field's comment: its label and unit, then its docs (each once, none that repeats the
    label), then the versions that send it when not every version does. `entries` are the
    field's entries in one layout (a field whose wire type changed has one per range)."""
    first = entries[0]
    parts = [f"{first.titled}."]
    for doc in dict.fromkeys(e.doc.strip() for e in entries):
        if doc and not repeats(first.label, doc):
            parts.append(doc if doc.endswith((".", "!", "?", '"', ")")) else doc + ".")
    if versions and not any(e.versions.unbounded for e in entries):
        parts.append(f"Sent by software {_ranges(entries)}.")
    return " ".join(parts)


def _ranges(entries: Sequence[ir.Field]) -> str:
    """"3.0 and later"; for entries of several wire types, each range with its type:
    "up to 1.8 (int16), and 3.0 and later (int32)"."""
    types = {getattr(e, "scalar", None) for e in entries}
    texts = [e.versions.describe() + (f" ({e.scalar.name})" if len(types) > 1 else "") for e in entries]
    return texts[0] if len(texts) == 1 else ", ".join(texts[:-1]) + ", and " + texts[-1]


def value_text(v: ir.EnumValue) -> str:
    """An enum member's comment: its doc, whether UR's tables lack it, the versions that send it."""
    return " ".join(t for t in (v.doc.strip(), "(undocumented)" if v.undocumented else "",
                                "" if v.versions.unbounded else f"(software {v.versions.describe()})") if t)
