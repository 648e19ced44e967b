"""Every input in tests/c/regressions/ (fuzzer finds, plus the README libFuzzer also reads),
replayed through the framer and decoders under the sanitizers: no crash, and Python agrees
(one driver process for all of them)."""
from __future__ import annotations

from pathlib import Path

import pytest

from tests.c.harness_c import CommandPeer, python_lines

FOLDER = Path(__file__).resolve().parent / "regressions"
INPUTS = sorted(p for p in FOLDER.iterdir() if p.is_file())


@pytest.fixture(scope="module")
def answers(asan) -> dict[str, tuple[list[str], int]]:
    with CommandPeer(asan.driver) as peer:
        # the fuzzer's first byte is its control byte
        return {path.name: peer.decode(path.read_bytes()[1:]) for path in INPUTS}


@pytest.mark.parametrize("path", INPUTS, ids=[p.name for p in INPUTS])
def test_regression_input(answers, path):
    lines, code = answers[path.name]
    assert code in (0, 1)
    assert (lines, code) == python_lines(path.read_bytes()[1:], None)
