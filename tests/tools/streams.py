"""Seeded random and mutated streams for differential tests: the same bytes go through every
decoder, which must agree. Built from the golden and conformance messages, then damaged."""
from __future__ import annotations

import random
import struct
from typing import Iterator, Sequence

KNOWN_TYPES = (5, 16, 20, 22, 23, 24, 25, 255)


def _header(length: int, mtype: int) -> bytes:
    return struct.pack(">iB", length, mtype)


def mutate(data: bytes, rng: random.Random) -> bytes:
    """One random damage: flip bytes, cut, insert garbage, corrupt a length, or splice."""
    b = bytearray(data)
    kind = rng.randrange(7)
    if kind == 0 and b:
        for _ in range(rng.randint(1, 8)):
            b[rng.randrange(len(b))] = rng.randrange(256)
    elif kind == 1 and b:
        del b[rng.randrange(len(b)):]
    elif kind == 2:
        at = rng.randrange(len(b) + 1)
        b[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
    elif kind == 3 and len(b) >= 5:
        # A sub-package or message length somewhere: nudge it.
        at = rng.randrange(len(b) - 3)
        (n,) = struct.unpack_from(">i", b, at)
        struct.pack_into(">I", b, at, (n + rng.choice((-5, -1, 1, 3, 1 << 20, -n))) & 0xFFFFFFFF)
    elif kind == 4 and b:
        at = rng.randrange(len(b))
        del b[at:at + rng.randint(1, 40)]
    elif kind == 5:
        body = bytes(rng.randrange(256) for _ in range(rng.randint(0, 40)))
        at = rng.randrange(len(b) + 1)
        b[at:at] = _header(len(body) + 5, rng.choice(KNOWN_TYPES)) + body
    elif b:
        # Set a type byte after a length to something else.
        at = rng.randrange(len(b))
        b[at] = rng.choice((0, 1, 3, 9, 12, 14, 17, 18, 99, 255))
    return bytes(b)


def streams(messages: Sequence[bytes], count: int, seed: int = 1) -> Iterator[bytes]:
    """`count` streams: a few real messages in random order, then 0-3 mutations."""
    rng = random.Random(seed)
    for _ in range(count):
        picked = [rng.choice(messages) for _ in range(rng.randint(1, 5))]
        data = b"".join(picked)
        for _ in range(rng.choice((0, 1, 1, 2, 3))):
            data = mutate(data, rng)
        yield data


def cut_tails(messages: Sequence[bytes], count: int, seed: int = 1) -> Iterator[bytes]:
    """`count` streams that end inside a message: real messages around 1-3 headers (with a few
    body bytes) whose lengths run past the end of the stream, so their spans nest."""
    rng = random.Random(seed)
    for _ in range(count):
        parts: list = [rng.choice(messages) for _ in range(rng.randint(0, 5))]
        for _ in range(rng.randint(1, 3)):
            parts.insert(rng.randint(0, len(parts)), None)
        pieces, after = [], 0
        for part in reversed(parts):
            if part is None:
                body = rng.choice(messages)[5:5 + rng.randrange(12)]
                part = _header(after + 5 + len(body) + rng.randint(1, 3000), rng.choice(KNOWN_TYPES)) + body
            pieces.append(part)
            after += len(part)
        yield b"".join(reversed(pieces))
