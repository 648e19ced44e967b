"""The RTDE golden vectors (tests/golden/rtde/*.yaml, format in its README.md): load them, and run
them through the Python Conversation. The C and Lua tests feed the same cases to their targets."""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import yaml

from tests.vectors import mismatches, parse_hex

RTDE_DIR = Path(__file__).resolve().parent / "golden" / "rtde"


@dataclass
class RtdeCase:
    name: str
    path: Path
    description: str
    protocol: Optional[int]
    messages: list[tuple[bool, bytes]]     # (from the robot, bytes), in the order they crossed
    expect: list                           # records; one whose JSON repeats a key: as shown_as() parses it
    exact: dict = field(default_factory=dict)   # index in expect -> the record's exact JSON line

    @property
    def robot_bytes(self) -> bytes:
        return b"".join(data for from_robot, data in self.messages if from_robot)

    @property
    def client_bytes(self) -> bytes:
        return b"".join(data for from_robot, data in self.messages if not from_robot)


def rtde_cases() -> list[RtdeCase]:
    cases = []
    for path in sorted(RTDE_DIR.glob("*.yaml")):
        doc = yaml.safe_load(path.read_text(encoding="utf-8"))
        messages = []
        for i, m in enumerate(doc["messages"]):
            if m["from"] not in ("robot", "client"):
                raise ValueError(f"{path.name}: messages[{i}].from is robot or client")
            messages.append((m["from"] == "robot", parse_hex(m["hex"], f"{path.name} messages[{i}]")))
        expect, exact = [], {}
        for i, record in enumerate(doc["expect"]):
            if isinstance(record, str):      # the exact line of a record that repeats a key
                exact[i] = record
                record = shown_as(record)
            expect.append(record)
        cases.append(RtdeCase(path.stem, path, doc["description"], doc.get("protocol"), messages, expect, exact))
    return cases


def shown_as(line: str) -> dict:
    """A JSON line as a dict in which a key that comes more than once (a variable a recipe names
    twice) holds the list of its values, in order: as tshark's -T json lists a field shown twice."""
    def pairs(items):
        out: dict = {}
        for key, value in items:
            if key in out:
                out[key] = (out[key] if isinstance(out[key], _Repeated) else _Repeated([out[key]])) + [value]
            else:
                out[key] = value
        return {k: list(v) if isinstance(v, _Repeated) else v for k, v in out.items()}
    return json.loads(line, object_pairs_hook=pairs)


class _Repeated(list):
    """The values of a key seen more than once."""

    def __add__(self, other):
        return _Repeated(list(self) + list(other))


def python_records(case: RtdeCase) -> list:
    """The case through urwire.rtde.Conversation, fed message by message; then closed."""
    from urwire.rtde import Conversation

    conversation = Conversation(protocol=case.protocol)
    records = []
    for from_robot, data in case.messages:
        records += conversation.feed(data, from_robot)
    return records + conversation.close()


__all__ = ["RtdeCase", "rtde_cases", "python_records", "mismatches", "shown_as"]
