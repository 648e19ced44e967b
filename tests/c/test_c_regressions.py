"""Every input in tests/c/regressions/ (fuzzer finds, plus the README libFuzzer also reads),
replayed through the framer and decoders under the sanitizers: no crash, and Python agrees."""
from __future__ import annotations

from pathlib import Path

import pytest

from tests.c.harness_c import parse_lines, python_records, run_cli

FOLDER = Path(__file__).resolve().parent / "regressions"
INPUTS = sorted(p for p in FOLDER.iterdir() if p.is_file())


@pytest.mark.parametrize("path", INPUTS, ids=[p.name for p in INPUTS])
def test_regression_input(asan, path):
    data = path.read_bytes()[1:]  # the fuzzer's first byte is its control byte
    result = run_cli(asan, data)
    assert result.returncode in (0, 1), result.stderr
    expected, code = python_records(data, None)
    assert parse_lines(result.stdout) == expected
    assert result.returncode == code
