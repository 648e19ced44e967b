"""The C runtime's JSON writer (runtime/c/json/json.c, shortest.c): its unit checks in C
(tests/c/json_unit.c: hard float cases, string escapes, the record buffer) under gcc, clang and the sanitizers,
then the float texts against Python: random bit patterns and every exponent's edges through the
test driver in one run each, compared with repr() for float64 and canonical.f32_text for float32
(a few hundred thousand in `make test`, millions in `make test-deep`)."""
from __future__ import annotations

import math
import random
import struct
import subprocess
import sys

import pytest

from tests.c.harness_c import JSON, JSON_RUNTIME, OUT, ROOT, SANITIZE, compile_c

from urwire.canonical import f32_text

UNIT_BUILDS = {
    "gcc": ("gcc", []),
    "clang": ("clang", []),
    "gcc-portable": ("gcc", ["-DSHORTEST_PORTABLE"]),  # the 64-bit multiply without __int128
}


def test_pow5_table_is_what_its_script_writes():
    result = subprocess.run([sys.executable, str(JSON_RUNTIME / "pow5_table.py"), "--check"], capture_output=True,
                            text=True)
    assert result.returncode == 0, result.stdout + result.stderr


@pytest.mark.parametrize("name", list(UNIT_BUILDS))
def test_json_unit_checks(name):
    cc, flags = UNIT_BUILDS[name]
    exe = OUT / f"json-unit-{name}"
    compile_c(cc, ["-O1", "-g", *SANITIZE, *flags], [ROOT / "tests" / "c" / "json_unit.c", *JSON], exe, ["-lm"])
    result = subprocess.run([str(exe)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip() == "all json checks passed"


def test_near_midpoint_finder_builds(tmp_path):
    """tests/c/near_midpoints.c wrote float32_near_midpoints.txt (running it takes a minute)."""
    compile_c("gcc", ["-O2"], [ROOT / "tests" / "c" / "near_midpoints.c"], tmp_path / "near_midpoints", ["-lm"])


def c_texts(build, kind: str, raw: bytes) -> list[str]:
    result = subprocess.run([str(build.driver), kind], input=raw, capture_output=True)
    assert result.returncode == 0, result.stderr
    return result.stdout.decode().splitlines()


def nonfinite(x: float) -> str:
    return "NaN" if math.isnan(x) else ("Infinity" if x > 0 else "-Infinity")


# The random patterns: a sample beside the edges below in `make test`, ten times as many in test-deep.
RANDOM_COUNTS = [pytest.param(200_000, id="sample"), pytest.param(2_000_000, id="millions", marks=pytest.mark.deep)]


@pytest.mark.parametrize("count", RANDOM_COUNTS)
def test_float64_texts_are_pythons_repr(fast, count):
    rng = random.Random(64)
    raw = rng.randbytes(8 * count)
    # Powers of two (lopsided intervals) and their neighbours, every exponent, both signs.
    specials = []
    for exponent in range(2047):
        for mantissa in (0, 1, (1 << 52) - 1):
            specials += [(exponent << 52) | mantissa, (1 << 63) | (exponent << 52) | mantissa]
    raw += b"".join(b.to_bytes(8, "big") for b in specials)
    texts = c_texts(fast, "f64", raw)
    values = struct.unpack(f">{len(raw) // 8}d", raw)
    assert len(texts) == len(values)
    wrong = [(struct.pack(">d", x).hex(), t) for x, t in zip(values, texts)
             if t != (repr(x) if math.isfinite(x) else nonfinite(x))]
    assert wrong == [], f"{len(wrong)} differ, e.g. {wrong[:5]}"


def float32_near_midpoints() -> list[int]:
    lines = (ROOT / "tests" / "c" / "float32_near_midpoints.txt").read_text().splitlines()
    return [int(word, 16) for line in lines if not line.startswith("#") for word in line.split()]


@pytest.mark.parametrize("count", RANDOM_COUNTS)
def test_float32_texts_are_pythons(fast, count):
    rng = random.Random(32)
    count //= 2     # 4 bytes each: half as many patterns (test-deep's 1,000,000 as before)
    raw = rng.randbytes(4 * count)
    near = float32_near_midpoints()
    assert 0x15AE43FD in near and len(near) > 300
    specials = near + [e << 23 | m for e in range(256) for m in (0, 1, (1 << 23) - 1)]
    specials += [0x8000_0000 | b for b in specials]
    raw += b"".join(b.to_bytes(4, "big") for b in specials)
    # Robot-state ranges: currents, voltages, temperatures.
    raw += b"".join(struct.pack(">f", rng.uniform(-100, 100)) for _ in range(count // 10))
    texts = c_texts(fast, "f32", raw)
    values = struct.unpack(f">{len(raw) // 4}f", raw)
    assert len(texts) == len(values)
    wrong = [(struct.pack(">f", x).hex(), t) for x, t in zip(values, texts) if t != f32_text(x)]
    assert wrong == [], f"{len(wrong)} differ, e.g. {wrong[:5]}"
