"""tests/c/unit.c: hand-built messages encoded with computed lengths, encode-side errors and
their texts, enum and value-type names, version parsing; under gcc, clang and the sanitizers."""
from __future__ import annotations

import subprocess

import pytest

from tests.c.harness_c import GEN, OUT, ROOT, SANITIZE, compile_c


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_unit_checks(cc):
    exe = OUT / f"unit-{cc}"
    compile_c(cc, ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "unit.c", GEN / "urwire.c"], exe)
    result = subprocess.run([str(exe)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip() == "all unit checks passed"
