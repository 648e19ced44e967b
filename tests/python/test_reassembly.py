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


def test_out_of_order_overlapping_and_repeated_segments_are_joined_once():
    segs = [(1150, DATA[150:]), (1100, DATA[100:160]), (1150, DATA[150:170]), (1120, DATA[120:190]),
            (1100, DATA[100:180]), (1000, DATA[:110])]
    assert feed(segs) == DATA


def test_out_of_order_segments_across_the_sequence_wrap():
    start = 0xFFFFFFFF - 120
    segs = [((start + i) & 0xFFFFFFFF, DATA[i:i + 20]) for i in range(0, 200, 20)]
    assert feed(segs[::-1], start) == DATA
    assert feed(segs[1::2] + segs[::2], start) == DATA


def segments(count: int, size: int = 7, start: int = 1000) -> tuple[bytes, list]:
    data = bytes(i % 251 for i in range(count * size))
    return data, [(start + i, data[i:i + size]) for i in range(0, len(data), size)]


def test_reversed_segments_cost_what_in_order_ones_do(monkeypatch):
    """Each segment is compared with the stream position a bounded number of times, however
    late it comes (held segments are kept ordered by sequence number)."""
    from urwire import capture

    comparisons = []
    real = capture._delta
    monkeypatch.setattr(capture, "_delta", lambda seq, ref: comparisons.append(1) or real(seq, ref))
    data, segs = segments(3000)
    for order in (segs, segs[::-1], segs[1::2] + segs[::2]):
        comparisons.clear()
        assert feed(order) == data
        assert len(comparisons) <= 3 * len(segs)


def test_too_many_held_bytes_give_up_the_gap(monkeypatch):
    from urwire import capture

    monkeypatch.setattr(capture, "MAX_PENDING", 50)
    stream = _Reassembly(1000)
    assert stream.add(1000, DATA[:10]) == DATA[:10]
    assert stream.add(1140, DATA[140:180]) == b""
    assert stream.add(1100, DATA[100:140]) == DATA[100:180]   # 80 bytes held: the gap is given up
    assert stream.add(1180, DATA[180:]) == DATA[180:]
    assert stream.add(1050, DATA[50:100]) == b""               # too late: already given up
