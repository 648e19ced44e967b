"""The C backend's records of the one-run layouts against pure Python: real-time packets
(urwire._ccore.FlatRecords over the generated FLAT_LAYOUTS). Every real-time golden vector, fed
whole and byte by byte, gives the same records (==, repr, JSON line, bytes again); every real-time
layout made in C from random bytes (NaNs among them) is its decoder's record, a packet cut short
raises as the decoder does.

The extension is built by `make python-ext`; without it these tests fail."""
from __future__ import annotations

import contextlib
import random
import struct

import pytest

import urwire
from urwire import realtime
from urwire._runtime import StreamError
from urwire.generated.ur_realtime import FLAT_LAYOUTS

from tests.vectors import interface_cases
from tests.tools import ccore_sanitized


@pytest.fixture(scope="module")
def ccore():
    return ccore_sanitized.extension()


@contextlib.contextmanager
def made_by(packets):
    """Real-time packets made by `packets` (a FlatRecords); None: pure Python."""
    saved = realtime._C_PACKETS
    realtime._C_PACKETS = packets
    try:
        yield
    finally:
        realtime._C_PACKETS = saved


def described(records: list) -> list:
    """Each record, its repr (== cannot tell True from 1), its JSON line and its bytes again."""
    return [(r, repr(r), urwire.to_json_line(r), None if isinstance(r, StreamError) else r.encode())
            for r in records]


def same(got: list, expected: list, again: list, what: str) -> None:
    """got against expected; where pure Python's two reads differ (a NaN), all but ==."""
    assert len(got) == len(expected), what
    for k, (g, e, a) in enumerate(zip(got, expected, again)):
        assert type(g[0]) is type(e[0]), f"{what}: record {k}"
        assert (g if e == a else g[1:]) == (e if e == a else e[1:]), f"{what}: record {k}"


def realtime_records(data: bytes, hint, piece: int) -> list:
    framer = realtime.RealtimeFramer(hint)
    step = piece or max(len(data), 1)
    records = []
    for at in range(0, len(data), step):
        records += framer.feed(data[at:at + step])
    return records + framer.close()


@pytest.mark.parametrize("case", interface_cases("ur_realtime"), ids=lambda c: c.name)
def test_every_realtime_vector_gives_the_same_records(ccore, case):
    with made_by(None):
        expected = described(realtime_records(case.data, case.version, 0))
        again = described(realtime_records(case.data, case.version, 0))
    with made_by(ccore.FlatRecords(FLAT_LAYOUTS)):
        for piece in (0, 1, 7, 1000):
            same(described(realtime_records(case.data, case.version, piece)), expected, again,
                 f"{case.name} in pieces of {piece}")


@pytest.mark.parametrize("cls", list(FLAT_LAYOUTS), ids=lambda c: c.__name__)
def test_every_realtime_layout_made_in_c_is_its_decoders_record(ccore, cls):
    packets = ccore.FlatRecords(FLAT_LAYOUTS)
    st, _ = FLAT_LAYOUTS[cls]
    rng = random.Random(cls.__name__)
    nan = struct.pack(">d", float("nan"))
    for offset in (0, 3):
        for _ in range(10):
            body = bytearray(rng.getrandbits(8) for _ in range(offset + st.size))
            at = offset + 4 + 8 * rng.randrange((st.size - 4) // 8)
            body[at:at + 8] = nan
            for packet in (bytes(body), body):        # the framer hands its bytearray
                got = packets.decode(cls, packet, offset)
                expected = cls.decode(packet, offset)
                assert type(got) is cls
                if expected == cls.decode(packet, offset):
                    assert got == expected
                assert (repr(got), got.encode()) == (repr(expected), expected.encode())
        with pytest.raises(struct.error) as from_c:
            packets.decode(cls, bytes(st.size - 1), 0)
        with pytest.raises(struct.error) as from_python:
            cls.decode(bytes(st.size - 1), 0)
        assert str(from_c.value) == str(from_python.value)
    assert packets.decode(realtime.UnknownPacket, bytes(8), 0) is None     # no layout: the decoder's
