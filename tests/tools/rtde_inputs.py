"""Long RTDE connections for the benchmark and the memory tests: one protocol 2 connection at 500
Hz with the recipe a driver asks for (RECIPE; 264-byte data packages), its values moving as a
robot's do. The client's side is built with urwire.rtde's client functions, the replies with the
generated classes, and the data packages with the recipe's struct (fast enough for millions)."""
from __future__ import annotations

import math
import os
import struct
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
for path in (ROOT / "python", ROOT / "generated" / "python"):
    if str(path) not in sys.path:
        sys.path.append(str(path))

from urwire import rtde  # noqa: E402
from urwire.generated import rtde as spec  # noqa: E402

BUILD = ROOT / "build"
RECIPE = ["timestamp", "actual_q", "actual_qd", "actual_current", "actual_TCP_pose", "actual_TCP_speed",
          "robot_mode", "safety_mode", "runtime_state"]
RECIPE_ID = 1
HZ = 500.0
_HEAD = struct.Struct(">HBB")


def recipe_types() -> list[str]:
    return [rtde.variable(name).type for name in RECIPE]


def values_struct() -> struct.Struct:
    shapes = [spec.VALUE_TYPES[t] for t in recipe_types()]
    return struct.Struct(">" + "".join(s.code * s.count for s in shapes))


PACKAGE_SIZE = _HEAD.size + values_struct().size


def client_bytes() -> bytes:
    return rtde.request_protocol_version(2) + rtde.setup_outputs(RECIPE, HZ) + rtde.start()


def robot_head() -> bytes:
    """The replies: protocol 2 accepted, the recipe's types, the start accepted."""
    return (spec.RequestProtocolVersionReply(True).encode() + spec.SetupOutputsReply(RECIPE_ID, recipe_types()).encode()
            + spec.StartReply(True).encode())


def packages(count: int):
    """Data packages, 2 ms apart: the joints swing, currents follow, modes stay RUNNING/NORMAL."""
    body = values_struct()
    header = _HEAD.pack(PACKAGE_SIZE, ord("U"), RECIPE_ID)
    for i in range(count):
        t = i / HZ
        q = [0.4 * j - 1.0 + 0.9 * math.sin(t / (5 + j) + j) for j in range(6)]
        qd = [0.9 / (5 + j) * math.cos(t / (5 + j) + j) for j in range(6)]
        current = [0.5 * v for v in qd]
        pose = [0.3 + 0.1 * q[0], -0.4 + 0.1 * q[1], 0.5, 3.1, 0.0, 0.1 * q[5]]
        speed = [0.1 * v for v in qd]
        yield header + body.pack(t, *q, *qd, *current, *pose, *speed, 7, 1, 1)


def package_count(megabytes: int) -> int:
    return megabytes * 1_000_000 // PACKAGE_SIZE


def capture(megabytes: int) -> Path:
    """A .pcap of one connection holding `megabytes` of data packages, one per TCP segment, under
    build/ (made once)."""
    from tests.tools import capture as pcap

    path = BUILD / f"rtde-{megabytes}MB.pcap"
    if not path.is_file():
        BUILD.mkdir(exist_ok=True)
        segments = [pcap.Segment(False, client_bytes()), pcap.Segment(True, robot_head()),
                    *(pcap.Segment(True, p) for p in packages(package_count(megabytes)))]
        partial = path.with_suffix(f".{os.getpid()}.partial")   # another test process may build it too
        pcap.write(partial, pcap.session_frames(segments, port=30004), step=0.001)
        partial.replace(path)
    return path
