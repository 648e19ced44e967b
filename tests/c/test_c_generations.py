"""Every controller generation through the C command and the Python decoder: sessions of random
valid messages of each generation (tests/tools/valid.py), with and without their Version message
and under a hint, print the same records byte for byte."""
from __future__ import annotations

import random

import pytest

from tests.c.harness_c import CommandPeer, python_lines
from tests.tools import valid


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_agree_with_python(fast, version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    with CommandPeer(fast.driver) as peer:
        for k in range(12):
            data = valid.session(rng, version, 12)
            cut = data[int.from_bytes(data[:4], "big"):]          # as a capture that starts mid-stream
            for stream, given in ((data, None), (cut, None), (cut, hint)):
                lines, code = python_lines(stream, given)
                assert peer.decode(stream, given or "") == (lines, code), f"{given} {stream.hex()}"


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_the_robot_state_decoder_agrees_with_the_iterator_in_every_generation(asan, version):
    """The one-pass robot-state decoder (with the fast paths of its version's row, where it has
    one) against the iterator, member by member (the driver's roundtrip), on sessions of each
    generation: with the Version message, cut before it, and cut under a hint."""
    rng = random.Random(hash(version) + 1)
    hint = ".".join(map(str, version))
    with CommandPeer(asan.driver, "roundtrip") as peer:
        for _ in range(4):
            data = valid.session(rng, version, 12)
            cut = data[int.from_bytes(data[:4], "big"):]
            for stream, given in ((data, ""), (cut, ""), (cut, hint)):
                (out,), code = peer.decode(stream, given)
                assert code == 0, f"{given} {out} {stream.hex()}"
