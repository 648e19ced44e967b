"""The RTDE golden vectors (tests/golden/rtde/*.yaml, format in its README.md): load them, and run
them through the Python Conversation. The C and Lua tests feed the same cases to their targets."""
from __future__ import annotations

from dataclasses import dataclass
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
    expect: list

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
        cases.append(RtdeCase(path.stem, path, doc["description"], doc.get("protocol"), messages, doc["expect"]))
    return cases


def python_records(case: RtdeCase) -> list:
    """The case through urwire.rtde.Conversation, fed message by message; then closed."""
    from urwire.rtde import Conversation

    conversation = Conversation(protocol=case.protocol)
    records = []
    for from_robot, data in case.messages:
        records += conversation.feed(data, from_robot)
    return records + conversation.close()


__all__ = ["RtdeCase", "rtde_cases", "python_records", "mismatches"]
