"""Differential test: random and mutated streams through the C CLI and the Python decoder.

The streams come from tests/tools/streams.py (real messages from every vector, shuffled,
then damaged: flipped bytes, cuts, garbage, nudged lengths, splices). Both decoders must print
the same records, error records and texts included, byte for byte, and exit with the same code.
"""
from __future__ import annotations

import struct
import subprocess

import pytest

from tests.c.harness_c import parse_lines, python_lines, python_records, run_cli
from tests.c.seeds import messages
from tests.tools.streams import cut_tails, streams
from tests.vectors import all_cases

MESSAGES = [m for case in all_cases() for m in messages(case.data)]


def test_there_are_messages_to_mix():
    assert len(MESSAGES) > 50


def compare(build, data: bytes, hint: str | None) -> None:
    args = ["--version-hint", hint] if hint else []
    result = run_cli(build, data, *args)
    assert result.returncode in (0, 1), result.stderr
    expected, code = python_records(data, hint)
    got = parse_lines(result.stdout)
    assert got == expected, f"stream {data.hex()}"
    assert result.returncode == code, f"stream {data.hex()}"
    assert result.stdout.decode("utf-8").splitlines() == python_lines(data, hint)[0], f"stream {data.hex()}"


@pytest.mark.parametrize("seed", range(4))
def test_random_streams_fast_build(fast, seed):
    for i, data in enumerate(streams(MESSAGES, 400, seed=seed)):
        compare(fast, data, (None, "3.2", "5.0", "5.9")[i % 4])


@pytest.mark.parametrize("seed", [101, 102])
def test_random_streams_under_sanitizers(asan, seed):
    for i, data in enumerate(streams(MESSAGES, 250, seed=seed)):
        compare(asan, data, (None, "5.0")[i % 2])


def test_streams_that_end_inside_a_message_rescan_their_tail_alike(asan):
    for i, data in enumerate(cut_tails(MESSAGES, 150, seed=11)):
        compare(asan, data, (None, "5.0")[i % 2])


def test_a_tail_of_nested_lengths_is_rescanned_alike(fast):
    """Every 5 bytes a plausible header whose length runs one byte past the end, then a message."""
    after = MESSAGES[0]
    headers = 200_000
    end = 5 * headers + len(after)
    data = b"".join(struct.pack(">iB", end + 1 - 5 * i, 20) for i in range(headers)) + after
    compare(fast, data, None)


@pytest.mark.parametrize("chunk", [1, 2, 3, 5, 64, 0])
def test_chunk_size_never_changes_the_records(asan, chunk, tmp_path):
    """The framer takes bytes in chunks of any size (0: varying sizes) with the same result."""
    for seed, data in enumerate(streams(MESSAGES, 40, seed=7)):
        path = tmp_path / f"s{seed}.bin"
        path.write_bytes(data)
        whole = run_cli(asan, data)
        chunked = subprocess.run([str(asan.driver), "chunks", str(chunk), str(path)], capture_output=True)
        assert chunked.stderr == b""
        assert chunked.stdout == whole.stdout
        assert chunked.returncode == whole.returncode
