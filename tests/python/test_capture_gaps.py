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
from tests.tools.envelope import bare, where

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


def test_a_gap_in_the_primary_stream_is_an_error_of_its_conversation_and_decoding_restarts(tmp_path):
    from tests.vectors import golden_cases

    state = next(c for c in golden_cases() if c.name == "generation_cb3_3_10_robot_state").data
    payloads = [state] * 4 + [state[:30], state[30:60], state[60:]] + [state] * 3   # a Version, a state
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30001)
    del frames[3 + 2 * 5]
    enveloped, status = decode(str(capture.write(tmp_path / "primary.pcap", frames)))
    assert status == 1
    assert {where(r) for r in enveloped} == {("ur", "from_robot", "192.168.56.101:30001-192.168.56.1:50123")}
    records = [bare(r) for r in enveloped]
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


# ---- a gap the capture shows final is decided where it shows it, not at the end ----

def dashboard_exchanges(count: int) -> list[tuple]:
    steps = [(True, b"Connected: Universal Robots Dashboard Server\n")]
    for i in range(count):
        steps += [(False, f"get loaded program {i}\n".encode()), (True, f"Loaded program: /p{i}.urp\n".encode())]
    return steps


def test_records_after_an_acknowledged_gap_come_in_capture_order(tmp_path):
    """A long dashboard session missing one robot reply, which the client acknowledged: every
    later reply comes right after its command, as in the capture, not all at the end; the gap's
    record comes where the next reply showed it final."""
    steps = dashboard_exchanges(50)
    frames = capture.exchange_frames(steps, port=29999, lose=4)     # the reply to the second command
    records, status = decode(str(capture.write(tmp_path / "dash.pcap", frames)))
    assert status == 1
    kinds = [("gap" if r["type"] == "error" else r["direction"]) for r in records]
    assert kinds == ["from_robot"] + ["to_robot", "from_robot"] + ["to_robot", "to_robot", "gap", "from_robot"] + \
        ["to_robot", "from_robot"] * 47
    gap = records[kinds.index("gap")]
    assert gap["direction"] == "from_robot"
    assert gap["error"] == f"{len(steps[4][1])} bytes missing from the capture at offset " \
                           f"{len(steps[0][1]) + len(steps[2][1])}"
    replies = [r["reply"] for r in records if r["direction"] == "from_robot" and "reply" in r]
    assert replies[-1] == "Loaded program: /p49.urp"


def test_rtde_replies_after_a_lost_client_segment_come_after_their_requests(tmp_path):
    """A client segment was lost and the robot acknowledged it: the client's later setup comes
    before the robot's reply to it, as in the capture, so the reply is not one "without a request
    seen"; the gap before it leaves its pairing unknown, which the reply says."""
    from urwire import rtde
    from urwire.generated import rtde as g

    recipe = rtde.Recipe(1, "outputs", ["timestamp"], ["DOUBLE"], g.VALUE_TYPES)
    steps = [(False, rtde.request_protocol_version(2)), (True, g.RequestProtocolVersionReply(True).encode()),
             (False, rtde.send_text_message("hello")),
             (False, rtde.setup_outputs(["timestamp"], 125.0)), (True, g.SetupOutputsReply(1, ["DOUBLE"]).encode()),
             (False, rtde.start()), (True, g.StartReply(True).encode())]
    steps += [(True, g.DataPackage(1, {"timestamp": float(i)}).encode(recipe)) for i in range(30)]
    frames = capture.exchange_frames(steps, port=30004, lose=2)
    records, status = decode(str(capture.write(tmp_path / "rtde.pcap", frames)))
    assert status == 1
    assert not [r for r in records if "without a request seen" in r.get("warning", "")]
    types = [r["type"] for r in records]
    assert types[:7] == ["request_protocol_version", "request_protocol_version_reply", "error", "setup_outputs",
                         "setup_outputs_reply", "start", "start_reply"]
    assert records[2]["direction"] == "to_robot"
    assert records[4]["error"] == "reply after bytes lost from the capture: its setup is unknown"
    assert types[7:] == ["data_package"] * 30


def held_while_reading(monkeypatch, path) -> list[int]:
    """The bytes held out of order by all streams after each segment, while timed_streams reads."""
    from urwire import capture as reader
    from urwire.capture import _Reassembly

    streams: list = []
    held: list = []

    class Watched(_Reassembly):
        def __init__(self, *args):
            super().__init__(*args)
            streams.append(self)

        def add(self, seq, data):
            out = super().add(seq, data)
            held.append(sum(s.held_bytes for s in streams))
            return out

    monkeypatch.setattr(reader, "_Reassembly", Watched)
    monkeypatch.setattr(reader, "CCORE", None)   # the Python reader, whose streams are watched
    with open(path, "rb") as fh:
        for _ in reader.timed_streams(fh, {30003}):
            pass
    return held


def test_an_acknowledged_gap_holds_nothing_in_a_long_capture(monkeypatch, tmp_path):
    """A 2,000-packet real-time stream missing its tenth packet: the client's acknowledgement
    decides the gap at once, so no packet is held waiting for the end of the capture."""
    from urwire.capture import SEGMENT_COST

    packets = [packet(i) for i in range(2000)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003)
    del frames[3 + 2 * 10]
    held = held_while_reading(monkeypatch, capture.write(tmp_path / "long.pcap", frames))
    assert max(held) <= SIZE + SEGMENT_COST


def test_without_acknowledgements_the_peers_window_bounds_what_a_gap_holds(monkeypatch, tmp_path):
    """The client's acknowledgements are not in the capture either: what a stream holds behind a
    gap stays within the 65,535-byte window the client offered (no window scale in its SYN)."""
    from urwire.capture import SEGMENT_COST

    packets = [packet(i) for i in range(400)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003)
    frames = frames[:3] + frames[3:3 + 2 * 400:2] + frames[3 + 2 * 400:]   # the robot's segments only
    del frames[3 + 10]
    path = capture.write(tmp_path / "noacks.pcap", frames)
    held = held_while_reading(monkeypatch, path)
    assert max(held) <= 65535 + SIZE + (65535 // SIZE + 1) * SEGMENT_COST
    records, _ = decode(str(path))
    kinds = [r["type"] for r in records]
    assert kinds == ["rt_3_10"] * 10 + ["error"] + ["rt_3_10"] * 389


def test_a_retransmission_before_the_acknowledgement_passes_still_fills_the_gap(tmp_path):
    """The robot's segment is lost and retransmitted after later ones; the client's
    acknowledgements meanwhile stay at the gap: the retransmission fills it, nothing is missing."""
    packets = [packet(i) for i in range(12)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003)
    lost = frames[3 + 2 * 4]
    dup_ack = frames[3 + 2 * 3 + 1]           # the acknowledgement of the packet before it
    later = [frames[3 + 2 * i] for i in (5, 6, 7)]
    frames = frames[:3 + 2 * 4] + [f for seg in later for f in (seg, dup_ack)] + [lost] + frames[3 + 2 * 7 + 1:]
    records, status = decode(str(capture.write(tmp_path / "retransmitted.pcap", frames)))
    assert status == 0
    assert [r["time"] for r in records] == [float(i) for i in range(12)]


def test_an_acknowledgement_captured_before_its_segment_makes_no_gap(tmp_path):
    """The capture shows the client's acknowledgement of a robot segment before the segment, which
    comes after the next one (a capture that reordered them): the acknowledgement covers no byte
    held behind the gap, so the late segment still fills it."""
    packets = [packet(i) for i in range(10)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003)
    seg = {i: frames[3 + 2 * i] for i in range(10)}
    ack = {i: frames[3 + 2 * i + 1] for i in range(10)}
    frames = frames[:3 + 2 * 4] + [ack[4], seg[5], seg[4], ack[5]] + frames[3 + 2 * 6:]
    records, status = decode(str(capture.write(tmp_path / "reordered.pcap", frames)))
    assert status == 0
    assert [r["time"] for r in records] == [float(i) for i in range(10)]


def test_a_window_scaled_in_the_handshake_holds_what_it_lets_a_sender_send(monkeypatch, tmp_path):
    """The same capture, but the SYNs ask for a window scale of 7 (8 MiB): 400 packets behind the
    gap are within it, so they wait for the end of the stream, where the gap is given up."""
    packets = [packet(i) for i in range(400)]
    frames = capture.session_frames([Segment(True, p) for p in packets], port=30003, window_shift=7)
    frames = frames[:3] + frames[3:3 + 2 * 400:2] + frames[3 + 2 * 400:]
    del frames[3 + 10]
    path = capture.write(tmp_path / "scaled.pcap", frames)
    assert max(held_while_reading(monkeypatch, path)) > 389 * SIZE
    records, _ = decode(str(path))
    assert [r["type"] for r in records] == ["rt_3_10"] * 10 + ["error"] + ["rt_3_10"] * 389
