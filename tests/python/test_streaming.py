"""The framer takes bytes in chunks of any size, split anywhere, and gives the same records."""
from __future__ import annotations

import random
import struct

import urwire
from hypothesis import given, settings, strategies as st

from tests.vectors import all_cases

# The conformance sample of a fake server: project "UR", software 5.24, build 42.
MINIMAL_VERSION = bytes.fromhex("0000001c140000000000000000fe030255520518000000000000002a")

CASES = all_cases()
STREAM = b"".join(c.data for c in CASES if c.version is None)


def lines(records) -> list[str]:
    return [urwire.to_json_line(r) for r in records]


WHOLE = lines(urwire.decode_stream(STREAM))


def chunked(data: bytes, cuts: list[int]):
    points = sorted({c % (len(data) + 1) for c in cuts})
    edges = [0] + points + [len(data)]
    return [data[a:b] for a, b in zip(edges, edges[1:])]


def test_one_byte_chunks_give_the_same_records():
    assert lines(urwire.decode_stream(STREAM[i:i + 1] for i in range(len(STREAM)))) == WHOLE


def test_one_mebibyte_chunks_give_the_same_records():
    data = STREAM * 40
    expected = lines(urwire.decode_stream(data))
    assert lines(urwire.decode_stream(data[i:i + (1 << 20)] for i in range(0, len(data), 1 << 20))) == expected
    assert len(expected) > 40 * len(WHOLE) // 2


@settings(max_examples=150, deadline=None)
@given(cuts=st.lists(st.integers(min_value=0), max_size=60))
def test_any_split_gives_the_same_records(cuts):
    assert lines(urwire.decode_stream(chunked(STREAM, cuts))) == WHOLE


def test_version_is_learned_from_the_version_message():
    framer = urwire.Framer()
    assert framer.version == urwire.DEFAULT_VERSION and not framer.version_seen
    version_5_0 = MINIMAL_VERSION[:19] + b"\x00" + MINIMAL_VERSION[20:]
    framer.feed(version_5_0)
    assert framer.version == (5, 0, 0) and framer.version_seen
    # The document's example, in 3.3/5.0 codes: BOOL true, CONST_STRING "aaaa".
    body = bytes(8) + b"\x01" + b"\x00\x00" + bytes.fromhex("0c010a030004616161610a")
    (msg,) = framer.feed((len(body) + 5).to_bytes(4, "big") + b"\x19" + body)
    assert [(v.type, v.value) for v in msg.variables] == [("BOOL", True), ("CONST_STRING", "aaaa")]


def version_with_bugfix(bugfix: int) -> bytes:
    """MINIMAL_VERSION as 5.0 with the given bugfix number (an int32 from 3.3)."""
    return MINIMAL_VERSION[:19] + b"\x00" + struct.pack(">i", bugfix) + MINIMAL_VERSION[24:]


def test_a_bugfix_out_of_range_keeps_major_minor_and_is_flagged():
    for bugfix in (-1, -(1 << 31), 1000, (1 << 31) - 1):
        framer = urwire.Framer()
        (msg,) = framer.feed(version_with_bugfix(bugfix))
        assert msg.bugfix_version == bugfix  # the record keeps what came
        assert framer.version == framer.announced == (5, 0, 0) and framer.version_seen
        assert framer.version_note == (f"Version message at offset 0: bugfix version {bugfix} is out of range "
                                       "(0 to 999); the stream is read as 5.0")
        # A later Version message in range sets its version and clears the note.
        framer.feed(version_with_bugfix(999))
        assert framer.version == (5, 0, 999) and framer.version_note is None


def test_a_bugfix_in_range_is_no_note():
    framer = urwire.Framer()
    framer.feed(MINIMAL_VERSION)
    assert framer.version == (5, 24, 0) and framer.version_note is None


def test_hint_applies_until_a_version_message():
    body = bytes(8) + b"\x01" + b"\x00\x00" + bytes.fromhex("0c010a030004616161610a")
    update = (len(body) + 5).to_bytes(4, "big") + b"\x19" + body
    (under_5_0,) = urwire.decode_stream(update, "5.0")
    (under_5_9,) = urwire.decode_stream(update)
    assert under_5_0.variables[0].type == "BOOL"
    assert isinstance(under_5_9, urwire.MalformedSubtype)  # 0x0c is POSE under 5.9: too short


def test_resynchronises_without_losing_what_follows():
    good = MINIMAL_VERSION
    garbage = b"\xff\xff\xff\xff\x01\x02\x03"  # no 5 bytes of it make a plausible header
    records = list(urwire.decode_stream(good + garbage + good + b"\x00\x00\x00"))
    kinds = [type(r).__name__ for r in records]
    assert kinds == ["VersionMessage", "StreamError", "VersionMessage", "StreamError"]
    assert records[1].offset == len(good)
    assert records[3].error == "truncated header: 3 bytes left"


def text_message(text: bytes, timestamp: int = 1) -> bytes:
    body = struct.pack(">QbB", timestamp, -2, 0) + text
    return struct.pack(">iB", 5 + len(body), 20) + body


def test_a_truncated_tail_is_rescanned_for_whole_messages():
    """A length that runs past the end of the stream is one fault; what it would have swallowed
    is framed again, in any chunking."""
    first, second = text_message(b"first"), text_message(b"second", 2)
    data = struct.pack(">iB", 1000, 16) + first + second
    expected = [f'{{"type": "error", "offset": 0, "error": "truncated message: length 1000, {len(data)} bytes left"}}',
                *lines([urwire.decode_message(first), urwire.decode_message(second)])]
    assert lines(urwire.decode_stream(data)) == expected
    assert lines(urwire.decode_stream(data[i:i + 1] for i in range(len(data)))) == expected


def test_a_message_after_the_recovered_ones_may_be_cut_again():
    inner = text_message(b"inner")
    cut = text_message(b"cut short")[:12]
    data = struct.pack(">iB", 500, 20) + inner + cut
    records = list(urwire.decode_stream(data))
    assert lines(records[1:2]) == lines([urwire.decode_message(inner)])
    assert [(r.offset, r.error) for r in records[::2]] == [
        (0, f"truncated message: length 500, {len(data)} bytes left"),
        (5 + len(inner), f"truncated message: length {len(text_message(b'cut short'))}, 12 bytes left")]


def nested_tail(headers: int, then: bytes) -> bytes:
    """Headers one after the other, then `then`; each header declares a length that runs one byte
    past the end."""
    end = 5 * headers + len(then)
    return b"".join(struct.pack(">iB", end + 1 - 5 * i, 20) for i in range(headers)) + then


def test_a_tail_of_nested_lengths_is_one_fault_rescanned_in_linear_work(monkeypatch):
    from urwire import framer

    checks = []
    real = framer._fault
    monkeypatch.setattr(framer, "_fault", lambda length, mtype: checks.append(1) or real(length, mtype))
    data = nested_tail(20_000, text_message(b"after"))
    records = list(urwire.decode_stream(data))
    assert lines(records) == [
        f'{{"type": "error", "offset": 0, "error": "truncated message: length {len(data) + 1}, {len(data)} bytes left"}}',
        '{"type": "text", "timestamp": 1, "source": -2, "text": "after"}']
    assert len(checks) <= 2 * len(data)


def test_resynchronising_checks_only_the_places_a_header_could_start(monkeypatch):
    """Over bytes that hold no header, the full check runs only where a length's first byte and
    a known type line up (about 1 place in 8,000 of random bytes), and the stream goes on."""
    from urwire import framer

    checks = []
    real = framer._fault
    monkeypatch.setattr(framer, "_fault", lambda length, mtype: checks.append(1) or real(length, mtype))
    rng = random.Random(12)
    junk = bytes(rng.getrandbits(8) for _ in range(1 << 20))
    after = text_message(b"after")
    records = list(urwire.decode_stream(b"\xff" + junk + after))
    assert lines(records[-1:]) == ['{"type": "text", "timestamp": 1, "source": -2, "text": "after"}']
    assert len(checks) < len(junk) // 1000


def test_feed_lazily_makes_each_record_as_it_is_iterated():
    """The same records as feed(), but the second is not read before the first is taken: a
    Version message after the first record has not set the version yet. decode_stream reads so,
    and so holds one record at a time for a reader that drops each."""
    data = text_message(b"first") + MINIMAL_VERSION
    framer = urwire.Framer()
    records = framer.feed_lazily(data)
    first = next(records)
    assert not framer.version_seen
    rest = list(records)
    assert framer.version_seen and framer.version == (5, 24, 0)
    assert lines([first, *rest]) == lines(urwire.Framer().feed(data)) and len(rest) == 1
