"""Loader for the golden vectors of the interfaces other than the primary one:
``golden/<interface>/*.yaml``, one case per file, hand-made from the documents.

A case is a conversation: ``segments``, each ``{from: robot|client|pc, hex: ...}`` (``pc``: the
control PC of the ROS driver's sockets, where the robot is the client) (hex annotated
line by line, ``#`` comments dropped), fed in order; an optional quoted ``version`` (the
software version known at the start); and ``expect``, the canonical JSON records in the order
the segments give them (a full match). Every target (Python, C, Lua) runs every case.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import yaml

from tests.vectors import GOLDEN_DIR, VectorError, parse_hex


@dataclass(frozen=True)
class Segment:
    from_robot: bool
    data: bytes


@dataclass(frozen=True)
class ConversationCase:
    name: str
    path: Path
    segments: tuple[Segment, ...]
    version: str | None
    expect: list


def _segment(raw: object, path: Path) -> Segment:
    if not isinstance(raw, dict) or raw.get("from") not in ("robot", "client", "pc") or "hex" not in raw:
        raise VectorError(f"{path}: a segment is {{from: robot|client|pc, hex: ...}}, not {raw!r}")
    return Segment(raw["from"] == "robot", parse_hex(raw["hex"], path))


def conversation_cases(interface: str) -> list[ConversationCase]:
    cases = []
    for path in sorted((GOLDEN_DIR / interface).glob("*.yaml")):
        doc = yaml.safe_load(path.read_text(encoding="utf-8"))
        version = doc.get("version")
        if version is not None and not isinstance(version, str):
            raise VectorError(f"{path}: version must be a quoted string, got {version!r}")
        if not isinstance(doc.get("expect"), list):
            raise VectorError(f"{path}: 'expect' must be a list of records")
        segments = tuple(_segment(raw, path) for raw in doc.get("segments", []))
        cases.append(ConversationCase(path.stem, path, segments, version, doc["expect"]))
    if not cases:
        raise VectorError(f"no vectors under {GOLDEN_DIR / interface}")
    return cases


def bytewise(segments: tuple[Segment, ...]) -> tuple[Segment, ...]:
    """The same conversation, one byte per segment: every line split at every byte."""
    return tuple(Segment(s.from_robot, s.data[i:i + 1]) for s in segments for i in range(len(s.data)))
