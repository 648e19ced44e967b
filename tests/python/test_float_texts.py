"""The float32 texts of canonical JSON: the fast digit count against the search by definition,
and their layout against repr().

f32_text counts the digits a float32 needs with double arithmetic and a margin
(canonical._f32_digits); canonical._f32_upwards tries %.1g, %.2g, ... and reads each back,
which is the definition itself. The text lays those digits out as repr() lays out a double, and
repr() of the double the %g text reads as is that layout: the double has no shorter text (that
text would read back as the same float32 too), so repr() prints the same digits. The C command's
texts are checked against f32_text in tests/c/test_c_json.py (millions of values in `make test-deep`).
"""
from __future__ import annotations

import math
import random
import struct

import pytest
from urwire import canonical

F32 = struct.Struct(">f")
BITS = struct.Struct(">I")


def from_bits(bits: int) -> float:
    return F32.unpack(BITS.pack(bits & 0xFFFFFFFF))[0]


def bits_of(x: float) -> int:
    return BITS.unpack(F32.pack(x))[0]


def neighbours(x: float, reach: int) -> list[float]:
    b = bits_of(x)
    return [from_bits(b + k) for k in range(-reach, reach + 1)]


def finite_nonzero(values) -> list[float]:
    return [x for x in values if x - x == 0.0 and x != 0.0]


def assert_definition(values) -> None:
    values = finite_nonzero(values)
    wrong = [(x.hex(), canonical._f32_digits(x), canonical._f32_upwards(x))
             for x in values if canonical._f32_digits(x) != canonical._f32_upwards(x)]
    assert not wrong, wrong[:10]
    laid_out = [(x.hex(), canonical._f32_shortest(x)) for x in values
                if canonical._f32_shortest(x) != repr(float(canonical._f32_upwards(x)))]
    assert not laid_out, laid_out[:10]


@pytest.mark.parametrize("value, text", [
    (30.0, "30.0"), (31.0, "31.0"), (-30.0, "-30.0"), (100.0, "100.0"), (2.5, "2.5"), (0.1, "0.1"),
    (1e-4, "0.0001"), (1e-5, "1e-05"), (1.5e-5, "1.5e-05"), (1.5e20, "1.5e+20"), (1e15, "1000000000000000.0"),
    (9.999999e15, "9999999000000000.0"), (1e16, "1e+16"), (123456789.0, "123456790.0"), (0.0, "0.0"),
    (-0.0, "-0.0"), (1e-45, "1e-45"), (-1e-45, "-1e-45"), (5.877472e-39, "5.877472e-39"),
    (1.1754942e-38, "1.1754942e-38"), (3.4028233e38, "3.4028233e+38"),
    (math.inf, "Infinity"), (-math.inf, "-Infinity"), (math.nan, "NaN")])
def test_the_notation_is_that_of_float64(value, text):
    """The digits are float32's own, the notation repr()'s: a decimal point from 1e-4 up to 1e16,
    an exponent outside (where %g would have written 3e+01 for 30)."""
    x = F32.unpack(F32.pack(value))[0]
    assert canonical.f32_text(x) == canonical._f32_shortest(x) == text
    assert canonical.f32_text(x) == text  # from the kept texts too


def test_no_float32_lies_between_a_power_of_ten_and_its_double():
    """The digit count compares x with the double nearest each power of ten; that is exact only if
    such a double is never itself a float32 unless the power is (10**0 to 10**10)."""
    for decade in range(-45, 39):
        nearest = float(f"1e{decade}")
        try:
            as_f32 = F32.unpack(F32.pack(nearest))[0]
        except OverflowError:
            continue
        assert (as_f32 == nearest) == (0 <= decade <= 10), decade


@pytest.mark.parametrize("decade", range(-38, 39))
def test_values_around_every_power_of_ten(decade):
    try:
        assert_definition(neighbours(F32.unpack(F32.pack(float(f"1e{decade}")))[0], 4))
    except OverflowError:
        pytest.skip("past FLT_MAX")


def test_values_around_every_power_of_two():
    """Powers of two have a narrower interval below them than above."""
    assert_definition(v for e in range(-149, 128) for v in neighbours(math.ldexp(1.0, e), 3))


def test_subnormals_and_the_largest_values():
    assert_definition([from_bits(b) for b in range(1, 2000)] + neighbours(from_bits(0x7F7FFFFF), 2)[:3])


def test_integers_and_short_decimals():
    """Values typed in as short decimals need few digits: the count goes down from 7."""
    values = [float(i) for i in range(1, 20001)] + [i / 1000 for i in range(1, 20001)]
    assert_definition(F32.unpack(F32.pack(v))[0] for v in values)


@pytest.mark.parametrize("count", [50_000, pytest.param(200_000, marks=pytest.mark.deep)])
def test_random_float32_bit_patterns(count):
    rng = random.Random(20261123)
    assert_definition(from_bits(rng.getrandbits(32)) for _ in range(count))


def test_the_ranges_a_robot_sends():
    """Currents, voltages, temperatures and positions: 7, 8 and 9 digits all occur here."""
    rng = random.Random(5)
    values = [F32.unpack(F32.pack(rng.uniform(lo, hi)))[0]
              for lo, hi in ((-5, 5), (0, 60), (20, 80), (-6.3, 6.3), (-1e-3, 1e-3)) for _ in range(20_000)]
    assert_definition(values)
    assert {len(canonical._f32_digits(x).lstrip("-0.").replace(".", "")) for x in values[:20_000]} >= {7, 8, 9}
