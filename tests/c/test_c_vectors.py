"""Every golden and conformance vector through build/urwire-decode (gcc, clang, sanitizers):
the expected records, and what the Python decoder prints (values, then the exact text), exit
code included."""
from __future__ import annotations

import pytest

from tests.c.harness_c import parse_lines, python_lines, python_records, run_cli
from tests.vectors import all_cases, mismatches

CASES = all_cases()


def test_there_are_vectors():
    assert len(CASES) > 50
    assert any(c.partial for c in CASES) and any(not c.partial for c in CASES)


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_vector(build, case):
    args = ["--version-hint", case.version] if case.version else []
    result = run_cli(build, case.data, *args)
    assert result.returncode in (0, 1), result.stderr
    assert result.stderr == b""
    records = parse_lines(result.stdout)
    assert mismatches(case.expect, records, partial=case.partial, tolerance=case.tolerance) == []
    expected, code = python_records(case.data, case.version)
    assert records == expected
    assert result.returncode == code
    # Not only the same values: the same text, byte for byte, as the Python CLI prints.
    assert result.stdout.decode("utf-8").splitlines() == python_lines(case.data, case.version)[0]
