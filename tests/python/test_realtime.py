"""The real-time interface in Python: a packet's size chooses its class, decode/encode give back
the same bytes, sizes no layout has are kept and framing goes on, and no bytes make it raise."""
import json
import struct

import pytest
from hypothesis import given, settings, strategies as st

import urwire
from urwire._runtime import StreamError
from urwire.generated import ur_realtime as rt
from urwire.realtime import RealtimeFramer, UnknownPacket, decode_packet, decode_stream, form_of, names_of

from tests.vectors import interface_cases, mismatches


def packet(size: int, first: float = 0.0) -> bytes:
    """A packet of `size` bytes whose doubles count up from `first` (built with struct, not urwire)."""
    n = (size - 4) // 8
    return struct.pack(f">i{n}d", size, *(first + i for i in range(n)))


def test_each_size_decodes_into_its_layout_and_back():
    for size, forms in rt.FORMS_BY_SIZE.items():
        data = packet(size)
        record = decode_packet(data)
        assert type(record) is forms[-1][2] and record.message_size == size
        assert record.encode() == data


def test_fields_sit_where_the_document_puts_them():
    record = decode_packet(packet(1116))
    assert record.time == 0.0 and record.q_target == (1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    assert record.q_actual == (31.0, 32.0, 33.0, 34.0, 35.0, 36.0)       # gnuplot columns 32-37
    assert record.robot_mode == 94.0 and record.safety_status == 138.0   # columns 95 and 139
    line = urwire.to_dict(record)
    assert line["type"] == "rt_3_10" and line["message_size"] == 1116 and line["q_actual"][0] == 31.0


def test_labels_and_units_are_metadata():
    import dataclasses
    meta = {f.name: f.metadata for f in dataclasses.fields(rt.Rt3_10)}
    assert meta["q_actual"] == {"label": "Actual joint position", "unit": "rad", "count": 6,
                                "items": ("Base", "Shoulder", "Elbow", "Wrist 1", "Wrist 2", "Wrist 3")}
    assert meta["motor_temperatures"]["unit"] == "°C"
    # a pose names its axes, and each axis its unit, as the Wireshark tree does
    assert meta["tool_vector_actual"]["items"] == ("X", "Y", "Z", "RX", "RY", "RZ")
    assert meta["tool_vector_actual"]["item_units"] == ("m", "m", "m", "rad", "rad", "rad")
    assert "item_units" not in meta["q_actual"] and "items" not in meta["time"]


def test_an_unknown_size_is_kept_raw_and_framing_goes_on():
    odd = struct.pack(">i3d", 28, 1.0, 2.0, 3.0)
    records = decode_stream(packet(1060) + odd + packet(1060, 5.0))
    assert [type(r) for r in records] == [rt.Rt3_2, UnknownPacket, rt.Rt3_2]
    unknown = records[1]
    assert unknown.error == "packet at offset 1060: size 28 matches no layout"
    assert unknown.encode() == odd
    assert urwire.to_dict(unknown) == {"type": "unknown", "message_size": 28,
                                       "error": "packet at offset 1060: size 28 matches no layout",
                                       "raw": odd[4:].hex()}


def test_chunks_of_any_size_give_the_same_records():
    stream = packet(1220) + packet(1108, 2.0) + packet(812)
    whole = [urwire.to_json_line(r) for r in decode_stream(stream)]
    for step in (1, 3, 4, 7, 1000):
        framer = RealtimeFramer()
        got = []
        for i in range(0, len(stream), step):
            got += framer.feed(stream[i:i + step])
        got += framer.close()
        assert [urwire.to_json_line(r) for r in got] == whole


def test_a_cut_tail_and_a_broken_size_are_stream_errors():
    cut = decode_stream(packet(1116) + packet(1116)[:100])
    assert cut[-1] == StreamError(1116, "packet at offset 1116: needs 1116 bytes, 100 left")
    assert decode_stream(packet(1116)[:2]) == [StreamError(0, "packet at offset 0: needs 4 bytes, 2 left")]
    broken = decode_stream(struct.pack(">i", 3) + packet(1116))
    assert broken[0] == StreamError(0, "packet at offset 0: size 3 is below 12")
    assert [r.message_size for r in broken[1:]] == [1116]      # framing goes on at the next packet
    huge = decode_stream(struct.pack(">i", 1 << 30) + bytes(100))
    assert huge == [StreamError(0, f"packet at offset 0: size {1 << 30} is above {rt.MAX_MESSAGE_SIZE}")]


def test_after_a_size_that_cannot_frame_a_packet_framing_goes_on_at_the_next_one():
    """The middle of a packet (a stream that lost bytes, or joined across them) reads as a bad size;
    the scan finds the next packet by a size some layout has, and every packet after it is decoded."""
    whole = b"".join(packet(1116, float(i)) for i in range(6))
    stream = whole[:1116] + whole[2 * 1116 + 500:]          # from the middle of packet 2 on
    records = decode_stream(stream)
    errors = [r for r in records if isinstance(r, StreamError)]
    assert len(errors) == 1 and errors[0].offset == 1116
    assert [r.time for r in records if not isinstance(r, StreamError)] == [0.0, 3.0, 4.0, 5.0]


def test_the_scan_trusts_only_sizes_a_layout_has():
    """A packet's doubles hold small int32s (2.0 after 0.0 reads 64): a scan that took any size
    that frames a packet would frame garbage."""
    unknown = struct.pack(">i", 40) + bytes(36)
    records = decode_stream(struct.pack(">i", 5) + bytes(9) + unknown * 3 + packet(812))
    assert records[0] == StreamError(0, "packet at offset 0: size 5 is below 12")
    assert [r.message_size for r in records[1:]] == [812]


def test_the_version_picks_among_forms_of_one_size():
    record = decode_packet(packet(1108))
    assert names_of(record, "3.6")["joint_mode"][248] == "PART_D_CALIBRATION_ERROR"
    assert 248 not in names_of(record)["joint_mode"]                     # no version: the newest, 5.0 to 5.3
    assert form_of(1108, (5, 1, 0))[0] == 5_000_000
    assert form_of(812, None)[3]["robot_mode"][0] == "RUNNING"          # CB2 codes


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=3000), st.integers(min_value=1, max_value=64))
def test_no_bytes_make_it_raise_and_known_packets_round_trip(data, step):
    framer = RealtimeFramer("5.9")
    records = []
    for i in range(0, len(data), step):
        records += framer.feed(data[i:i + step])
    records += framer.close()
    rebuilt = b"".join(r.encode() for r in records if not isinstance(r, StreamError))
    assert data.startswith(rebuilt)
    for r in records:
        urwire.to_json_line(r)


# ---- the golden vectors (tests/golden/ur_realtime/), which every target runs ----

CASES = interface_cases("ur_realtime")


def test_the_vectors_cover_cb2_cb3_and_eseries():
    types = {r["type"] for case in CASES for r in case.expect}
    assert {"rt_1_8", "rt_3_2", "rt_5_10", "unknown", "error"} <= types


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_vector(case):
    records = decode_stream(case.data, case.version)
    got = [json.loads(urwire.to_json_line(r)) for r in records]
    assert mismatches(case.expect, got, partial=False, tolerance=0.0) == []
    # Lossless: every record but a stream fault gives back its bytes.
    rebuilt = b"".join(r.encode() for r in records if not isinstance(r, StreamError))
    assert case.data.startswith(rebuilt) and len(rebuilt) == sum(
        r["message_size"] for r in case.expect if r["type"] != "error")
