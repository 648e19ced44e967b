"""Every controller generation through the C command and the Python decoder: sessions of random
valid messages of each generation (tests/tools/valid.py), with and without their Version message
and under a hint, print the same records byte for byte."""
from __future__ import annotations

import random

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
