"""The CLI's hand-written JSON pieces against Python: UTF-8 replacement (maximal subparts, as
bytes.decode("utf-8", "replace")), JSON string escapes, and the float texts."""
from __future__ import annotations

import json
import math
import random
import struct
import subprocess

import pytest

from tests.c.harness_c import CommandPeer
from urwire.canonical import f32_text


def c_text(build, data: bytes) -> str:
    result = subprocess.run([str(build.driver), "text"], input=data, capture_output=True)
    assert result.returncode == 0, result.stderr
    line = result.stdout.decode("utf-8")  # the output itself is always valid UTF-8
    assert line.endswith("\n")
    return line[:-1]


def c_texts(build, inputs: list[bytes]) -> list[str]:
    """c_text of each input, from one driver process (`driver batch text`)."""
    with CommandPeer(build.driver, "text") as peer:
        return [peer.decode(data)[0][0] for data in inputs]


EDGES = [b"", b"plain", b"\x00\x01\x1f\x7f\"\\/\n\r\t\b\f", "héllo wörld ✓ 𝄞".encode(),
         b"\x80", b"\xbf\x80", b"\xc0\xaf", b"\xc1\xbf", b"\xc2", b"\xc2\x41", b"\xe0\x80\xaf", b"\xe0\xa0",
         b"\xe0\xa0\x41", b"\xed\xa0\x80", b"\xed\x9f\xbf", b"\xef\xbf\xbf", b"\xf0\x8f\xbf\xbf",
         b"\xf0\x90\x80", b"\xf0\x90\x80\x80", b"\xf4\x8f\xbf\xbf", b"\xf4\x90\x80\x80", b"\xf5\x80",
         b"\xff\xfe", b"a\xe2\x82", b"\xe2\x82\xac\xe2\x82"]


@pytest.mark.parametrize("data", EDGES, ids=[d.hex() or "empty" for d in EDGES])
def test_edge_cases_decode_like_python(asan, data):
    text = c_text(asan, data)
    assert json.loads(text) == data.decode("utf-8", "replace")
    # Escapes as Python's json module writes them (ensure_ascii=False).
    assert text == json.dumps(data.decode("utf-8", "replace"), ensure_ascii=False)


def test_random_bytes_decode_like_python(asan):
    rng = random.Random(5)
    alphabet = [bytes([b]) for b in range(256)] + ["é", "€", "𝄞", "\u2028"]
    inputs = []
    for _ in range(300):
        parts = [rng.choice(alphabet) for _ in range(rng.randint(0, 40))]
        data = b"".join(p if isinstance(p, bytes) else p.encode() for p in parts)
        if rng.random() < 0.3:  # cut inside a sequence now and then
            data = data[:rng.randint(0, len(data))]
        inputs.append(data)
    for data, text in zip(inputs, c_texts(asan, inputs), strict=True):
        assert text == json.dumps(data.decode("utf-8", "replace"), ensure_ascii=False), data.hex()


def float_bits(rng: random.Random, size: int, count: int) -> list[bytes]:
    special = [0.0, -0.0, 1.0, -1.0, 0.1, 1e-45, 3.4028234663852886e38, 1e-38, 16777217.0, math.inf, -math.inf,
               math.nan, 123456.789, 2.5e-8, 1e-4, 1e-5, 1e15, 1e16, 123456789012345678.0, 5e-324,
               1.7976931348623157e308, 0.30000000000000004, 100.0, 1.5e-7, 30.0, 31.0, -30.0, 1.5e20,
               9.999999e15, 1e-4 * 0.999, 1e16 * 1.001,
               -6.243497100631985e+144, 7.291122019556398e-304]  # the last two: lopsided intervals
    fmt = ">f" if size == 4 else ">d"
    out = [struct.pack(fmt, x) for x in special if size == 8 or not abs(x) < math.inf or abs(x) < 3.4e38]
    out += [rng.getrandbits(size * 8).to_bytes(size, "big") for _ in range(count)]
    if size == 8:  # powers of two, where the rounding interval is lopsided
        out += [struct.pack(fmt, rng.choice((1, -1)) * 2.0 ** rng.randint(-1074, 1023)) for _ in range(count)]
    out += [struct.pack(fmt, rng.uniform(-1000, 1000)) for _ in range(count)]
    return out


def test_float32_texts_are_pythons(asan):
    items = float_bits(random.Random(1), 4, 3000)
    result = subprocess.run([str(asan.driver), "f32"], input=b"".join(items), capture_output=True)
    assert result.returncode == 0
    for raw, text in zip(items, result.stdout.decode().splitlines(), strict=True):
        (x,) = struct.unpack(">f", raw)
        if abs(x) > 3.4028234e38 and not math.isinf(x):
            continue  # Python's f32_text raises OverflowError here: see the test below
        assert text == f32_text(x), raw.hex()


def test_float32_max_prints_its_shortest_text(asan):
    """The shortest %g of FLT_MAX is 3.4028235e+38 (p = 8): strtof reads it back as FLT_MAX.
    Python's f32_text packs float("3.4028235e+38") with struct, which refuses any double above
    FLT_MAX before rounding, so the Python decoder raises OverflowError on such a float32
    (reported; the C decoder follows the documented rule)."""
    items = [bytes.fromhex("7f7fffff"), bytes.fromhex("ff7fffff"), bytes.fromhex("7f7ffffe")]
    result = subprocess.run([str(asan.driver), "f32"], input=b"".join(items), capture_output=True)
    assert result.stdout.decode().splitlines() == ["3.4028235e+38", "-3.4028235e+38", "3.4028233e+38"]


def test_float64_texts_are_pythons_repr(asan):
    items = float_bits(random.Random(2), 8, 3000)
    result = subprocess.run([str(asan.driver), "f64"], input=b"".join(items), capture_output=True)
    assert result.returncode == 0
    for raw, text in zip(items, result.stdout.decode().splitlines(), strict=True):
        (x,) = struct.unpack(">d", raw)
        if math.isnan(x):
            assert text == "NaN"
            continue
        if math.isinf(x):
            assert text == ("Infinity" if x > 0 else "-Infinity")
            continue
        assert struct.pack(">d", float(text)) == raw, (raw.hex(), text)
        assert text == repr(x), raw.hex()  # shortest digits, laid out as repr() does
