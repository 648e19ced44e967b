"""A real-time stream that lost a TCP segment, in Wireshark: both dissectors skip the middle of a
packet the segments after the gap start in, up to the next size some layout has (one error on the
skipped bytes), and frame every packet from there, as `urwire decode` does. Several gap positions
and segment sizes; tshark with the Lua dissector, tshark with the native plugin and urwire decode
show the same packets, and the two dissectors the same frames, Info column and expert infos."""
from __future__ import annotations

import json
import random
import struct
import subprocess
import sys

import pytest

from tests.native import harness
from tests.native.lua_twin import compare, readable, run_lua, run_native
from tests.tools import capture
from tests.tools.capture import Segment

PROTOCOL = "ur_realtime"
SIZE = 1220                 # rt_5_10
COUNT = 300
ENV = {"PYTHONPATH": f"{harness.ROOT / 'python'}:{harness.ROOT / 'generated' / 'python'}"}
# (segment size, index of the lost segment): segments smaller and larger than a packet, lost from
# the start, the middle and near the end of the stream
GAPS = [(1000, 1), (1448, 3), (700, 40), (1448, 150), (3000, 60), (1000, 297)]


@pytest.fixture(scope="module", autouse=True)
def built():
    return harness.plugin("gcc")


def packet(number: int) -> bytes:
    """A packet whose time is its number; its other doubles vary, so the bytes after a gap read as
    any size."""
    rng = random.Random(number)
    doubles = [float(number)] + [rng.uniform(-3.0, 3.0) for _ in range((SIZE - 4) // 8 - 1)]
    return struct.pack(f">i{len(doubles)}d", SIZE, *doubles)


def lost_segment(tmp_path, segment: int, lost: int):
    stream = b"".join(packet(i) for i in range(COUNT))
    payloads = [stream[i:i + segment] for i in range(0, len(stream), segment)]
    frames = capture.session_frames([Segment(True, p) for p in payloads], port=30003)
    del frames[3 + 2 * lost]                  # after the handshake's 3 frames, one robot segment per 2
    return readable(capture.write(tmp_path / f"lost-{segment}-{lost}.pcap", frames))


def tshark_times(result: subprocess.CompletedProcess) -> list[float]:
    layers = json.loads(harness.checked(result) or "[]")
    return sorted(float(t) for p in layers for t in p["_source"]["layers"]["ur_realtime.time"])


def decoded_times(pcap) -> list[float]:
    res = subprocess.run([sys.executable, "-m", "urwire", "decode", str(pcap)], capture_output=True, text=True,
                         env=ENV, timeout=300)
    assert res.returncode == 1, res.stderr            # the gap is an error record
    return sorted(r["time"] for r in map(json.loads, res.stdout.splitlines()) if r["type"] == "rt_5_10")


@pytest.mark.parametrize("segment,lost", GAPS, ids=lambda v: str(v))
def test_wireshark_decodes_every_packet_urwire_decode_does_after_a_gap(tmp_path, segment, lost):
    pcap = lost_segment(tmp_path, segment, lost)
    args = ("-2", "-T", "json", "-e", "ur_realtime.time", "-Y", "ur_realtime.time")
    lua = tshark_times(run_lua(pcap, *args, protocol=PROTOCOL))
    native = tshark_times(run_native(pcap, *args, alone=PROTOCOL))
    decoded = decoded_times(pcap)
    start, end = lost * segment, (lost + 1) * segment
    touched = {i for i in range(COUNT) if i * SIZE < end and start < (i + 1) * SIZE}
    assert decoded == [float(i) for i in range(COUNT) if i not in touched]
    assert lua == decoded
    assert native == decoded


@pytest.mark.parametrize("segment,lost", GAPS[:3], ids=lambda v: str(v))
def test_lua_and_native_show_the_same_frames_after_a_gap(tmp_path, segment, lost):
    pcap = lost_segment(tmp_path, segment, lost)
    shown = compare(pcap, PROTOCOL)
    bad = [e for e in shown.experts if "cannot frame a packet" in str(e)]
    assert len(bad) == 1, shown.experts            # one error, on the bytes skipped after the gap
    # The expert tap builds no tree: the same error there, in both.
    tap = harness.checked(run_lua(pcap, "-q", "-z", "expert", protocol=PROTOCOL))
    assert "cannot frame a packet" in tap
    assert harness.checked(run_native(pcap, "-q", "-z", "expert", alone=PROTOCOL)) == tap
