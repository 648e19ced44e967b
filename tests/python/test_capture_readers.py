"""The C capture reader (runtime/c/capture, urwire._ccore.CaptureStreams) against the Python one
(capture.py over dpkt): every capture the tests have, captures whose segments are reordered,
lost, repeated and changed, and damaged files give the same items: streams and their bytes,
gaps, retransmissions that differ, capture faults, times, and the conversations on no port."""
from __future__ import annotations

import random
from pathlib import Path

import pytest

from tests.tools import capture as pcap
from tests.tools.capture import Segment
from urwire import capture
from urwire.cell import ports_of
from urwire.extension import CCORE
from urwire.interfaces import INTERFACES

ROOT = Path(__file__).resolve().parents[2]
CAPTURES = sorted(p for folder in ("tests", "examples", "dissector") for pattern in ("*.pcap", "*.pcapng")
                  for p in (ROOT / folder).rglob(pattern))
BY_PORT = ports_of(INTERFACES.values())
BOTH_WAYS = frozenset(port for port, interface in BY_PORT.items() if interface.both_directions)

pytestmark = pytest.mark.skipif(CCORE is None, reason="the C extension is not built")


def items(path: Path, in_c: bool, monkeypatch) -> tuple[list, dict]:
    monkeypatch.setattr(capture, "CCORE", CCORE if in_c else None)
    others = capture.OtherConversations()
    with open(path, "rb") as fh:
        read = list(capture.timed_streams(fh, set(BY_PORT), BOTH_WAYS, others))
    return read, others.bytes


def assert_same(path: Path, monkeypatch) -> list:
    in_python, in_c = items(path, False, monkeypatch), items(path, True, monkeypatch)
    assert in_c[0] == in_python[0], path.name
    assert list(in_c[1].items()) == list(in_python[1].items()), path.name
    return in_c[0]


def test_there_are_captures_to_compare():
    assert len(CAPTURES) >= 10


@pytest.mark.parametrize("path", CAPTURES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_capture_of_the_tests_reads_the_same_in_c(path, monkeypatch):
    assert_same(path, monkeypatch)


def shuffled_session(seed: int, port: int) -> list[bytes]:
    """A session of one port whose robot segments come reordered, lost, repeated, overlapping
    and changed, as far as a seed says; the client acknowledges what it got, sometimes."""
    rng = random.Random(seed)
    stream = bytes(rng.randrange(256) for _ in range(6000))
    cuts = sorted(rng.sample(range(1, len(stream)), 40))
    pieces = [stream[a:b] for a, b in zip([0] + cuts, cuts + [len(stream)])]
    frames = pcap.session_frames([Segment(True, p) for p in pieces], port=port, client_port=50000 + seed)
    head, body, tail = frames[:3], frames[3:-4], frames[-4:]
    out = []
    for frame in body:
        roll = rng.random()
        if roll < 0.08:
            continue                        # lost
        if roll < 0.16:
            out.insert(max(0, len(out) - rng.randrange(1, 6)), frame)   # late
            continue
        out.append(frame)
        if roll > 0.9:
            copy = bytearray(frame)
            if rng.random() < 0.5 and len(copy) > 60:
                copy[-1 - rng.randrange(len(copy) - 60)] ^= 0xFF    # a retransmission that differs
            out.append(bytes(copy))
    return head + out + (tail if seed % 3 else [])


@pytest.mark.parametrize("seed", range(12))
def test_reordered_lost_repeated_and_changed_segments_read_the_same(seed, tmp_path, monkeypatch):
    frames = shuffled_session(seed, 30003) + shuffled_session(seed + 100, 29999)
    path = pcap.write(tmp_path / "shuffled.pcapng", frames, pcapng=bool(seed % 2))
    read = assert_same(path, monkeypatch)
    assert any(isinstance(item[2], (capture.Gap, capture.Differs)) for item in read if type(item) is tuple)


def test_a_lost_segment_the_client_acknowledges_reads_the_same(tmp_path, monkeypatch):
    payloads = [bytes([i % 256]) * 1400 for i in range(50)]
    frames = pcap.session_frames([Segment(True, p) for p in payloads], port=30003)
    del frames[3 + 2 * 10]                  # a robot segment (after the handshake's 3 frames)
    read = assert_same(pcap.write(tmp_path / "lost.pcap", frames), monkeypatch)
    assert [item[2] for item in read if isinstance(item[2], capture.Gap)] == [capture.Gap(10 * 1400, 1400)]


@pytest.mark.parametrize("path", [p for p in CAPTURES if p.stat().st_size < 40000][:6], ids=lambda p: p.name)
def test_damaged_copies_of_the_captures_read_the_same(path, tmp_path, monkeypatch):
    data = path.read_bytes()
    rng = random.Random(path.name)
    for n in range(40):
        damaged = bytearray(data)
        if n % 4 == 0:
            damaged = damaged[:rng.randrange(12, len(damaged))]       # cut short
        for _ in range(1 + n % 3):
            at = rng.randrange(24, len(damaged)) if len(damaged) > 24 else 0
            damaged[at] = rng.randrange(256)
        copy = tmp_path / f"damaged{n}{path.suffix}"
        copy.write_bytes(bytes(damaged))
        assert_same(copy, monkeypatch)
