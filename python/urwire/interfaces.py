"""The interfaces of a UR cell that urwire reads, and the ports they listen on.

Each interface decodes one TCP conversation at a time through a `Conversation`: bytes go in per
direction as they arrive, records come out in order. The capture reader and `urwire decode
--protocol NAME` pick the interface of a conversation from this table, so adding an interface is
adding its entry here.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Protocol

from . import rtde
from .framer import Framer
from .generated import (robotiq_gripper, ur_dashboard, ur_interpreter, ur_realtime, ur_reverse, ur_script_command,
                        ur_script_sender, ur_trajectory)
from .generated.spec import PORTS
from .realtime import RealtimeConversation


class Conversation(Protocol):
    """One TCP connection of one interface; its state (software version, recipes) is its own."""

    def feed(self, data: bytes, from_robot: bool) -> list:
        """The records the bytes so far complete, in order."""

    def close(self, from_robot: Optional[bool] = None) -> list:
        """What the end of one direction's stream leaves (both, to_robot's first, when
        `from_robot` is None): a truncated tail becomes an error record of that direction."""

    def lost(self, from_robot: bool, offset: int) -> list:
        """Bytes of one direction are missing before its stream offset `offset`: what that
        direction holds is given up as close() gives it, and its decoding starts afresh there,
        keeping what the connection learnt (version, recipes, protocol)."""

    # Optional: `software_version` (the version the conversation learnt, else None) and
    # `learn_version(version)` (the version another conversation of the same robot learnt).


@dataclass(frozen=True)
class Interface:
    name: str                      # the Wireshark protocol, and a record's "interface"
    title: str
    ports: tuple[int, ...]         # the controller's default ports
    conversation: Callable[..., Conversation]   # (version_hint=None) -> a fresh Conversation
    both_directions: bool = False  # a capture reader feeds it what clients send, too (RTDE)
    # The robot is the TCP client (the ROS driver's sockets, where the control PC listens): bytes
    # sent to the port come from the robot. Else the robot listens and sends from the port.
    robot_is_client: bool = False


class PrimaryConversation:
    """The primary/secondary interface: the robot's stream framed and decoded; what a client sends
    there is URScript, which is not decoded."""

    def __init__(self, version_hint=None):
        self.framer = Framer(version_hint)

    def feed(self, data: bytes, from_robot: bool) -> list:
        return self.framer.feed(data) if from_robot else []

    def close(self, from_robot: Optional[bool] = None) -> list:
        return [] if from_robot is False else self.framer.close()

    def lost(self, from_robot: bool, offset: int) -> list:
        return self.framer.restart(offset) if from_robot else []

    @property
    def software_version(self):
        """The version the robot's Version message announced, else None: what the capture reader
        passes on to the robot's other conversations (Conversation.learn_version)."""
        return self.framer.announced


INTERFACES: dict[str, Interface] = {i.name: i for i in (
    Interface("ur", "Universal Robots primary/secondary client interface", tuple(PORTS), PrimaryConversation),
    Interface(ur_realtime.PROTOCOL, ur_realtime.TITLE, ur_realtime.PORTS, RealtimeConversation),
    Interface(rtde.NAME, rtde.TITLE, rtde.PORTS, rtde.Conversation, both_directions=True),
    *(Interface(m.NAME, m.TITLE, m.PORTS, m.conversation, both_directions=True)
      for m in (ur_dashboard, ur_interpreter, robotiq_gripper)),
    *(Interface(m.NAME, m.TITLE, m.PORTS, m.conversation, both_directions=True, robot_is_client=True)
      for m in (ur_reverse, ur_script_sender, ur_trajectory, ur_script_command)),
)}


def interface_of_port(port: int) -> Optional[Interface]:
    """The interface whose default ports include this one, if any."""
    for interface in INTERFACES.values():
        if port in interface.ports:
            return interface
    return None
