"""Encoders: encode(decode(m)) == m for every framed message and sub-package, lengths computed,
and an output buffer one byte short fails cleanly (under the sanitizers). The test driver
checks stream after stream in one process (`driver batch roundtrip`)."""
from __future__ import annotations

from tests.c.harness_c import CommandPeer
from tests.c.seeds import messages
from tests.tools.streams import streams
from tests.vectors import all_cases

MESSAGES = [m for case in all_cases() for m in messages(case.data)]


def roundtrip(peer: CommandPeer, data: bytes, hint: str = "") -> str:
    (out,), code = peer.decode(data, hint)
    assert code == 0, f"{out} {data.hex()}"
    return out


def test_every_vector_message_encodes_back_to_its_bytes(asan):
    with CommandPeer(asan.driver, "roundtrip") as peer:
        out = roundtrip(peer, b"".join(MESSAGES))
    count = int(out.split()[1])
    assert count == len(MESSAGES)
    assert int(out.split()[3]) > 40  # sub-packages were checked one by one too


def test_damaged_messages_encode_back_too(asan):
    """Malformed, unknown and extra-byte parts are kept raw, so they re-encode exactly."""
    with CommandPeer(asan.driver, "roundtrip") as peer:
        for data in streams(MESSAGES, 150, seed=11):
            roundtrip(peer, data)
