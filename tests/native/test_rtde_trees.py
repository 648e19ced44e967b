"""The RTDE tree reads as the real-time and primary trees do, in the native plugin and the Lua
dissector alike: codes by their enum's names, status bits as named flags, a vector's items by joint
or axis with each one's unit, and a setup reply's types each paired with the variable it answers."""
from __future__ import annotations

import re
import struct
import tempfile
from pathlib import Path

import pytest

from tests.native import harness
from tests.native.test_rtde_native import PORT, assert_same, lua, native
from tests.tools import capture
from tests.tools.capture import Segment

NAMES = [b"robot_mode", b"safety_status", b"runtime_state", b"robot_status_bits", b"safety_status_bits",
         b"actual_digital_input_bits", b"joint_mode", b"actual_TCP_pose", b"actual_TCP_force", b"actual_q"]
TYPES = [b"INT32", b"INT32", b"UINT32", b"UINT32", b"UINT32", b"UINT64", b"VECTOR6INT32", b"VECTOR6D", b"VECTOR6D",
         b"VECTOR6D"]


def _message(code: bytes, body: bytes) -> bytes:
    return struct.pack(">HB", 3 + len(body), code[0]) + body


def _session() -> bytes:
    values = (struct.pack(">iiIII", 7, 1, 2, 0b0011, 1) + struct.pack(">Q", 5) + struct.pack(">6i", *[253] * 6)
              + struct.pack(">6d", 0.375, -0.125, 0.5, 3.0, -0.0625, 0.03125)
              + struct.pack(">6d", 1.5, -2.25, 30.0, 0.5, -0.25, 0.125)
              + struct.pack(">6d", 0.5, -1.5, 1.25, -0.75, 1.5, 0.0))
    segments = [Segment(False, _message(b"O", struct.pack(">d", 125.0) + b",".join(NAMES))),
                Segment(True, _message(b"O", b"\x01" + b",".join(TYPES))),
                Segment(True, _message(b"U", b"\x01" + values))]
    with tempfile.TemporaryDirectory() as folder:
        return capture.write(Path(folder) / "trees.pcap", capture.session_frames(segments, port=PORT)).read_bytes()


@pytest.fixture(scope="module")
def tree() -> str:
    session = _session()
    assert_same(session)                        # -T json, Info, experts and -V: native as Lua
    text = harness.checked(native(session, "-O", "rtde", "-V"))
    assert text == harness.checked(lua(session, "-O", "rtde", "-V"))
    return text


@pytest.mark.parametrize("line", [
    r"Robot mode: RUNNING \(7\)",                                # codes by name
    r"Safety status: NORMAL \(1\)",
    r"Program state: PLAYING \(2\)",
    r"[.01 ]*\.\.\.1 = Is power on: True",                         # status bits as named flags
    r"[.01 ]*\.0\.\. = Is teach button pressed: False",
    r"[.01 ]*\.\.\.1 = Is normal mode: True",
    r"[.01 ]*\.1\.\. = Standard 2: True",
    r"Joint control modes",                                       # a vector's items by joint or axis
    r"Wrist 3: RUNNING \(253\)",
    r"Actual TCP pose \(m, rad\)",
    r"Z: 0\.5 m",
    r"RX: 3 rad",
    r"Fz: 30 N",
    r"Tx: 0\.5 Nm",
    r"Shoulder: -1\.5 rad",
    r"\[actual_q: VECTOR6D\]",                                   # a setup reply's types by variable
    r"\[robot_status_bits: UINT32\]",
])
def test_the_tree_reads_in_names(tree, line):
    assert re.search(rf"^\s+{line}$", tree, re.M), line


def test_a_pair_sits_on_its_types_bytes(tree):
    """Each pair under the reply's types, in the request's order."""
    pairs = re.findall(r"^ {8}\[(\w+): (\w+)\]$", tree, re.M)
    assert pairs == [(n.decode(), t.decode()) for n, t in zip(NAMES, TYPES)]
