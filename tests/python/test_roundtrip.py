"""Lossless: encode(decode(b)) == b, for every well-framed input, unknown parts included."""
from __future__ import annotations

import random

import pytest
import urwire
from hypothesis import given, settings, strategies as st

from tests.tools import valid
from tests.vectors import all_cases

# The conformance sample of a fake server: project "UR", software 5.24, build 42.
MINIMAL_VERSION = bytes.fromhex("0000001c140000000000000000fe030255520518000000000000002a")

CASES = [c for c in all_cases() if not any(isinstance(r, urwire.StreamError)
                                           for r in urwire.decode_stream(c.data, c.version))]
VERSIONS = valid.versions()   # one version per form of every type code: every generation


def reencode(data: bytes, hint) -> bytes:
    framer = urwire.Framer(hint)
    out = b""
    for record in framer.feed(data) + framer.close():
        version = framer.version if getattr(record, "SETS_VERSION", None) is None else record_version(record)
        out += urwire.encode_message(record, version)
    return out


def record_version(record):
    return (getattr(record, record.SETS_VERSION[0]), getattr(record, record.SETS_VERSION[1]))


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_every_well_framed_vector_reencodes_exactly(case):
    hint = urwire.parse_version(case.version)
    assert reencode(case.data, hint) == case.data


@settings(max_examples=400, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), version=st.sampled_from(VERSIONS))
def test_random_valid_messages_roundtrip(seed, version):
    data = valid.message(random.Random(seed), version)
    (record,) = urwire.decode_stream(data, version)
    assert not urwire.canonical.has_error(record), urwire.to_json_line(record)
    assert getattr(record, "extra", b"") == b""
    assert urwire.encode_message(record, version) == data


@settings(max_examples=300, deadline=None)
@given(body=st.binary(min_size=0, max_size=300), mtype=st.sampled_from([16, 20, 25, 5, 22, 23, 24, 255]))
def test_any_framed_bytes_reencode_exactly(body, mtype):
    # Whatever is inside a well-framed message (garbage, short or long parts), nothing is lost.
    data = (len(body) + 5).to_bytes(4, "big") + bytes([mtype]) + body
    (record,) = urwire.decode_stream(data)
    assert urwire.encode_message(record) == data


def test_lengths_are_computed_by_encode():
    data = MINIMAL_VERSION
    (msg,) = urwire.decode_stream(data)
    msg.project_name = "URControl"
    out = msg.encode()
    assert int.from_bytes(out[:4], "big") == len(out) == len(data) + 7
    assert out[16:25] == b"URControl" and out[15] == 9  # the int8 name length is computed too


def test_float32_signalling_nan_keeps_its_bits():
    body = bytes.fromhex("00") + bytes(4) * 3 + bytes.fromhex("7f800001") + bytes(4) * 2  # rx_idle_chars sNaN
    pkg = (len(body) + 5).to_bytes(4, "big") + b"\x0b" + body
    data = (len(pkg) + 5).to_bytes(4, "big") + b"\x10" + pkg
    (state,) = urwire.decode_stream(data)
    assert urwire.to_dict(state)["packages"][0]["rx_idle_chars"] != urwire.to_dict(state)["packages"][0]["rx_idle_chars"]
    assert state.encode() == data


def test_the_largest_float32_prints_and_reencodes():
    body = b"\x00" + bytes(12) + bytes.fromhex("7f7fffff") + bytes.fromhex("ff7fffff")  # +-FLT_MAX
    pkg = (len(body) + 5).to_bytes(4, "big") + b"\x0b" + body
    data = (len(pkg) + 5).to_bytes(4, "big") + b"\x10" + pkg
    (state,) = urwire.decode_stream(data)
    line = urwire.to_json_line(state)
    assert '"rx_idle_chars": 3.4028235e+38' in line and '"tx_idle_chars": -3.4028235e+38' in line
    assert state.encode() == data


def test_a_matrix_only_encodes_as_it_reads_back():
    codec = urwire.generated.spec.value_codec((5, 9))
    out = bytearray()
    codec.encode(out, codec.make("MATRIX", []))
    assert bytes(out) == b"\x12\x00\x00\x00\x00"
    with pytest.raises(urwire.EncodeError, match="0 columns"):
        codec.encode(bytearray(), codec.make("MATRIX", [[], []]))
