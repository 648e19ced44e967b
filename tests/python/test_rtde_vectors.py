"""The RTDE golden vectors through the Python Conversation: every record as expected, and every
message encodes back to its bytes."""
from __future__ import annotations

import pytest

import urwire
from tests.rtde_vectors import mismatches, python_records, rtde_cases, shown_as
from urwire.rtde import Conversation
from urwire._runtime import StreamError

CASES = rtde_cases()


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_python_decodes_vector(case):
    records = python_records(case)
    got = [shown_as(urwire.to_json_line(r)) for r in records]
    problems = mismatches(case.expect, got, partial=False, tolerance=0.0)
    assert not problems, "\n".join(problems)
    for index, line in case.exact.items():
        assert urwire.to_json_line(records[index]) == line


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_encode_gives_the_bytes_back(case):
    """Lossless: the records of each fed piece encode to exactly its bytes, data packages by their
    recipe and raw records (unknown recipe, undocumented code) as they came."""
    conversation = Conversation(protocol=case.protocol)
    for from_robot, data in case.messages:
        records = conversation.feed(data, from_robot)
        if any(isinstance(r, StreamError) for r in records) or conversation._framers[from_robot].buf:
            continue                       # a fault or a cut-off tail: not a whole message
        assert b"".join(r.encode() for r in records) == data
