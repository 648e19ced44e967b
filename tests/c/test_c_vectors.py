"""Every golden and conformance vector through urwire-decode's record loop (gcc, clang,
sanitizers): the expected records, and what the Python decoder prints (values, then the exact
text), exit code included. Each build's test driver answers for the command, vector after vector,
in one process (`driver batch`: the command's own records.c, nothing on stderr); the command
itself prints the same for every vector too, in one run over all of them.
"""
from __future__ import annotations

import pytest

from tests.c.harness_c import CommandPeer, parse_lines, python_lines, python_records, run_cli
from tests.vectors import all_cases, mismatches

CASES = all_cases()


def test_there_are_vectors():
    assert len(CASES) > 50
    assert any(c.partial for c in CASES) and any(not c.partial for c in CASES)


@pytest.fixture(scope="module")
def answers(build) -> dict[str, tuple[list[str], int]]:
    """Each vector's lines and exit status from one driver process of the build."""
    with CommandPeer(build.driver) as peer:
        return {case.name: peer.decode(case.data, case.version or "") for case in CASES}


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_vector(answers, case):
    lines, code = answers[case.name]
    assert code in (0, 1)
    records = parse_lines("\n".join(lines).encode())
    assert mismatches(case.expect, records, partial=case.partial, tolerance=case.tolerance) == []
    expected, expected_code = python_records(case.data, case.version)
    assert records == expected
    assert code == expected_code
    # Not only the same values: the same text, byte for byte, as the Python CLI prints.
    assert lines == python_lines(case.data, case.version)[0]


@pytest.mark.parametrize("hint", sorted({c.version for c in CASES if c.version}) + [None])
def test_the_command_prints_what_the_driver_answers(build, hint):
    """The command itself on the vectors of one hint joined into one stream: the lines and exit
    status the driver gives for that stream, and nothing on stderr."""
    cases = [c for c in CASES if c.version == hint]
    data = b"".join(c.data for c in cases)
    result = run_cli(build, data, *(["--version-hint", hint] if hint else []))
    assert result.stderr == b""
    with CommandPeer(build.driver) as peer:
        lines, code = peer.decode(data, hint or "")
    assert result.stdout.decode("utf-8").split("\n")[:-1] == lines
    assert result.returncode == code
