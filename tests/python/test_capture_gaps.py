"""Every byte of a capture is decoded or named: a segment the capture lost is an error record of its
conversation and direction, the message it cut short is reported, and decoding goes on after it
with every packet real tshark shows; a retransmission that differs from the bytes it repeats is
named too, an identical one is not."""
from __future__ import annotations

import json
import random
import struct
import subprocess
import sys

import pytest

from tests.tools import capture
from tests.tools.capture import Segment

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
REALTIME_LUA = ROOT / "generated" / "lua" / "ur_realtime.lua"
SIZE = 1116                 # rt_3_10
COUNT = 120


def packet(number: int) -> bytes:
    """A 1116-byte packet whose first double (its time) is its number; the others vary."""
    rng = random.Random(number)
    doubles = [float(number)] + [rng.uniform(-3.0, 3.0) for _ in range((SIZE - 4) // 8 - 1)]
    return struct.pack(f">i{len(doubles)}d", SIZE, *doubles)


def decode(*args: str) -> tuple[list[dict], int]:
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", *args], capture_output=True, text=True,
                         env=ENV, timeout=300)
    assert res.returncode in (0, 1), res.stderr
    return [json.loads(line) for line in res.stdout.splitlines()], res.returncode


def lost_segment_capture(tmp_path, cut_at: int = 40) -> tuple:
    """A 30003 session of one packet per segment, but for packets `cut_at` and `cut_at` + 1, split
    across three segments of which the middle one, from inside the first to inside the second, is
    not in the capture."""
    packets = [packet(i) for i in range(COUNT)]
    first, second = packets[cut_at], packets[cut_at + 1]
    payloads = packets[:cut_at] + [first[:600], first[600:] + second[:300], second[300:]] + packets[cut_at + 2:]
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30003)
    del frames[3 + 2 * (cut_at + 1)]          # the robot's middle segment (after the handshake's 3 frames)
    return capture.write(tmp_path / "lost.pcap", frames), cut_at * SIZE + 600, 516 + 300


def test_a_lost_segment_inside_a_packet_is_named_and_every_later_packet_decoded(tmp_path):
    pcap, gap_at, gap_length = lost_segment_capture(tmp_path)
    records, status = decode(str(pcap))
    assert status == 1
    assert {(r["interface"], r["direction"]) for r in records} == {("ur_realtime", "from_robot")}
    errors = [r for r in records if r["type"] == "error"]
    assert errors[0]["offset"] == gap_at
    assert errors[0]["error"] == f"{gap_length} bytes missing from the capture at offset {gap_at}"
    # The packet the gap cut short, then the middle of the next one where decoding starts afresh.
    assert errors[1]["error"] == f"packet at offset {40 * SIZE}: needs {SIZE} bytes, 600 left"
    assert errors[2]["offset"] == gap_at + gap_length
    assert len(errors) == 3
    times = [r["time"] for r in records if r["type"] == "rt_3_10"]
    assert times == [float(i) for i in range(COUNT) if i not in (40, 41)]
    # Each packet's place in the stream counts the missing bytes: the error after the gap is where
    # the next byte the capture holds sits in the robot's stream.
    assert all(r["conversation"] == records[0]["conversation"] for r in records)


def tshark_times(pcap) -> list[float]:
    """The time of every real-time packet real tshark shows with the Lua dissector."""
    out = subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{REALTIME_LUA}", "-2", "-T", "json",
                          "-e", "ur_realtime.time", "-Y", "ur_realtime.time"],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return sorted(float(t) for p in json.loads(out.stdout) for t in p["_source"]["layers"]["ur_realtime.time"])


def test_the_same_capture_in_tshark_shows_no_packet_python_misses(tmp_path):
    """Real tshark with the Lua dissector: every packet it shows after the gap, Python decodes."""
    pcap, _, _ = lost_segment_capture(tmp_path)
    shown = tshark_times(pcap)
    records, _ = decode(str(pcap))
    decoded = sorted(r["time"] for r in records if r["type"] == "rt_3_10")
    assert len(shown) == COUNT - 2 and shown == decoded


def test_segments_cut_anywhere_lose_only_the_packets_the_gap_touches(tmp_path):
    """A robot's stream in segments of any size, one lost from the middle: Python decodes every
    packet the gap does not touch, and tshark shows the same (its dissector skips the middle of a
    packet a segment after the gap starts in, as Python does)."""
    stream = b"".join(packet(i) for i in range(COUNT))
    payloads = capture.random_cuts([stream], seed=3, max_len=1448)
    lost = len(payloads) // 2
    start = sum(map(len, payloads[:lost]))
    end = start + len(payloads[lost])
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30003)
    del frames[3 + 2 * lost]
    pcap = capture.write(tmp_path / "cuts.pcap", frames)
    records, status = decode(str(pcap))
    assert status == 1
    decoded = sorted(r["time"] for r in records if r["type"] == "rt_3_10")
    touched = {i for i in range(COUNT) if i * SIZE < end and start < (i + 1) * SIZE}
    assert decoded == [float(i) for i in range(COUNT) if i not in touched]
    assert tshark_times(pcap) == decoded


def test_a_gap_in_the_primary_stream_is_an_unenveloped_error_and_decoding_restarts(tmp_path):
    from tests.vectors import golden_cases

    state = next(c for c in golden_cases() if c.name == "generation_cb3_3_10_robot_state").data
    payloads = [state] * 4 + [state[:30], state[30:60], state[60:]] + [state] * 3   # a Version, a state
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30001)
    del frames[3 + 2 * 5]
    records, status = decode(str(capture.write(tmp_path / "primary.pcap", frames)))
    assert status == 1
    gap = {"type": "error", "offset": 4 * len(state) + 30, "error": f"30 bytes missing from the capture at offset "
                                                                    f"{4 * len(state) + 30}"}
    assert records[8] == gap                  # after the 4 copies' version and robot state
    assert records[9] == {"type": "error", "offset": 4 * len(state), "error": "truncated message: length 55, "
                                                                          "30 bytes left"}
    # Afresh after the gap, in the middle of a message: faults while the framer resynchronises, then
    # every whole copy after it.
    assert records[10]["type"] == "error" and records[10]["offset"] == 4 * len(state) + 60
    assert [r["type"] for r in records[-6:]] == ["version", "robot_state"] * 3


def test_a_retransmission_that_differs_is_named_and_an_identical_one_is_not(tmp_path):
    packets = [packet(i) for i in range(6)]
    same = capture.session_frames([Segment(True, p) for p in packets], port=30003, retransmit=[2])
    records, status = decode(str(capture.write(tmp_path / "same.pcap", same)))
    assert status == 0 and len(records) == 6
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003, retransmit=[2])
    original = frames[3 + 2 * 2 + 1]          # the second copy of the third packet's segment
    changed = original[:-16] + bytes(16)      # its last double and the one before, other bytes
    # dpkt checks nothing, and the reader takes the payload as it is: change it after the checksum.
    frames[3 + 2 * 2 + 1] = changed
    records, status = decode(str(capture.write(tmp_path / "differs.pcap", frames)))
    assert status == 1
    errors = [r for r in records if r["type"] == "error"]
    assert len(errors) == 1 and errors[0]["direction"] == "from_robot"
    assert errors[0]["offset"] == 2 * SIZE
    assert "differ from those delivered first" in errors[0]["error"]
    assert [r["time"] for r in records if r["type"] == "rt_3_10"] == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]


def test_held_segments_behind_a_gap_at_the_end_are_decoded_after_its_record(tmp_path):
    """The capture ends while segments wait behind a gap: the gap is named and what waited is
    decoded, not dropped."""
    packets = [packet(i) for i in range(8)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003)
    frames = frames[:3 + 2 * 8]               # no FIN: the capture ends with the session open
    del frames[3 + 2 * 3]
    records, status = decode(str(capture.write(tmp_path / "open.pcap", frames)))
    assert status == 1
    assert [r["type"] for r in records] == ["rt_3_10"] * 3 + ["error"] + ["rt_3_10"] * 4
    assert records[3]["error"] == f"{SIZE} bytes missing from the capture at offset {3 * SIZE}"


@pytest.mark.parametrize("interface,port,client,robot", [
    ("ur_dashboard", 29999, b"power on\npopup hel", b"Connected: Universal Robots Dashboard Server\nPowering on\n"),
    ("rtde", 30004, b"\x00\x05V\x00", b"\x00\x04V\x01"),
])
def test_a_clients_cut_tail_in_a_capture_is_the_clients(tmp_path, interface, port, client, robot):
    frames = capture.session_frames([Segment(False, client), Segment(True, robot)], port=port)
    records, status = decode("--protocol", interface, str(capture.write(tmp_path / "cut.pcap", frames)))
    assert status == 1
    (tail,) = [r for r in records if r["type"] == "error"]
    assert tail["direction"] == "to_robot"


def test_an_rtde_conversation_keeps_its_recipe_across_a_gap(tmp_path):
    """A gap inside the robot's data packages: the package it cut short and the middle of the next
    are named, and every later package is still read with the recipe the client set up."""
    from urwire import rtde
    from urwire.generated import rtde as g

    recipe = rtde.Recipe(1, "outputs", ["timestamp"], ["DOUBLE"], g.VALUE_TYPES)
    packages = [g.DataPackage(1, {"timestamp": float(i)}).encode(recipe) for i in range(12)]
    size = len(packages[0])
    robot = [g.RequestProtocolVersionReply(True).encode(), g.SetupOutputsReply(1, ["DOUBLE"]).encode(),
             g.StartReply(True).encode()]
    segments = [Segment(False, rtde.request_protocol_version(2)), Segment(True, robot[0]),
                Segment(False, rtde.setup_outputs(["timestamp"], 125.0)), Segment(True, robot[1]),
                Segment(False, rtde.start()), Segment(True, robot[2])]
    cut = packages[:5] + [packages[5][:5], packages[5][5:] + packages[6][:6], packages[6][6:]] + packages[7:]
    segments += [Segment(True, p) for p in cut]
    frames = capture.session_frames(segments, port=30004)
    del frames[3 + 2 * (len(segments) - len(cut) + 6)]        # the middle one of packages 5 and 6
    records, status = decode(str(capture.write(tmp_path / "rtde.pcap", frames)))
    assert status == 1
    robot_offset = sum(map(len, robot)) + 5 * size
    errors = [r for r in records if r["type"] == "error"]
    assert [(e["direction"], e["offset"]) for e in errors[:2]] == [("from_robot", robot_offset + 5),
                                                                  ("from_robot", robot_offset)]
    assert errors[0]["error"] == f"{size + 1} bytes missing from the capture at offset {robot_offset + 5}"
    stamps = [r["timestamp"] for r in records if r["type"] == "data_package"]
    assert stamps == [float(i) for i in range(12) if i not in (5, 6)]
    assert all("error" not in r for r in records if r["type"] == "data_package")
