"""A capture that makes the Lua dissector carry bytes by hand: one large text message sent in
1 to 7 byte TCP segments, after one bad header (a length of -1), or without it (the baseline,
which TCP reassembly puts together). Deterministic: the same bytes and cuts every time."""
from __future__ import annotations

import struct
from pathlib import Path

from tests.tools import capture

BAD_HEADER = b"\xff\xff\xff\xff\x10"   # length -1, type 16: "length -1 is below 5"
BAD_HEADER_TEXT = "length -1 is below 5"


def text(size: int) -> bytes:
    """size printable bytes, none of them a new line."""
    return bytes(97 + (i * 7 + 3) % 26 for i in range(size))


def text_message(body_text: bytes) -> bytes:
    """A robot message (type 20) of subtype text (0): timestamp, source, subtype, text."""
    body = struct.pack(">QbB", 1, -2, 0) + body_text
    return struct.pack(">iB", 5 + len(body), 20) + body


def write(path: Path, size: int = 100_000, bad_header: bool = True, seed: int = 7) -> Path:
    """The capture: [bad header] + a text message of `size` text bytes, cut into 1-7 bytes."""
    data = (BAD_HEADER if bad_header else b"") + text_message(text(size))
    return capture.write(path, capture.robot_session(capture.random_cuts([data], seed=seed, max_len=7)))
