"""Where a record came from: its interface, direction and conversation, in the envelope every record
of a capture comes in (docs/canonical-json.md#records-of-a-capture), and the two ends of a TCP
conversation."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional, Union

FROM_ROBOT, TO_ROBOT = "from_robot", "to_robot"


def _at(address: str, port: int) -> str:
    return f"[{address}]:{port}" if ":" in address else f"{address}:{port}"


class Endpoints(str):
    """The two ends of a TCP conversation, as its records name it: the text
    "<server address>:<port>-<client address>:<port>" (an IPv6 address in brackets), which is what
    the canonical JSON prints and what a filter compares, with each part as an attribute.

    The server is the side that listens on the interface's port: the robot, but on the ROS
    driver's sockets, where the control PC listens and the robot connects (`robot_address` is the
    robot's either way)."""

    server_address: str
    server_port: int
    client_address: str
    client_port: int
    robot_is_client: bool

    def __new__(cls, server_address: str, server_port: int, client_address: str, client_port: int,
                robot_is_client: bool = False) -> "Endpoints":
        self = super().__new__(cls, f"{_at(server_address, server_port)}-{_at(client_address, client_port)}")
        self.server_address, self.server_port = server_address, server_port
        self.client_address, self.client_port = client_address, client_port
        self.robot_is_client = robot_is_client
        return self

    @property
    def robot_address(self) -> str:
        """The robot's address: the server's, or the client's on the driver's sockets."""
        return self.client_address if self.robot_is_client else self.server_address

    def __reduce__(self):
        return Endpoints, (self.server_address, self.server_port, self.client_address, self.client_port,
                           self.robot_is_client)


@dataclass(slots=True)
class Enveloped:
    """A record with where it came from. `record` is what the interface's decoder made (a robot
    state, an RTDE data package, a dashboard reply, an error record, ...).

    In a capture (urwire.decode_capture) `conversation` is the Endpoints of its TCP conversation
    and `capture_time` the time of the frame that completed the record, in seconds since the epoch;
    a record of the capture file itself (a block that cannot be read) has no interface, direction
    or conversation (None). Of two raw streams of one connection (`urwire decode --to-robot`),
    `conversation` is the file the record came from and there is no capture time."""

    interface: Optional[str]        # the interface's name, which is its Wireshark protocol: "ur", "rtde"
    direction: Optional[str]        # FROM_ROBOT or TO_ROBOT
    conversation: Union[Endpoints, str, None]   # Endpoints in a capture, else the file of a raw stream
    record: Any
    capture_time: Optional[float] = None
