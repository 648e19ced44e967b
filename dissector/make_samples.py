"""Write the sample captures in dissector/samples/ from the conformance bytes and a few hand-made
messages: `make samples` (python3 dissector/make_samples.py).

primary_session.pcapng   port 30001: Version, robot states at 10 Hz (a program starts, moves the
                         six joints for 20 s, stops on a protective stop), key/text/popup/
                         runtime-exception/safety-mode/robot-comm messages, program threads, global
                         variables setup and updates, and the client's URScript; some robot states
                         cut across segments, some packed.
secondary_session.pcap   port 30002: Version, then robot states at 10 Hz as the secondary
                         interface sends them (fewer sub-packages).
cell_session.pcapng      a whole cell, every conversation from the golden vectors
                         (tests/tools/cell_session.py): primary (30001), real-time (30003), RTDE
                         protocol 2 (30004: a setup with a NOT_FOUND, inputs IN_USE, start, data
                         both ways; a second client whose data arrive between a setup and its
                         reply), the dashboard server (29999), the ROS driver's four sockets
                         (50001-50004, the robot connecting to the control PC), interpreter mode
                         (30020: statements acked with their ids) and a Robotiq gripper's socket
                         (63352: activated, closed onto a part).

The output is deterministic (fixed seeds and timestamps), so a re-run leaves git clean.
"""
from __future__ import annotations

import copy
import math
import struct
import sys
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]

import urwire  # noqa: E402
from tests.tools import capture, cell_session  # noqa: E402
from tests.tools.capture import Segment  # noqa: E402
from tests.vectors import parse_hex  # noqa: E402

CONF = ROOT / "tests" / "conformance"
OUT = Path(__file__).resolve().parent / "samples"
V59 = (5, 9)
RUN_STEPS = 200          # robot states while the program runs: 20 s at 10 Hz
STEP_SECONDS = 0.1       # the robot-state period


def conformance(name: str) -> bytes:
    return parse_hex((CONF / name).read_text(encoding="ascii"), name)


def robot_message(subtype: int, body: bytes, timestamp: int, source: int = -2) -> bytes:
    inner = struct.pack(">QbB", timestamp, source, subtype) + body
    return struct.pack(">iB", 5 + len(inner), 20) + inner


def program_state(subtype: int, body: bytes, timestamp: int) -> bytes:
    inner = struct.pack(">QB", timestamp, subtype) + body
    return struct.pack(">iB", 5 + len(inner), 25) + inner


def text(s: str) -> bytes:
    return s.encode("utf-8")


def version_message() -> bytes:
    name = b"URControl"
    return robot_message(3, struct.pack(">b", len(name)) + name + struct.pack(">BBii", 5, 11, 8, 110254)
                         + b"12-09-2022, 08:31:05", 0)


def key_message(ts: int, code: int, title: str, body: str) -> bytes:
    t = text(title)
    return robot_message(7, struct.pack(">iiB", code, 0, len(t)) + t + text(body), ts)


def text_message(ts: int, body: str) -> bytes:
    return robot_message(0, text(body), ts)


def popup(ts: int, title: str, body: str, warning=False, error=False, blocking=True) -> bytes:
    t = text(title)
    return robot_message(2, struct.pack(">IIBBBB", 1, 8, warning, error, blocking, len(t)) + t + text(body), ts)


def runtime_exception(ts: int, line: int, col: int, body: str) -> bytes:
    return robot_message(10, struct.pack(">ii", line, col) + text(body), ts, source=-3)


def safety_mode(ts: int, mode: int, code: int, arg: int) -> bytes:
    return robot_message(5, struct.pack(">iiBII", code, arg, mode, 0, 0), ts, source=-3)


def robot_comm(ts: int, code: int, arg: int, level: int, body: str) -> bytes:
    return robot_message(6, struct.pack(">iiiII", code, arg, level, 0, 0) + text(body), ts, source=-3)


def program_threads(ts: int, threads) -> bytes:
    body = b""
    for label_id, label, thread in threads:
        lb, tb = text(label), text(thread)
        body += struct.pack(">ii", label_id, len(lb)) + lb + struct.pack(">i", len(tb)) + tb
    return robot_message(14, body, ts)


def globals_setup(ts: int, names) -> bytes:
    return program_state(0, struct.pack(">H", 0) + b"".join(text(n) + b"\n" for n in names), ts)


def globals_update(ts: int, counter: int, speed: float, pose) -> bytes:
    """5.9 value codes: INT 15, FLOAT 16, POSE 12, BOOL 13, CONST_STRING 3, LIST 17."""
    body = struct.pack(">H", 0)
    body += b"\x0f" + struct.pack(">i", counter) + b"\n"
    body += b"\x10" + struct.pack(">f", speed) + b"\n"
    body += b"\x0c" + struct.pack(">6f", *pose) + b"\n"
    body += b"\x0d" + bytes([counter % 2]) + b"\n"
    body += b"\x03" + struct.pack(">h", 4) + b"home" + b"\n"
    body += b"\x11" + struct.pack(">h", 2) + b"\x0f" + struct.pack(">i", 1) + b"\x0f" + struct.pack(">i", counter) + b"\n"
    return program_state(1, body, ts)


class StateMaker:
    """Robot states derived from a real 5.11 capture, with the modes and joints moved along."""

    def __init__(self, raw: bytes, secondary: bool = False):
        (self.base,) = list(urwire.decode_stream(raw))
        self.secondary = secondary

    def make(self, step: int, robot_mode: int, safety: int, running: bool, with_kinematics: bool,
             pose: Optional[int] = None) -> bytes:
        """Robot state `step`; its joints stand where the motion has them at step `pose` (the
        step itself by default), and move while `running`."""
        pose = step if pose is None else pose
        msg = copy.deepcopy(self.base)
        keep = []
        for pkg in msg.packages:
            name = getattr(pkg, "TYPE", "")
            if name in ("kinematics_info", "configuration_data") and not with_kinematics:
                continue
            # Sub-package 14 is read as payload_info now that the spec lays it out; the secondary
            # sample never held it.
            if self.secondary and name in ("calibration_data", "safety_data", "tool_comm_info",
                                           "tool_mode_info", "payload_info", "unknown"):
                continue
            if name == "robot_mode_data":
                pkg.timestamp = 19_805_995_000 + step * 100_000_000
                pkg.robot_mode = robot_mode
                pkg.is_program_running = running
                pkg.is_protective_stopped = safety == 3
            elif name == "joint_data":
                for j, joint in enumerate(pkg.joints):
                    # Each joint swings about its own centre with its own period (5 to 10 s).
                    w, t = 2 * math.pi / (5 + j), pose * STEP_SECONDS
                    joint.q_actual = 0.4 * j - 1.0 + 0.9 * math.sin(w * t + j)
                    joint.q_target = joint.q_actual + 0.001
                    joint.qd_actual = 0.9 * w * math.cos(w * t + j) if running else 0.0
                    joint.t_motor += 0.01 * pose   # warmer after moving
                    joint.joint_mode = 253 if robot_mode == 7 else 255
            elif name == "masterboard_data":
                pkg.safety_mode = safety
                pkg.digital_output_bits = (step // 5) & 0xFF
            keep.append(pkg)
        msg.packages = keep
        return urwire.encode_message(msg, V59)


URSCRIPT = [
    "def urwire_demo():\n  set_digital_out(0, True)\n  movej([0, -1.57, 1.57, 0, 1.57, 0], a=1.2, v=0.25)\n"
    "  textmsg(\"cycle done\")\nend\n",
    "popup(\"Check the gripper\", title=\"Operator\", blocking=True)\n",
    "stopj(2.0)\n",
]


class Timeline:
    """The segments of one session and when each is sent: robot state `step` at (step + 1) x
    100 ms, every other segment a few milliseconds after the one before it."""

    GAP = 0.005

    def __init__(self) -> None:
        self.segments: list[Segment] = []
        self.times: list[float] = []
        self.clock = 0.05

    def state(self, step: int, *payloads: bytes) -> None:
        """A robot state (with what shares its segment), at its slot."""
        self.clock = (step + 1) * STEP_SECONDS
        self.robot(*payloads)

    def robot(self, *payloads: bytes) -> None:
        self.send(True, b"".join(payloads))

    def client(self, payload: bytes) -> None:
        self.send(False, payload)

    def send(self, from_robot: bool, payload: bytes) -> None:
        self.segments.append(Segment(from_robot, payload))
        self.times.append(self.clock)
        self.clock += self.GAP

    def frame_times(self) -> list[float]:
        """One time per frame of capture.session_frames: the handshake, each segment and its
        acknowledgement, then the closing exchange."""
        out = [0.0, 0.0005, 0.001]
        for t in self.times:
            out += [t, t + 0.0005]
        end = self.clock + STEP_SECONDS
        return out + [end, end + 0.0005, end + 0.001]


def primary_session() -> Timeline:
    states = StateMaker(conformance("Universal_Robots_Client_Library/robot_state_real_robot_5.11_pr137.hex"))
    s = Timeline()
    t = 1_000_000
    s.robot(version_message())
    run_end = 4 + RUN_STEPS
    s.state(0, states.make(0, 5, 1, False, True, pose=4))  # the first state carries kinematics and configuration
    for step in range(1, 4):
        s.state(step, states.make(step, 5, 1, False, False, pose=4))
    s.client(text(URSCRIPT[0]))
    s.robot(globals_setup(t, ["counter", "speed", "target_pose", "gripper_closed", "home_name", "history"]))
    s.robot(key_message(t + 1, 0, "PROGRAM_XXX_STARTED", "urwire_demo"),
            program_threads(t + 2, [(3, "MoveJ", "urwire_demo")]))
    for step in range(4, run_end):
        msg = states.make(step, 7, 1, True, False)
        if step % 4 == 1:
            s.state(step, msg[:3])                       # a header split inside its first 5 bytes
            s.robot(msg[3:])
        elif step % 4 == 2:
            s.state(step, msg[:700])                     # a message across two segments
            s.robot(msg[700:])
        elif step % 4 == 3:
            s.state(step, msg, globals_update(t + step, step, 0.25 + step / 100, [0.1 * step, -0.3, 0.4, 0, 3.14, 0]))
        else:
            s.state(step, msg)
        if step == 8:
            s.robot(text_message(t + 8, "cycle done"))
    s.client(text(URSCRIPT[1]))
    s.robot(popup(t + run_end, "Operator", "Check the gripper"))
    s.state(run_end, states.make(run_end, 7, 1, True, False))
    s.robot(robot_comm(t + run_end + 1, 209, 3, 3, "C209A3: Protective stop: Position close to joint limits"))
    s.robot(safety_mode(t + run_end + 2, 3, 209, 3))
    s.state(run_end + 1, states.make(run_end + 1, 7, 3, False, False, pose=run_end))
    s.robot(conformance("Universal_Robots_Client_Library/runtime_exception_message.hex")[:57])  # its own length
    s.robot(key_message(t + run_end + 3, 0, "PROGRAM_XXX_STOPPED", "urwire_demo"))
    s.client(text(URSCRIPT[2]))
    for step in range(run_end + 2, run_end + 6):
        s.state(step, states.make(step, 5, 1, False, False, pose=run_end))
    return s


def secondary_session() -> Timeline:
    states = StateMaker(conformance("Universal_Robots_Client_Library/robot_state_real_robot_5.11_pr137.hex"),
                        secondary=True)
    s = Timeline()
    s.robot(version_message())
    for step in range(30):
        s.state(step, states.make(step, 7 if step >= 5 else 5, 1, step >= 5, step == 0))
    return s


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    primary, secondary = primary_session(), secondary_session()
    capture.write(OUT / "primary_session.pcapng", capture.session_frames(primary.segments, port=30001),
                  pcapng=True, times=primary.frame_times())
    capture.write(OUT / "secondary_session.pcap",
                  capture.session_frames(secondary.segments, port=30002, client_port=50124),
                  times=secondary.frame_times())
    cell_session.write(OUT / "cell_session.pcapng")
    print(f"wrote {OUT / 'primary_session.pcapng'}, {OUT / 'secondary_session.pcap'} and {OUT / 'cell_session.pcapng'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
