"""Every controller generation through the C command and the Python decoder: sessions of random
valid messages of each generation (tests/tools/valid.py), with and without their Version message
and under a hint, print the same records byte for byte."""
from __future__ import annotations

import random
import subprocess

import pytest

from tests.c.harness_c import python_lines, run_cli
from tests.tools import valid


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_agree_with_python(fast, version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    for k in range(12):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]          # as a capture that starts mid-stream
        for stream, args in ((data, ()), (cut, ()), (cut, ("--version-hint", hint))):
            result = run_cli(fast, stream, *args)
            lines, code = python_lines(stream, args[1] if args else None)
            # split on "\n" only: a text may hold U+2028 or U+0085, which JSON leaves as they are
            assert result.stdout.decode("utf-8").split("\n")[:-1] == lines, f"{args} {stream.hex()}"
            assert result.returncode == code


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_the_robot_state_decoder_agrees_with_the_iterator_in_every_generation(asan, version, tmp_path):
    """The one-pass robot-state decoder (with the fast paths of its version's row, where it has
    one) against the iterator, member by member (the driver's roundtrip), on sessions of each
    generation: with the Version message, cut before it, and cut under a hint."""
    rng = random.Random(hash(version) + 1)
    hint = ".".join(map(str, version))
    path = tmp_path / "s.bin"
    for _ in range(4):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]
        for stream, args in ((data, []), (cut, []), (cut, [hint])):
            path.write_bytes(stream)
            result = subprocess.run([str(asan.driver), "roundtrip", str(path), *args], capture_output=True, text=True)
            assert result.returncode == 0, f"{args} {result.stdout}{result.stderr} {stream.hex()}"
