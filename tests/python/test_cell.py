"""The cell's plumbing: `urwire decode CAPTURE` reads every UR conversation of a capture by its
port, each record naming its interface, direction and conversation, the primary interface's too;
`urwire decode --protocol NAME` reads a raw stream of any interface, with `--to-robot` for the
client's side."""
from __future__ import annotations

import json
import struct
import subprocess
import sys

import urwire
from urwire.capture import timed_streams
from urwire.cell import timed_cell_records
from urwire.interfaces import INTERFACES, Interface
from urwire.reading import records_of

from tests.tools import capture
from tests.tools.capture import Segment
from tests.tools.envelope import bare, where
from tests.vectors import golden_cases, interface_cases

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
REALTIME = interface_cases("ur_realtime")
PRIMARY = next(c for c in golden_cases() if c.name == "generation_cb3_3_10_robot_state")


def packet(size: int, first: float) -> bytes:
    n = (size - 4) // 8
    return struct.pack(f">i{n}d", size, *(first + i for i in range(n)))


def interleave(*sessions: list) -> list:
    """Frames of several sessions, one frame of each in turn: conversations that overlap in time."""
    out = []
    longest = max(map(len, sessions))
    for i in range(longest):
        out += [s[i] for s in sessions if i < len(s)]
    return out


def urwire_decode(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", "decode", *args], capture_output=True, text=True,
                          env=ENV, timeout=120)


def test_a_cell_capture_gives_every_conversation_with_its_envelope(tmp_path):
    primary = capture.session_frames([Segment(True, PRIMARY.data)], port=30002)
    robot_a = capture.session_frames([Segment(True, packet(1116, 1.0)), Segment(True, packet(1116, 2.0))],
                                     port=30003, client_port=40001)
    robot_b = capture.session_frames([Segment(False, b"textmsg(1)\n"), Segment(True, packet(812, 3.0))],
                                     port=30003, client_port=40001, robot="192.168.56.102")
    pcap = capture.write(tmp_path / "cell.pcap", interleave(primary, robot_a, robot_b))
    res = urwire_decode(str(pcap))
    assert res.returncode == 0, res.stderr
    lines = [json.loads(line) for line in res.stdout.splitlines()]
    # The primary interface's records name their conversation too; the rest is the golden vector's.
    primary_lines = [r for r in lines if r["interface"] == "ur"]
    assert {where(r) for r in primary_lines} == {("ur", "from_robot", "192.168.56.101:30002-192.168.56.1:50123")}
    assert [bare(r) for r in primary_lines] == PRIMARY.expect
    realtime = [r for r in lines if r.get("interface") == "ur_realtime"]
    assert [(r["conversation"], r["type"], r["time"]) for r in realtime] == [
        ("192.168.56.101:30003-192.168.56.1:40001", "rt_3_10", 1.0),
        ("192.168.56.101:30003-192.168.56.1:40001", "rt_3_10", 2.0),
        ("192.168.56.102:30003-192.168.56.1:40001", "rt_1_8", 3.0),
    ]
    assert {r["direction"] for r in realtime} == {"from_robot"}
    assert list(realtime[0])[:4] == ["interface", "direction", "conversation", "type"]
    only = urwire_decode("--protocol", "ur_realtime", str(pcap))
    assert [json.loads(x) for x in only.stdout.splitlines()] == realtime


def test_the_primary_alone_reads_as_before_with_its_conversation(tmp_path):
    """A capture of the primary interface decodes to the lines decode_file gives, each in its
    conversation's envelope, which decode_capture gives as attributes."""
    frames = capture.robot_session(capture.random_cuts([PRIMARY.data], seed=5))
    pcap = capture.write(tmp_path / "primary.pcap", frames)
    lines = [json.loads(x) for x in urwire_decode(str(pcap)).stdout.splitlines()]
    assert [bare(r) for r in lines] == PRIMARY.expect == [urwire.to_dict(r) for r in urwire.decode_file(pcap)]
    records = list(urwire.decode_capture(pcap))
    assert [urwire.to_dict(r) for r in records] == lines
    assert [urwire.to_dict(r.record) for r in records] == PRIMARY.expect
    assert {(r.interface, r.direction, r.conversation) for r in records} == {(x["interface"], x["direction"],
                                                                              x["conversation"]) for x in lines}


def test_a_raw_stream_of_an_interface_gives_its_records_as_they_are(tmp_path):
    for case in REALTIME:
        path = tmp_path / "rt.bin"
        path.write_bytes(case.data)
        res = urwire_decode("--protocol", "ur_realtime", *(["--version-hint", case.version] if case.version else []),
                            str(path))
        assert [json.loads(x) for x in res.stdout.splitlines()] == case.expect
        assert res.returncode == (1 if any("error" in r for r in case.expect) else 0)


def test_to_robot_names_each_records_direction_and_file(tmp_path):
    robot, client = tmp_path / "robot.bin", tmp_path / "client.bin"
    robot.write_bytes(b"Connected: Universal Robots Dashboard Server\nStarting program\n")
    client.write_bytes(b"play\n")
    res = urwire_decode("--protocol", "ur_dashboard", "--to-robot", str(client), str(robot))
    lines = [json.loads(x) for x in res.stdout.splitlines()]
    assert [(x["interface"], x["direction"], x["conversation"]) for x in lines] == [
        ("ur_dashboard", "to_robot", str(client)), ("ur_dashboard", "from_robot", str(robot)),
        ("ur_dashboard", "from_robot", str(robot))]
    assert res.returncode == 0


def test_to_robot_is_refused_for_an_interface_that_reads_the_robots_side_only(tmp_path):
    robot, client = tmp_path / "robot.bin", tmp_path / "client.bin"
    robot.write_bytes(packet(1060, 0.0))
    client.write_bytes(b"textmsg(1)\n")
    for protocol in ("ur_realtime", "ur"):
        res = urwire_decode("--protocol", protocol, "--to-robot", str(client), str(robot))
        assert res.returncode == 2 and res.stdout == ""
        assert "--to-robot" in res.stderr and "rtde" in res.stderr


class _Echo:
    """A conversation that reads both directions: one record per chunk, saying which way it went."""

    def __init__(self, version_hint=None):
        pass

    def feed(self, data, from_robot):
        return [urwire.StreamError(len(data), "robot" if from_robot else "client")]

    def close(self, from_robot=None):
        return []

    def lost(self, from_robot, offset):
        return []


def test_an_interface_that_reads_both_directions_gets_the_clients_bytes(tmp_path):
    echo = Interface("echo", "Both ways", (40000,), _Echo, both_directions=True)
    frames = capture.session_frames([Segment(False, b"abc"), Segment(True, b"defg")], port=40000)
    pcap = capture.write(tmp_path / "both.pcap", frames)
    with open(pcap, "rb") as fh:
        records = [r for _, r in timed_cell_records(fh, None, {40000: echo})]
    assert [(r.direction, r.record.error, r.record.offset) for r in records] == [
        ("to_robot", "client", 3), ("from_robot", "robot", 4)]
    # Ports of an interface that reads one way give the robot's bytes only, as before.
    with open(pcap, "rb") as fh:
        assert [item[1] for item in timed_streams(fh, {40000}) if item[2]] == [True]


def test_the_library_reads_captures_of_the_primary_by_default(tmp_path):
    frames = capture.session_frames([Segment(True, packet(1116, 1.0))], port=30003)
    pcap = capture.write(tmp_path / "rt.pcap", frames)
    with open(pcap, "rb") as fh:
        assert list(records_of(fh)) == []                       # 30003 is not a primary port
    assert "ur_realtime" in INTERFACES and 30003 in INTERFACES["ur_realtime"].ports


def test_the_primary_streams_version_reaches_the_robots_real_time_conversation(tmp_path):
    """A 1108-byte packet is CB3 3.5-3.9 or e-Series 5.0-5.3: the robot's Version message says
    which (spec framing.same_size); a robot whose primary stream the capture lacks is read as the
    newest, and a version the caller gives is kept."""
    from dataclasses import replace

    from urwire.realtime import RealtimeConversation

    cb3 = next(c for c in golden_cases() if c.name == "generation_cb3_3_5_robot_state")
    primary = capture.session_frames([Segment(True, cb3.data)], port=30002, client_port=40010)
    realtime = capture.session_frames([Segment(True, packet(1108, 0.0))] * 2, port=30003, client_port=40011)
    other = capture.session_frames([Segment(True, packet(1108, 0.0))], port=30003, client_port=40012,
                                   robot="192.168.56.200")
    pcap = capture.write(tmp_path / "versions.pcap", primary + realtime + other)
    made = []

    def conversation(hint=None):
        made.append(RealtimeConversation(hint))
        return made[-1]

    realtime_interface = replace(INTERFACES["ur_realtime"], conversation=conversation)
    by_port = {p: i for i in INTERFACES.values() for p in i.ports}
    by_port.update({p: realtime_interface for p in realtime_interface.ports})
    with open(pcap, "rb") as fh:
        records = [r for _, r in timed_cell_records(fh, None, by_port) if hasattr(r, "interface")]
    assert len(records) == 3 and len(made) == 2
    assert made[0].framer.version == (3, 5, 1) and made[1].framer.version is None   # the vector announces 3.5.1
    made.clear()
    with open(pcap, "rb") as fh:
        list(timed_cell_records(fh, "5.2", by_port))
    assert made[0].framer.version == (5, 2, 0)
