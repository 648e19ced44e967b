"""The C backend's records of the one-run layouts against pure Python: real-time packets
(urwire._ccore.FlatRecords over the generated FLAT_LAYOUTS) and the extension's RTDE values by
name (urwire._ccore.values_by_name, which decoding no longer calls: a recipe's reader in Python,
typed_records.values_reader, is faster). Every real-time golden vector, fed whole and byte by
byte, gives the same records (==, repr, JSON line, bytes again); every real-time layout made in C
from random bytes (NaNs among them) is its decoder's record, a packet cut short raises as the
decoder does; random recipes' values, bools of any byte among them, are the Python loop's.

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


def python_values(flat: tuple, plan: tuple) -> dict:
    """typed_records.Recipe.decode's loop, over a plan of (name, first, count, is a bool)."""
    from urwire._runtime import BOOL

    values = {}
    for name, first, count, is_bool in plan:
        if count == 1:
            values[name] = BOOL[flat[first]] if is_bool else flat[first]
        else:
            values[name] = list(flat[first:first + count])
    return values


def test_values_by_name_are_the_python_loops(ccore):
    """Random plans over random values: the same dict, in the same order, with the same types;
    a bool's byte 0 and 1 as False and True, 2 to 255 as the number; a bool that is not a byte
    (a signed code's -1) gives None, for the Python loop to answer."""
    rng = random.Random(25)
    for _ in range(300):
        plan, flat = [], []
        for k in range(rng.randrange(1, 12)):
            count = rng.choice((1, 1, 3, 6))
            is_bool = count == 1 and rng.random() < 0.3
            plan.append((f"v{k}", len(flat), count, is_bool))
            if is_bool:
                flat.append(rng.choice((0, 1, 2, 255, True, False)))
            else:
                flat += [rng.choice((rng.random(), rng.getrandbits(31), -rng.getrandbits(63)))
                         for _ in range(count)]
        plan, flat = tuple(plan), tuple(flat)
        got = ccore.values_by_name(flat, plan)
        expected = python_values(flat, plan)
        assert list(got.items()) == list(expected.items())
        assert [type(v) for v in got.values()] == [type(v) for v in expected.values()]
    assert ccore.values_by_name((-1,), (("flag", 0, 1, True),)) is None
    with pytest.raises(TypeError):
        ccore.values_by_name([1], (("x", 0, 1, False),))
