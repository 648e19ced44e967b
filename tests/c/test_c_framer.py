"""The framer where the CLI cannot reach: a buffer smaller than a message (the message is
reported and skipped, framing goes on after it), at every chunk size."""
from __future__ import annotations

import json
import struct
import subprocess

import pytest


def text_message(text: bytes) -> bytes:
    body = struct.pack(">QbB", 1000, -2, 0) + text
    return struct.pack(">iB", 5 + len(body), 20) + body


@pytest.mark.parametrize("chunk", [1, 7, 64, 0])
def test_a_message_bigger_than_the_buffer_is_reported_and_skipped(asan, tmp_path, chunk):
    small, big, after = text_message(b"a"), text_message(b"x" * 300), text_message(b"after")
    path = tmp_path / "s.bin"
    path.write_bytes(small + big + after)
    result = subprocess.run([str(asan.driver), "chunks", str(chunk), str(path), "128"], capture_output=True)
    assert result.stderr == b""
    records = [json.loads(line) for line in result.stdout.decode().splitlines()]
    assert records == [
        {"type": "text", "timestamp": 1000, "source": -2, "text": "a"},
        {"type": "error", "offset": len(small),
         "error": f"message of length {len(big)} exceeds the framer's buffer of 128 bytes"},
        {"type": "text", "timestamp": 1000, "source": -2, "text": "after"},
    ]
    assert result.returncode == 1


def test_a_stream_ending_inside_a_skipped_message_just_ends(asan, tmp_path):
    big = text_message(b"x" * 300)
    path = tmp_path / "s.bin"
    path.write_bytes(big[:200])
    result = subprocess.run([str(asan.driver), "chunks", "16", str(path), "128"], capture_output=True)
    records = [json.loads(line) for line in result.stdout.decode().splitlines()]
    assert [r["type"] for r in records] == ["error"]
    assert "exceeds the framer's buffer" in records[0]["error"]
