"""RTDE stream framing on its own (runtime/c/typed_messages/rtde_stream.c, beside the RTDE parser it frames for):
tests/c/rtde_stream_unit.c under gcc and clang with ASan and UBSan, each stream framed whole, a
byte at a time and cut at every point: whole messages, garbage prefixes (one fault however cut),
the largest message, streams longer than the buffer, tails."""
from __future__ import annotations

import subprocess

import pytest

from tests.c.harness_c import GEN, HELD, OUT, ROOT, RTDE_STREAM, SANITIZE, compile_c


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_rtde_stream_unit_checks(cc):
    exe = OUT / f"rtde-stream-unit-{cc}"
    compile_c(cc, ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_stream_unit.c", RTDE_STREAM, HELD, GEN / "rtde.c"],
              exe)
    result = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert result.stdout.strip() == "all rtde stream checks passed"
