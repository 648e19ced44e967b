"""Every golden vector of every interface as one TCP session each, in one capture: a handful of
tshark runs then read them all. `cut=True` sends every segment in 1-7 byte pieces (seeded), so
that each dissector's reassembly meets every split.

Ports are the interfaces' own: 30001 the primary interface, 30003 real-time, 30004 RTDE, 29999
the dashboard server, 30020 interpreter mode, 63352 the Robotiq gripper's socket, 50001-50004 the
ROS driver's sockets (where the control PC listens and the robot connects). Each session has a client port of its own.
"""
from __future__ import annotations

import random
from pathlib import Path

from tests.interface_vectors import conversation_cases
from tests.rtde_vectors import rtde_cases
from tests.tools import capture
from tests.tools.capture import Segment
from tests.tools.cell_session import Conversation
from tests.vectors import golden_cases, interface_cases

LISTENING_LINES = {"ur_dashboard": 29999, "ur_interpreter": 30020, "robotiq_gripper": 63352}
DRIVER_PORTS = {"ur_reverse": 50001, "ur_script_sender": 50002, "ur_trajectory": 50003, "ur_script_command": 50004}


def _listener_sessions() -> list[tuple[str, int, bool, list[Segment]]]:
    """(vector, port, robot listens, segments from the listening side or not)."""
    out = [(f"ur/{c.name}", 30001, True, [Segment(True, c.data)]) for c in golden_cases()]
    out += [(f"ur_realtime/{c.name}", 30003, True, [Segment(True, c.data)]) for c in interface_cases("ur_realtime")]
    out += [(f"rtde/{c.name}", 30004, True, [Segment(r, d) for r, d in c.messages]) for c in rtde_cases()]
    for interface, port in LISTENING_LINES.items():
        out += [(f"{interface}/{c.name}", port, True, [Segment(s.from_robot, s.data) for s in c.segments])
                for c in conversation_cases(interface)]
    for interface, port in DRIVER_PORTS.items():
        # the control PC listens: "from the listening side" is from the PC, not from the robot
        out += [(f"{interface}/{c.name}", port, False, [Segment(not s.from_robot, s.data) for s in c.segments])
                for c in conversation_cases(interface)]
    return out


def _cut(segments: list[Segment], rng: random.Random) -> list[Segment]:
    pieces = []
    for segment in segments:
        at = 0
        while at < len(segment.payload):
            size = rng.randint(1, 7)
            pieces.append(Segment(segment.from_robot, segment.payload[at:at + size]))
            at += size
    return pieces


def conversations(cut: bool = False, seed: int = 7, interface: str | None = None) -> list[Conversation]:
    """The sessions of every interface, or of `interface` alone ("ur": the primary one)."""
    rng = random.Random(seed)
    out = []
    for i, (vector, port, robot_listens, segments) in enumerate(_listener_sessions()):
        if interface is not None and vector.split("/", 1)[0] != interface:
            continue
        segments = [s for s in segments if s.payload]
        out.append(Conversation(vector, port, 20000 + i, tuple(_cut(segments, rng) if cut else segments),
                                robot_listens))
    return out


def write(path: Path, cut: bool = False, pcapng: bool = False, interface: str | None = None) -> Path:
    frames = [frame for conversation in conversations(cut, interface=interface) for frame in conversation.frames()]
    return capture.write(path, frames, pcapng=pcapng, step=0.001)
