"""Encoders: encode(decode(m)) == m for every framed message and sub-package, lengths computed,
and an output buffer one byte short fails cleanly (under the sanitizers)."""
from __future__ import annotations

import subprocess

from tests.c.seeds import messages
from tests.tools.streams import streams
from tests.vectors import all_cases

MESSAGES = [m for case in all_cases() for m in messages(case.data)]


def roundtrip(build, data: bytes, path) -> str:
    path.write_bytes(data)
    result = subprocess.run([str(build.driver), "roundtrip", str(path)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout


def test_every_vector_message_encodes_back_to_its_bytes(asan, tmp_path):
    out = roundtrip(asan, b"".join(MESSAGES), tmp_path / "all.bin")
    count = int(out.split()[1])
    assert count == len(MESSAGES)
    assert int(out.split()[3]) > 40  # sub-packages were checked one by one too


def test_damaged_messages_encode_back_too(asan, tmp_path):
    """Malformed, unknown and extra-byte parts are kept raw, so they re-encode exactly."""
    for i, data in enumerate(streams(MESSAGES, 150, seed=11)):
        roundtrip(asan, data, tmp_path / f"s{i}.bin")
