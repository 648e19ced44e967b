"""Streaming framer: bytes in chunks of any size in, decoded records out, in stream order.

Frames by the declared lengths, learns the software version from each Version message (a bugfix
out of range is set aside and flagged in `Framer.version_note`), and reports stream faults (bad
length, unknown type, truncated tail) then resynchronises on the next plausible header; after a
truncated tail, on the next whole message inside it.
"""
from __future__ import annotations

import re
from typing import Iterable, Iterator, Optional, Union

from ._runtime import StreamError
from .arguments import VersionLike, bytes_of, parse_version
from .decoding import decode_message
from .generated.spec import (BUGFIX_ANY, DEFAULT_VERSION, HEADER, HEADER_SIZE, KNOWN_MESSAGE_TYPES,
                             MAX_MESSAGE_LENGTH)


def _fault(length: int, mtype: int) -> Optional[str]:
    if length < HEADER_SIZE:
        return f"length {length} is below {HEADER_SIZE}"
    if length > MAX_MESSAGE_LENGTH:
        return f"length {length} is above {MAX_MESSAGE_LENGTH}"
    if mtype not in KNOWN_MESSAGE_TYPES:
        return f"unknown message type {mtype}"
    return None


def _candidates() -> "re.Pattern[bytes]":
    """Where a plausible header may start: its length's first byte small enough for the largest
    length, and a known type after the length. A regular expression finds them at C speed, so
    that resynchronising over bytes that hold no header costs little; each one found is then
    checked in full (_fault)."""
    assert HEADER.format.endswith("B")  # the length, then a one-byte type
    length_size = HEADER_SIZE - 1
    first = MAX_MESSAGE_LENGTH >> 8 * (length_size - 1)
    def one_of(values) -> bytes:
        return b"[" + b"".join(re.escape(bytes([v])) for v in values) + b"]"
    return re.compile(b"(?=" + one_of(range(first + 1)) + b".{%d}" % (length_size - 1)
                      + one_of(sorted(KNOWN_MESSAGE_TYPES)) + b")", re.DOTALL)


_CANDIDATE = _candidates()


def _announced_version(msg, sets: tuple, offset: int) -> tuple[tuple[int, int, int], Optional[str]]:
    """The version a Version message sets, and a note when a part of it is out of range.

    Major and minor are single bytes, always in range. A bugfix below 0 or above BUGFIX_ANY
    cannot be compared with the spec's bounds, so it is set aside: the stream goes on as
    major.minor.0, the note says so, and the record itself keeps the number as it came."""
    major, minor, bugfix = sets
    major, minor = getattr(msg, major), getattr(msg, minor)
    bugfix = (getattr(msg, bugfix) or 0) if bugfix else 0
    if 0 <= bugfix <= BUGFIX_ANY:
        return (major, minor, bugfix), None
    return (major, minor, 0), (f"Version message at offset {offset}: bugfix version {bugfix} is out of range "
                               f"(0 to {BUGFIX_ANY}); the stream is read as {major}.{minor}")


class Framer:
    """Feed bytes with feed(); call close() at the end of the stream for a truncated tail."""

    def __init__(self, version_hint: VersionLike = None):
        self.hint = parse_version(version_hint)
        self.announced: Optional[tuple[int, int, int]] = None
        """The version the stream's last Version message set (see version_note)."""
        self.implied: Optional[tuple[int, int, int]] = None
        """The version the layout sizes of a robot state showed, when none was known."""
        self.version: tuple[int, int, int] = self.hint or DEFAULT_VERSION
        """Software version in force: the stream's last Version message, else the hint, else
        what the layout sizes show, else DEFAULT_VERSION."""
        self.version_seen = False
        self.version_note: Optional[str] = None
        """Why `version` differs from what the last Version message says (a part out of range
        was set aside), else None."""
        self._buf = bytearray()
        self._base = 0          # stream offset of _buf[0]
        self._resyncing = False
        self._ended_inside = False  # the stream ended inside a message: rescans stop at whole ones

    def feed(self, data: bytes) -> list:
        """The records that the bytes so far complete; data is any bytes-like object."""
        return list(self.feed_lazily(data))

    def feed_lazily(self, data: bytes) -> Iterator:
        """feed(), each record made as it is iterated: a reader that drops each record before
        the next holds one at a time, where feed() holds the whole chunk's (and the C backend then
        hands the copies of a dropped robot state to the next, see urwire.backends). Iterate it to
        the end before the next feed or close."""
        self._buf += bytes_of(data, "Framer.feed")
        return self._drain(final=False)

    def close(self) -> list:
        return list(self._drain(final=True))

    def restart(self, offset: int) -> list:
        """The stream lost bytes: what is held is given up (close()'s records), and framing starts
        afresh at stream offset `offset`, the version learnt kept."""
        out = self.close()
        self._buf.clear()
        self._base = offset
        self._resyncing = self._ended_inside = False
        return out

    def _drain(self, final: bool) -> Iterator:
        buf = self._buf
        n = len(buf)
        pos = 0
        while True:
            if self._resyncing:
                while True:
                    found = _CANDIDATE.search(buf, pos)
                    if found is None:
                        pos = max(pos, n - HEADER_SIZE + 1)  # keep what could start a header
                        break
                    pos = found.start()
                    length, mtype = HEADER.unpack_from(buf, pos)
                    if _fault(length, mtype) is None and not (self._ended_inside and length > n - pos):
                        self._resyncing = False
                        break
                    pos += 1
                if self._resyncing:
                    if final:
                        pos = n  # the last few bytes belong to the fault already reported
                    break
            left = n - pos
            if left < HEADER_SIZE:
                if final and left:
                    yield StreamError(self._base + pos, f"truncated header: {left} bytes left")
                    pos = n
                break
            length, mtype = HEADER.unpack_from(buf, pos)
            fault = _fault(length, mtype)
            if fault is not None:
                yield StreamError(self._base + pos, fault)
                self._resyncing = True
                pos += 1
                continue
            if length > left:
                if not final:
                    break
                # Every byte of the stream is here: the rest of the span is rescanned for the
                # whole messages it holds; headers whose lengths also run past the end belong to
                # this fault, so a tail of nested lengths costs one check per byte.
                yield StreamError(self._base + pos, f"truncated message: length {length}, {left} bytes left")
                self._ended_inside = self._resyncing = True
                pos += 1
                continue
            known = self.version_seen or self.hint is not None
            msg = decode_message(bytes(buf[pos:pos + length]), self.version, known)
            sets = getattr(msg, "SETS_VERSION", None)
            if sets is not None:
                self.announced, self.version_note = _announced_version(msg, sets, self._base + pos)
                self.version = self.announced
                self.version_seen = True
            elif not known and getattr(msg, "implied_version", None) is not None:
                self.version = self.implied = msg.implied_version
            pos += length
            yield msg
        if pos:
            del buf[:pos]
            self._base += pos


def decode_stream(data: Union[bytes, Iterable[bytes]], version_hint: VersionLike = None) -> Iterator:
    """Every record of a whole stream, made as it is iterated: a bytes-like object (any buffer,
    read as its bytes), or an iterable of them such as a socket reader's chunks. A large buffer
    is framed FEED bytes at a time, so that its records are never all held at once."""
    try:
        memoryview(data)
        chunks: Iterable = (data,)
    except TypeError:
        if isinstance(data, str) or not hasattr(data, "__iter__"):
            raise TypeError("decode_stream: expected a bytes-like object or an iterable of them, "
                            f"got {type(data).__name__}") from None
        chunks = data
    return _records(Framer(version_hint), chunks)


FEED = 1 << 20


def _records(framer: Framer, chunks: Iterable) -> Iterator:
    for chunk in chunks:
        data = memoryview(bytes_of(chunk, "a chunk of decode_stream"))
        for at in range(0, len(data), FEED):
            yield from framer.feed_lazily(data[at:at + FEED])
    yield from framer.close()
