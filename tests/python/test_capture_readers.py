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


# ---- runs of segments joined (capture.Segments), as a reader of large captures asks for ----

def events(read: list) -> list:
    """The items as events, a run of segments as its segments: (bytes, time) each, then the
    stream's end with the time of the item that ended it."""
    out = []
    for item in read:
        if type(item) is not tuple:
            out.append(item)
            continue
        key, from_robot, piece, ended, time = item
        if isinstance(piece, (bytes, capture.Segments)):
            pieces = piece.pieces() if isinstance(piece, capture.Segments) else [(piece, time)] if piece else []
            out += [("bytes", key, from_robot, data, at) for data, at in pieces]
            out += [("end", key, from_robot, time)] if ended else []
        else:
            out.append((key, from_robot, piece, ended, time))
    return out


def assert_joined_the_same(path: Path) -> list:
    with open(path, "rb") as fh:
        alone = list(capture.timed_streams(fh, set(BY_PORT), BOTH_WAYS))
    with open(path, "rb") as fh:
        joined = list(capture.timed_streams(fh, set(BY_PORT), BOTH_WAYS, joined=frozenset(BY_PORT)))
    assert events(joined) == events(alone), path.name
    return joined


@pytest.mark.parametrize("path", CAPTURES, ids=lambda p: str(p.relative_to(ROOT)))
def test_runs_of_segments_joined_hold_each_segment_and_its_time(path):
    assert_joined_the_same(path)


def test_runs_are_joined_between_faults_and_other_conversations(tmp_path):
    one, other = shuffled_session(3, 30003), shuffled_session(104, 30001)
    frames = [frame for at in range(0, max(len(one), len(other)), 6) for frame in one[at:at + 6] + other[at:at + 6]]
    joined = assert_joined_the_same(pcap.write(tmp_path / "shuffled.pcap", frames))
    runs = [item[2] for item in joined if type(item) is tuple and isinstance(item[2], capture.Segments)]
    assert max(len(run.pieces()) for run in runs) > 3
    assert any(isinstance(item[2], (capture.Gap, capture.Differs)) for item in joined if type(item) is tuple)


# ---- the link layers, IPv6 and pcapng's interfaces and sections, in one capture ----

def links(ethernet: bytes) -> dict[int, bytes]:
    """One Ethernet IPv4 frame in every link type both readers take, by their pcapng link type:
    (0) null, (1) Ethernet with a VLAN tag, (101) raw IP, (113) Linux cooked, (276) its v2;
    and an Ethernet frame of QinQ tags, under a link type of its own key (1001)."""
    macs, ip = ethernet[:12], ethernet[14:]
    return {0: (2).to_bytes(4, "little") + ip,
            1: macs + b"\x81\x00\x00\x07\x08\x00" + ip,
            101: ip,
            113: b"\x00\x00\x00\x01\x00\x06" + ethernet[6:12] + b"\x00\x00\x08\x00" + ip,
            276: b"\x08\x00\x00\x00\x00\x00\x00\x02\x00\x01\x00\x06" + ethernet[6:12] + b"\x00\x00" + ip,
            1001: macs + b"\x88\xa8\x00\x05\x81\x00\x00\x07\x08\x00" + ip}


def ipv6_of(ethernet: bytes) -> bytes:
    """The same segment over IPv6 (the IPv4 addresses mapped), in an Ethernet frame."""
    ip = ethernet[14:]
    header = (ip[0] & 15) * 4
    tcp = ip[header:int.from_bytes(ip[2:4], "big")]
    src, dst = b"\xfe\x80" + b"\x00" * 10 + ip[12:16], b"\xfe\x80" + b"\x00" * 10 + ip[16:20]
    return ethernet[:12] + b"\x86\xdd" + b"\x60\x00\x00\x00" + len(tcp).to_bytes(2, "big") + b"\x06\x40" + src + \
        dst + tcp


def block(kind: int, body: bytes, order: str) -> bytes:
    body += b"\x00" * (-len(body) % 4)
    length = (12 + len(body)).to_bytes(4, "little" if order == "<" else "big")
    return kind.to_bytes(4, "little" if order == "<" else "big") + length + body + length


def section(order: str, faces: list[tuple[int, int]], packets: list[tuple[int, int, bytes]]) -> bytes:
    """A pcapng section in byte order `order`: interfaces (link type, if_tsresol or None), then
    packets (interface, timestamp in its units, frame)."""
    import struct

    out = block(0x0A0D0D0A, struct.pack(order + "IHHq", 0x1A2B3C4D, 1, 0, -1), order)
    for linktype, tsresol in faces:
        options = b"" if tsresol is None else struct.pack(order + "HHB3x", 9, 1, tsresol) + b"\x00" * 4
        out += block(1, struct.pack(order + "HHI", linktype, 0, 0) + options, order)
    for face, stamp, frame in packets:
        out += block(6, struct.pack(order + "IIIII", face, stamp >> 32, stamp & 0xFFFFFFFF, len(frame), len(frame))
                     + frame, order)
    return out


def test_every_link_type_ipv6_and_pcapng_interfaces_and_sections_read_the_same(tmp_path, monkeypatch):
    payloads = [bytes([i]) * (100 + i) for i in range(48)]
    frames = pcap.session_frames([Segment(True, p) for p in payloads], port=30001)
    faces = [(0, None), (1, 9), (101, 0x86), (113, 3), (276, None), (1, 6)]     # the last: QinQ
    first = [(i % 6, 1_700_000_000_000 + i, links(f)[1001 if i % 6 == 5 else faces[i % 6][0]])
             for i, f in enumerate(frames[:len(frames) // 2])]
    # A second section, in the other byte order: interfaces start again, IPv6 over Ethernet.
    second = [(0, 1_700_000_100 + i, ipv6_of(f)) for i, f in enumerate(frames[len(frames) // 2:])]
    path = tmp_path / "links.pcapng"
    path.write_bytes(section("<", faces, first) + section(">", [(1, 0)], second))
    read = assert_same(path, monkeypatch)
    streams = {}
    for key, from_robot, piece, _, _ in read:
        streams.setdefault(key, b"")
        streams[key] += piece if isinstance(piece, bytes) else b""
    # Every byte read: each link type and both sections parsed, the stream cut between IPv4 and IPv6.
    assert len(streams) == 2 and sum(map(len, streams.values())) == sum(map(len, payloads))
    assert any(":" in key[0] for key in streams)
    times = sorted({item[4] for item in read})
    assert times[0] < 1_700_000_000.01 and times[-1] >= 1_700_000_100


@pytest.mark.deep
def test_the_c_reader_under_asan_and_ubsan(tmp_path):
    """The same comparisons through an urwire._ccore built with ASan and UBSan
    (capture_asan_peer.py): no difference, no report."""
    from tests.tools import ccore_sanitized

    result = ccore_sanitized.run_peer("capture_asan_peer.py", tmp_path)
    assert result.returncode == 0, result.stderr[-3000:]
    assert int(result.stdout.split()[-1]) >= 30
