"""The envelope of a record from an interface other than the primary one: which interface,
which direction and which conversation it came from (docs/canonical-json.md#records-of-the-other-interfaces)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

FROM_ROBOT, TO_ROBOT = "from_robot", "to_robot"


@dataclass(slots=True)
class Enveloped:
    interface: str           # the interface's name: "ur_realtime"
    direction: str           # FROM_ROBOT or TO_ROBOT
    conversation: str        # "robot address:port-client address:port", or the file of a raw stream
    record: Any
