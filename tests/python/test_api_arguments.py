"""The public functions on arguments of every kind: no bytes make them raise, however few;
anything that is not bytes-like or a software version is a TypeError that says what is wanted."""
from __future__ import annotations

import array

import pytest
import urwire
from hypothesis import given, settings, strategies as st

from tests.vectors import all_cases

# A text robot message, "hi" (hand-made: length 17, type 20, timestamp 1, source -2, subtype 0).
TEXT = bytes.fromhex("00000011 14 0000000000000001 fe 00 6869")
VERSIONS = [None, (3, 2, 0), (5, 0, 0), (5, 9, 0), (5, 25, 1), (10, 7, 0)]


def records(data) -> list[str]:
    return [urwire.to_json_line(r) for r in urwire.decode_stream(data)]


@pytest.mark.parametrize("data", [b"", b"\x00", b"\x00\x00\x00", b"\x00\x00\x00\x11"])
def test_a_message_shorter_than_its_header_is_an_unknown_message_with_an_error(data):
    record = urwire.decode_message(data)
    assert isinstance(record, urwire.UnknownMessage) and record.raw == data
    assert record.error == f"length at offset 0: needs 5 bytes, {len(data)} left"
    assert urwire.to_dict(record) == {"type": "unknown", "message_type": 0, "error": record.error,
                                      "raw": data.hex()}


@pytest.mark.parametrize("data", [b"", b"\x00", b"\x00\x00\x00\x11"])
def test_short_streams_and_chunks_never_raise(data):
    framer = urwire.Framer()
    assert framer.feed(data) == []
    assert len(framer.close()) == (1 if data else 0)
    assert len(records(data)) == (1 if data else 0)


@settings(max_examples=400, deadline=None)
@given(data=st.binary(max_size=300), version=st.sampled_from(VERSIONS), known=st.sampled_from([None, True, False]))
def test_decode_message_never_raises_on_any_bytes(data, version, known):
    urwire.to_json_line(urwire.decode_message(data, version, known))


@settings(max_examples=200, deadline=None)
@given(head=st.binary(max_size=60), message=st.sampled_from([c.data for c in all_cases()][:40]),
       cut=st.integers(0, 2000))
def test_decode_message_never_raises_on_a_message_cut_anywhere(head, message, cut):
    urwire.to_json_line(urwire.decode_message((head + message)[:cut]))


@settings(max_examples=300, deadline=None)
@given(chunks=st.lists(st.binary(max_size=40), max_size=12), hint=st.sampled_from([None, "3.2", "5.0", "5.9"]))
def test_framer_feed_and_close_never_raise_on_any_chunks(chunks, hint):
    framer = urwire.Framer(hint)
    out = [r for chunk in chunks for r in framer.feed(chunk)] + framer.close()
    for r in out:
        urwire.to_json_line(r)


@pytest.mark.parametrize("kind", [bytes, bytearray, memoryview, lambda b: memoryview(bytearray(b))])
def test_decode_message_takes_any_bytes_like_object(kind):
    assert urwire.to_json_line(urwire.decode_message(kind(TEXT))) == urwire.to_json_line(urwire.decode_message(TEXT))


def test_decode_stream_reads_any_buffer_as_its_bytes():
    expected = records(TEXT * 4)
    words = array.array("H")
    words.frombytes(TEXT * 4)   # 68 bytes: 34 two-byte items
    assert records(words) == expected
    assert records(memoryview(words)) == expected
    assert records(memoryview(TEXT * 8)[::2]) == records((TEXT * 8)[::2])   # not contiguous
    assert records([bytearray(TEXT), memoryview(TEXT), words]) == records(TEXT * 6)


@pytest.mark.parametrize("data", [None, "00000011", 5, 10**9, 5.9, [10**9], ["abc"], [None]])
def test_decode_stream_rejects_what_is_not_bytes(data):
    with pytest.raises(TypeError, match=r"^(a chunk of )?decode_stream: expected a bytes-like object"):
        list(urwire.decode_stream(data))


@pytest.mark.parametrize("data", [None, "00000011140000", 17, [0, 0, 0, 17, 20]])
def test_decode_message_and_feed_reject_what_is_not_bytes(data):
    with pytest.raises(TypeError, match=r"^decode_message: expected a bytes-like object \(bytes, bytearray, memoryview"):
        urwire.decode_message(data)
    with pytest.raises(TypeError, match=r"^Framer.feed: expected a bytes-like object"):
        urwire.Framer().feed(data)


@pytest.mark.parametrize("version", [5.9, 5, b"5.9", object()])
def test_a_version_of_the_wrong_type_names_the_types_it_may_be(version):
    expected = r"a software version is a str such as '5\.9' or '5\.25\.1' or a tuple such as \(5, 25, 1\)"
    with pytest.raises(TypeError, match=expected):
        urwire.Framer(version)
    with pytest.raises(TypeError, match=expected):
        urwire.decode_stream(TEXT, version)
    with pytest.raises(TypeError, match=expected):
        urwire.decode_message(TEXT, version)


@pytest.mark.parametrize("version", [(5,), (5, 9, 0, 1), (5, -1), (5, "9"), (5, 9.0), (True, 9), "5", "5.x"])
def test_a_version_that_is_no_software_version_is_a_value_error(version):
    with pytest.raises(ValueError, match="not a software version"):
        urwire.parse_version(version)


def test_versions_as_str_or_tuple_mean_the_same():
    assert urwire.parse_version("5.9") == urwire.parse_version((5, 9)) == urwire.parse_version([5, 9, 0]) == (5, 9, 0)
    assert urwire.decode_message(TEXT, "5.25.1") == urwire.decode_message(TEXT, (5, 25, 1))
