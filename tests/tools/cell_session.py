"""A capture of a whole UR cell from the hand-made golden vectors: the primary interface, the
real-time interface, RTDE (a protocol 2 session, and a second client whose data packages arrive
in the middle of its setups), the dashboard server, the ROS driver's four sockets, interpreter mode
and a Robotiq gripper's socket, each a TCP conversation of its own, overlapping in time as a cell's
do.

`dissector/make_samples.py` writes it as dissector/samples/cell_session.pcapng; the export and
sample tests build the same conversations. Every byte comes from a golden vector (tests/golden/),
so what each conversation decodes to is written down there, field by field.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tests.interface_vectors import conversation_cases
from tests.rtde_vectors import rtde_cases
from tests.tools import capture
from tests.tools.capture import Segment
from tests.vectors import golden_cases, interface_cases

ROBOT, CONTROL_PC = capture.ROBOT, capture.CLIENT
FRAME_SECONDS = 0.002    # between two frames of the capture, whichever conversation they belong to


@dataclass(frozen=True)
class Conversation:
    """One TCP conversation: the vector it comes from, the listening side's port, and its segments
    (`from_robot` of capture.Segment meaning: from the side that listens)."""
    vector: str
    port: int
    client_port: int
    segments: tuple
    robot_listens: bool = True

    def frames(self) -> list[bytes]:
        server, client = (ROBOT, CONTROL_PC) if self.robot_listens else (CONTROL_PC, ROBOT)
        return capture.session_frames(self.segments, port=self.port, client_port=self.client_port,
                                      robot=server, client=client)


def _one(cases, name: str):
    return next(c for c in cases if c.name == name or c.name.endswith("/" + name))


def _driver(interface: str, vector: str, port: int, client_port: int, pc_bytes: int = -1) -> Conversation:
    """A ROS driver socket: the control PC listens, the robot connects. `pc_bytes`: only the first
    bytes the PC sends (a vector's deliberately cut tail left out), else all."""
    case = _one(conversation_cases(interface), vector)
    segments, sent = [], 0
    for s in case.segments:
        data = s.data
        if not s.from_robot and pc_bytes >= 0:
            data, sent = data[:max(0, pc_bytes - sent)], sent + len(data)
        if data:
            segments.append(Segment(not s.from_robot, data))
    return Conversation(f"{interface}/{vector}", port, client_port, tuple(segments), robot_listens=False)


def conversations() -> list[Conversation]:
    """The cell's conversations, in the order they open."""
    primary = _one(golden_cases(), "generation_eseries_5_11_robot_state")
    realtime = _one(interface_cases("ur_realtime"), "eseries_5_10")
    rtde = _one(rtde_cases(), "protocol2_session")
    rtde_busy = _one(rtde_cases(), "data_during_setup")
    dashboard = _one(conversation_cases("ur_dashboard"), "session_load_play")
    interpreter = _one(conversation_cases("ur_interpreter"), "statements_acked")
    gripper = _one(conversation_cases("robotiq_gripper"), "activate_and_close")
    return [
        Conversation(primary.name, 30001, 50101, (Segment(True, primary.data),)),
        Conversation(realtime.name, 30003, 50102, (Segment(True, realtime.data),)),
        Conversation(f"rtde/{rtde.name}", 30004, 50103,
                     tuple(Segment(from_robot, data) for from_robot, data in rtde.messages)),
        Conversation(f"rtde/{rtde_busy.name}", 30004, 50105,
                     tuple(Segment(from_robot, data) for from_robot, data in rtde_busy.messages)),
        Conversation(f"ur_dashboard/{dashboard.name}", 29999, 50104,
                     tuple(Segment(s.from_robot, s.data) for s in dashboard.segments)),
        _driver("ur_reverse", "servoj_and_idle", 50001, 40001, pc_bytes=2 * 32),   # its two whole commands
        _driver("ur_script_sender", "request_and_program", 50002, 40002),
        _driver("ur_trajectory", "point_and_result_2_14", 50003, 40003),
        _driver("ur_script_command", "set_payload_2_14", 50004, 40004),
        Conversation(f"ur_interpreter/{interpreter.name}", 30020, 50106,
                     tuple(Segment(s.from_robot, s.data) for s in interpreter.segments)),
        Conversation(f"robotiq_gripper/{gripper.name}", 63352, 50107,
                     tuple(Segment(s.from_robot, s.data) for s in gripper.segments)),
    ]


def interleave(sessions: list[list[bytes]]) -> list[bytes]:
    """One frame of each session in turn: conversations that overlap in time."""
    out = []
    for i in range(max(map(len, sessions))):
        out += [s[i] for s in sessions if i < len(s)]
    return out


def write(path: Path, pcapng: bool = True) -> Path:
    frames = interleave([c.frames() for c in conversations()])
    return capture.write(path, frames, pcapng=pcapng, times=[i * FRAME_SECONDS for i in range(len(frames))])
