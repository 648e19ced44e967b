"""TCP reassembly of robot->client streams: in order, retransmissions dropped, gaps closed."""
from __future__ import annotations

from urwire.capture import _Reassembly

DATA = bytes(range(200))


def feed(segments, start=1000):
    stream = _Reassembly(start)
    out = b""
    for seq, data in segments:
        out += stream.add(seq, data)
    return out + stream.flush()


def test_in_order_segments_are_joined():
    assert feed([(1000, DATA[:50]), (1050, DATA[50:])]) == DATA


def test_retransmitted_and_overlapping_segments_are_dropped():
    segs = [(1000, DATA[:80]), (1000, DATA[:80]), (1040, DATA[40:120]), (1120, DATA[120:])]
    assert feed(segs) == DATA


def test_out_of_order_segments_wait_for_the_gap():
    segs = [(1100, DATA[100:150]), (1150, DATA[150:]), (1000, DATA[:100])]
    assert feed(segs) == DATA


def test_sequence_numbers_wrap_around():
    start = 0xFFFFFFFF - 60
    segs = [(start, DATA[:100]), ((start + 100) & 0xFFFFFFFF, DATA[100:])]
    assert feed(segs, start) == DATA


def test_a_capture_starting_mid_stream_starts_at_its_first_segment():
    stream = _Reassembly()
    assert stream.add(77777, DATA[:10]) == DATA[:10]
    assert stream.add(77787, DATA[10:]) == DATA[10:]


def test_a_gap_never_filled_is_given_up_at_the_end():
    segs = [(1000, DATA[:50]), (1100, DATA[100:])]
    assert feed(segs) == DATA[:50] + DATA[100:]
