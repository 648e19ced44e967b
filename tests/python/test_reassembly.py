"""TCP reassembly of robot->client streams: in order, retransmissions dropped, gaps closed,
every byte given up or retransmitted differently named."""
from __future__ import annotations

from urwire.capture import Differs, Gap, _Reassembly

DATA = bytes(range(200))


def joined(pieces: list) -> bytes:
    return b"".join(p for p in pieces if isinstance(p, bytes))


def faults(pieces: list) -> list:
    return [p for p in pieces if not isinstance(p, bytes)]


def pieces_of(segments, start=1000) -> list:
    stream = _Reassembly(start)
    out: list = []
    for seq, data in segments:
        out += stream.add(seq, data)
    return out + stream.flush()


def feed(segments, start=1000):
    """The stream's bytes, where the segments leave no gap and repeat no byte differently."""
    pieces = pieces_of(segments, start)
    assert faults(pieces) == []
    return joined(pieces)


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
    assert stream.add(77777, DATA[:10]) == [DATA[:10]]
    assert stream.add(77787, DATA[10:]) == [DATA[10:]]


def test_a_gap_never_filled_is_given_up_at_the_end_and_named():
    segs = [(1000, DATA[:50]), (1100, DATA[100:])]
    assert pieces_of(segs) == [DATA[:50], Gap(50, 50), DATA[100:]]


def test_every_gap_before_held_bytes_is_named_at_the_end():
    """Held segments behind two gaps: both gaps named, every held byte delivered after its gap."""
    segs = [(1000, DATA[:20]), (1050, DATA[50:60]), (1100, DATA[100:120]), (1120, DATA[120:130])]
    assert pieces_of(segs) == [DATA[:20], Gap(20, 30), DATA[50:60], Gap(60, 40), DATA[100:120], DATA[120:130]]


def test_a_gap_at_the_start_of_a_stream_is_named():
    assert pieces_of([(1010, DATA[10:40])]) == [Gap(0, 10), DATA[10:40]]


def test_a_retransmission_that_differs_is_named_and_the_first_copy_kept():
    changed = DATA[30:40] + b"\xff\xfe" + DATA[42:60]
    pieces = pieces_of([(1000, DATA[:50]), (1030, changed), (1060, DATA[60:80])])
    assert joined(pieces) == DATA[:80]
    assert faults(pieces) == [Differs(30, 20, 2)]
    assert "differ" in faults(pieces)[0].error


def test_a_differing_copy_of_held_bytes_is_named():
    pieces = pieces_of([(1050, DATA[50:70]), (1050, DATA[50:60] + b"x" * 15), (1000, DATA[:50])])
    assert joined(pieces) == DATA[:70] + b"x" * 5      # the first copy, and what the longer one adds
    assert faults(pieces) == [Differs(50, 20, 10)]


def test_a_retransmission_past_the_bytes_kept_is_named(monkeypatch):
    from urwire import capture

    monkeypatch.setattr(capture, "HISTORY_KEPT", 16)
    pieces = pieces_of([(1000 + i, DATA[i:i + 10]) for i in range(0, 200, 10)] + [(1000, DATA[:10])])
    assert faults(pieces) == [Differs(0, 10)]
    assert "could not be compared" in faults(pieces)[0].error


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


def test_a_gap_given_up_goes_on_from_the_earliest_segment_held():
    stream = _Reassembly(1000)
    assert stream.add(1000, DATA[:10]) == [DATA[:10]]
    assert stream.add(1140, DATA[140:180]) == []
    assert stream.add(1100, DATA[100:140]) == []
    assert stream.skip_gap() == [Gap(10, 90), DATA[100:140], DATA[140:180]]
    assert stream.held_bytes == 0
    assert stream.add(1180, DATA[180:]) == [DATA[180:]]
    # Too late, already given up: bytes from before the gap, which cannot be compared.
    assert stream.add(1050, DATA[50:100]) == [Differs(50, 50)]


def test_each_held_segment_counts_what_holding_it_costs():
    """One-byte segments weigh their objects, not their one byte: a capture of tiny segments
    behind a gap cannot hold a hundred times MAX_PENDING."""
    from urwire.capture import SEGMENT_COST

    stream = _Reassembly(1000)
    for i in range(100, 150):
        stream.add(1000 + i, DATA[i:i + 1])
    stream.add(1120, DATA[120:125])   # a longer retransmission: its extra bytes only
    assert stream.held_bytes == 50 * (1 + SEGMENT_COST) + 4
    assert joined(stream.add(1000, DATA[:100])) == DATA[:150]
    assert stream.held_bytes == 0


def test_the_streams_together_hold_at_most_max_pending(monkeypatch, tmp_path):
    """Two sessions, each missing its second segment and every acknowledgement: the one holding
    the most gives up its gap whenever all of them hold more than MAX_PENDING, long before the
    capture ends."""
    from tests.tools import capture as pcap
    from urwire import capture

    monkeypatch.setattr(capture, "MAX_PENDING", 2000)
    streams = []

    class Watched(_Reassembly):
        def __init__(self, *args):
            super().__init__(*args)
            streams.append(self)

        def add(self, seq, data):
            out = super().add(seq, data)
            held.append(sum(s.held_bytes for s in streams))
            return out

    held: list = []
    monkeypatch.setattr(capture, "_Reassembly", Watched)
    monkeypatch.setattr(capture, "CCORE", None)   # the Python reader, whose streams are watched
    payloads = {port: [bytes([port % 256, i]) * 50 for i in range(40)] for port in (50001, 50002)}
    sessions = [pcap.session_frames([pcap.Segment(True, p) for p in payloads[port]], client_port=port)
                for port in payloads]
    for i, frames in enumerate(sessions):
        # Only the robot's segments after the handshake (no acknowledgement decides a gap), and of
        # them not the second.
        frames = sessions[i] = frames[:3] + frames[3:3 + 2 * 40:2]
        del frames[3 + 1]
    frames = [f for pair in zip(*sessions) for f in pair]
    path = pcap.write(tmp_path / "gaps.pcap", frames)
    got: dict = {}
    before_the_end: dict = {}
    gaps: dict = {}
    with path.open("rb") as fh:
        for (_, _, _, port), _, piece, ended, _ in capture.timed_streams(fh, {30001}):
            if isinstance(piece, Gap):
                gaps.setdefault(port, []).append(piece)
                continue
            got[port] = got.get(port, b"") + piece
            if not ended:
                before_the_end[port] = got[port]
    for port, sent in payloads.items():
        assert got[port] == sent[0] + b"".join(sent[2:])
        assert before_the_end[port].startswith(sent[0] + sent[2])
        assert gaps[port] == [Gap(100, 100)]
    assert max(held) <= 2000 + 100 + capture.SEGMENT_COST


def test_a_gap_the_peer_acknowledged_is_given_up_at_once():
    """The peer acknowledged bytes beyond the gap: it got them and the capture did not, so the
    stream goes on at once instead of waiting for the end of the capture."""
    stream = _Reassembly(1000)
    assert stream.add(1000, DATA[:10]) == [DATA[:10]]
    assert stream.add(1100, DATA[100:140]) == []
    assert stream.ack(1140, 65535) == [Gap(10, 90), DATA[100:140]]
    assert stream.held_bytes == 0


def test_an_acknowledgement_of_no_held_byte_decides_nothing():
    """A capture may show an acknowledgement before the segment it acknowledges (its directions
    reordered): only one that covers bytes held behind the gap shows the gap final."""
    stream = _Reassembly(1000)
    assert stream.add(1000, DATA[:10]) == [DATA[:10]]
    assert stream.ack(1140, 65535) == []          # nothing held yet
    assert stream.add(1100, DATA[100:140]) == []
    assert stream.ack(1100, 65535) == []          # up to the bytes held, not into them
    assert stream.add(1010, DATA[10:100]) == [DATA[10:100], DATA[100:140]]
    assert stream.flush() == []


def test_an_acknowledgement_gives_up_every_gap_before_the_bytes_it_covers():
    stream = _Reassembly(1000)
    stream.add(1000, DATA[:10])
    stream.add(1050, DATA[50:60])
    stream.add(1100, DATA[100:140])
    assert stream.ack(1055, 65535) == [Gap(10, 40), DATA[50:60]]
    assert stream.ack(1101, 65535) == [Gap(60, 40), DATA[100:140]]


def test_a_retransmission_before_the_acknowledgement_passes_fills_the_gap():
    stream = _Reassembly(1000)
    stream.add(1000, DATA[:10])
    stream.add(1100, DATA[100:140])
    assert stream.ack(1010, 65535) == []          # duplicate acknowledgements: the gap is not final
    assert stream.ack(1010, 65535) == []
    assert stream.add(1010, DATA[10:100]) == [DATA[10:100], DATA[100:140]]
    assert stream.flush() == []


def test_held_bytes_beyond_the_peers_window_give_up_the_gap():
    """The acknowledgement was lost too: a sender never goes further than the window the peer
    offered beyond what it acknowledged, so bytes held further than that are past a final gap."""
    stream = _Reassembly(1000)
    stream.add(1000, DATA[:10])
    stream.ack(1010, 100)
    assert stream.add(1100, DATA[100:105]) == []          # 95 bytes ahead: within the window
    assert stream.add(1105, DATA[105:140]) == [Gap(10, 90), DATA[100:105], DATA[105:140]]
