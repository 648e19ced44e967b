"""Two robots in one capture, a CB2 1.8 and an e-Series 5.11, each with its primary and its
real-time conversation, on the same port numbers and the same client port, their messages
interleaved: every record names its conversation (`urwire.decode_capture` as attributes, `urwire
decode` in JSON and text), each robot decodes with its own version, as its golden vectors say, and
filtering by conversation, or by robot, gives each robot's records alone. A conversation that no
interface reads is named once, by the API and on the command's stderr."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import urwire

from tests.tools import capture
from tests.tools.capture import Segment
from tests.tools.envelope import bare, where
from tests.vectors import golden_cases, interface_cases

ROOT = Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
PRIMARY = {c.name: c for c in golden_cases()}
REALTIME = {c.name: c for c in interface_cases("ur_realtime")}
CB2, ESERIES = "192.168.56.101", "192.168.56.102"
ROBOTS = {CB2: (PRIMARY["generation_cb2_1_8_robot_state"], REALTIME["ur_realtime/cb2_1_8"]),
          ESERIES: (PRIMARY["generation_eseries_5_11_robot_state"], REALTIME["ur_realtime/eseries_5_10"])}
CLIENT_PORT = 50123                     # both robots' clients, on one control PC, use the same one
MODBUS = ("192.168.56.1", 502, "192.168.56.7", 40123)   # a conversation no interface of the cell reads


def messages(data: bytes) -> list[bytes]:
    out, pos = [], 0
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        out.append(data[pos:pos + n])
        pos += n
    return out


def conversation(robot: str, port: int) -> str:
    return f"{robot}:{port}-192.168.56.1:{CLIENT_PORT}"


@pytest.fixture(scope="module")
def two_robots(tmp_path_factory) -> Path:
    sessions = []
    for robot, (primary, realtime) in ROBOTS.items():
        sessions.append(capture.session_frames([Segment(True, m) for m in messages(primary.data)], port=30001,
                                               client_port=CLIENT_PORT, robot=robot))
        sessions.append(capture.session_frames([Segment(True, realtime.data)], port=30003, client_port=CLIENT_PORT,
                                               robot=robot))
    server, server_port, client, client_port = MODBUS
    sessions.append(capture.session_frames([Segment(False, b"\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x01"),
                                            Segment(True, b"\x00\x01\x00\x00\x00\x05\x01\x03\x02\x00\x2a")],
                                           port=server_port, client_port=client_port, robot=server, client=client))
    frames = [f for i in range(max(map(len, sessions))) for s in sessions if i < len(s) for f in [s[i]]]
    return capture.write(tmp_path_factory.mktemp("two_robots") / "two_robots.pcapng", frames, pcapng=True)


def test_each_record_names_its_conversation_and_each_robot_reads_with_its_own_version(two_robots):
    records = urwire.decode_capture(two_robots)
    got = list(records)
    assert {(r.interface, r.direction, r.conversation) for r in got} == {
        (interface, "from_robot", conversation(robot, port))
        for robot in ROBOTS for interface, port in (("ur", 30001), ("ur_realtime", 30003))}
    for robot, (primary, realtime) in ROBOTS.items():
        # Filtering by conversation separates the two robots: each is its golden vectors, whole.
        own = [r for r in got if r.conversation == conversation(robot, 30001)]
        assert [urwire.to_dict(r.record) for r in own] == primary.expect, robot
        assert [urwire.to_dict(r.record) for r in got if r.conversation == conversation(robot, 30003)] == \
            realtime.expect, robot
        # And by robot, whatever the interface.
        assert {r.interface for r in got if r.conversation.robot_address == robot} == {"ur", "ur_realtime"}
    versions = {r.conversation.server_address: (r.record.major_version, r.record.minor_version)
                for r in got if isinstance(r.record, urwire.VersionMessage)}
    assert versions == {CB2: (1, 8), ESERIES: (5, 11)}
    ends = got[0].conversation
    assert (ends.server_port, ends.client_address, ends.client_port) == (30001, "192.168.56.1", CLIENT_PORT)
    assert all(r.capture_time is not None and r.capture_time >= 1_700_000_000 for r in got)
    # The Modbus conversation is no interface's: not decoded, but named, with the bytes it carried.
    assert records.unclaimed == {"192.168.56.1:502-192.168.56.7:40123": 23}
    (unclaimed,) = records.unclaimed
    assert (unclaimed.server_address, unclaimed.server_port, unclaimed.client_port) == (MODBUS[0], 502, 40123)


def test_urwire_decode_names_each_records_conversation_in_json_and_text(two_robots):
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", str(two_robots)], capture_output=True, text=True,
                         env=ENV, timeout=120)
    assert res.returncode == 0
    lines = [json.loads(line) for line in res.stdout.splitlines()]
    for robot, (primary, realtime) in ROBOTS.items():
        assert [bare(r) for r in lines if r["conversation"] == conversation(robot, 30001)] == primary.expect
        assert [bare(r) for r in lines if r["conversation"] == conversation(robot, 30003)] == realtime.expect
    assert all(list(r)[:4] == ["interface", "direction", "conversation", "type"] for r in lines)
    # The lines are what the API's records write.
    assert lines == [urwire.to_dict(r) for r in urwire.decode_capture(two_robots)]
    # Said once, on stderr: the conversation no interface reads.
    assert res.stderr.count("\n") == 1 and "192.168.56.1:502-192.168.56.7:40123 (23 bytes)" in res.stderr
    text = subprocess.run([sys.executable, "-m", "urwire", "decode", "--format", "text", str(two_robots)],
                          capture_output=True, text=True, env=ENV, timeout=120).stdout.splitlines()
    assert len(text) == len(lines)
    assert all(line.startswith("[{} {} {}] ".format(*where(r))) for line, r in zip(text, lines))


def test_one_interface_of_the_capture_leaves_the_others_out_without_a_word(two_robots):
    """--protocol keeps one interface's conversations: those of the others are left out as asked,
    and only the conversation that no interface reads is named."""
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "ur_realtime", str(two_robots)],
                         capture_output=True, text=True, env=ENV, timeout=120)
    assert {json.loads(line)["interface"] for line in res.stdout.splitlines()} == {"ur_realtime"}
    assert res.stderr.count("\n") == 1 and ":502-" in res.stderr and ":3000" not in res.stderr
    records = urwire.decode_capture(two_robots, protocol="ur_realtime")
    assert len(list(records)) == 2 and list(records.unclaimed) == ["192.168.56.1:502-192.168.56.7:40123"]


def test_decode_file_reads_the_primary_interface_as_it_always_has(two_robots, tmp_path):
    """decode_file gives the primary interface's records as they are, both robots' interleaved;
    decode_capture reads captures only."""
    got = [urwire.to_dict(r) for r in urwire.decode_file(two_robots)]
    assert sorted(map(json.dumps, got)) == sorted(json.dumps(r) for p, _ in ROBOTS.values() for r in p.expect)
    raw = tmp_path / "stream.bin"
    raw.write_bytes(ROBOTS[CB2][0].data)
    with pytest.raises(ValueError, match="not a .pcap or .pcapng capture"):
        urwire.decode_capture(raw)


@pytest.mark.parametrize("first_from_client", [True, False])
def test_a_conversation_seen_without_its_handshake_has_its_client_on_the_higher_port(tmp_path, first_from_client):
    request, reply = Segment(False, b"\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x01"), Segment(True, b"\x00" * 11)
    frames = capture.session_frames([request, reply] if first_from_client else [reply, request], port=502,
                                    client_port=40123, handshake=False, robot="192.168.56.1", client="192.168.56.7")
    records = urwire.decode_capture(capture.write(tmp_path / "modbus.pcap", frames))
    assert list(records) == []
    assert records.unclaimed == {"192.168.56.1:502-192.168.56.7:40123": 23}
