"""Differential test: random and mutated streams through the C command's record loop and the
Python decoder.

The streams come from tests/tools/streams.py (real messages from every vector, shuffled,
then damaged: flipped bytes, cuts, garbage, nudged lengths, splices). Both decoders must print
the same records, error records and texts included, byte for byte, and exit with the same code.
Each build's test driver answers for urwire-decode stream after stream in one process (`driver
batch`, the command's own records.c); tests/c/test_c_cli.py runs the command itself.
"""
from __future__ import annotations

import struct

import pytest

from tests.c.harness_c import CommandPeer, parse_lines, python_lines
from tests.c.seeds import messages
from tests.tools.streams import cut_tails, streams
from tests.vectors import all_cases

MESSAGES = [m for case in all_cases() for m in messages(case.data)]


def test_there_are_messages_to_mix():
    assert len(MESSAGES) > 50


def compare(peer: CommandPeer, data: bytes, hint: str | None) -> None:
    got, code = peer.decode(data, hint or "")
    assert code in (0, 1), f"stream {data.hex()}"
    expected, expected_code = python_lines(data, hint)
    assert parse_lines("\n".join(got).encode()) == parse_lines("\n".join(expected).encode()), f"stream {data.hex()}"
    assert code == expected_code, f"stream {data.hex()}"
    assert got == expected, f"stream {data.hex()}"


@pytest.mark.parametrize("seed", range(4))
def test_random_streams_fast_build(fast, seed):
    with CommandPeer(fast.driver) as peer:
        for i, data in enumerate(streams(MESSAGES, 400, seed=seed)):
            compare(peer, data, (None, "3.2", "5.0", "5.9")[i % 4])


@pytest.mark.parametrize("seed", [101, 102])
def test_random_streams_under_sanitizers(asan, seed):
    with CommandPeer(asan.driver) as peer:
        for i, data in enumerate(streams(MESSAGES, 250, seed=seed)):
            compare(peer, data, (None, "5.0")[i % 2])


def test_streams_that_end_inside_a_message_rescan_their_tail_alike(asan):
    with CommandPeer(asan.driver) as peer:
        for i, data in enumerate(cut_tails(MESSAGES, 150, seed=11)):
            compare(peer, data, (None, "5.0")[i % 2])


def test_a_tail_of_nested_lengths_is_rescanned_alike(fast):
    """Every 5 bytes a plausible header whose length runs one byte past the end, then a message."""
    after = MESSAGES[0]
    headers = 200_000
    end = 5 * headers + len(after)
    data = b"".join(struct.pack(">iB", end + 1 - 5 * i, 20) for i in range(headers)) + after
    with CommandPeer(fast.driver) as peer:
        compare(peer, data, None)


@pytest.mark.parametrize("chunk", [1, 2, 3, 5, 64, 0])
def test_chunk_size_never_changes_the_records(asan, chunk):
    """The framer takes bytes in chunks of any size (0: varying sizes) with the same result."""
    with CommandPeer(asan.driver) as whole, CommandPeer(asan.driver, "chunks", str(chunk)) as chunked:
        for data in streams(MESSAGES, 40, seed=7):
            assert chunked.decode(data) == whole.decode(data), f"stream {data.hex()}"
