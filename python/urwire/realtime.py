"""The real-time interface (30003, 30013): framing a stream of fixed packets, each chosen by its
int32 size, and the records of packets no layout fits.

The layouts, and the rule that chooses one for a size (`FORMS_BY_SIZE`, spec framing.same_size),
are generated from spec/ur_realtime.yaml into urwire.generated.ur_realtime. Bad input never
raises: a size no layout has is kept raw in an `UnknownPacket` with its error, and framing goes on
after it; a size that cannot frame a packet (below 12, or above the largest plausible) is a
`StreamError`, and framing goes on at the next plausible packet, the next size some layout has
(docs/realtime.md); a packet cut
short is reported by `close()`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Iterable, Optional, Union

from ._runtime import StreamError
from .arguments import VersionLike, bytes_of, parse_version
from .extension import CCORE
from .generated.ur_realtime import FLAT_LAYOUTS, FORMS_BY_SIZE, MAX_MESSAGE_SIZE, SIZE_FIELD, SIZE_FIELD_BYTES

# The smallest size that frames a packet: the size field and one double.
MIN_MESSAGE_SIZE = SIZE_FIELD_BYTES + 8
# Under the C backend (extension.py) a packet's record is made in C from its layout's
# FLAT_LAYOUTS entry, the same record its class's decoder makes; None under pure Python.
_C_PACKETS = None if CCORE is None else CCORE.FlatRecords(FLAT_LAYOUTS)


@dataclass(slots=True)
class UnknownPacket:
    """A packet whose size matches no layout: its bytes after the size field, kept."""

    TYPE: ClassVar[str] = "unknown"
    LABEL: ClassVar[str] = "Real-time packet of unknown size"
    IS_ERROR: ClassVar[bool] = True      # the command exits 1 for it, as urwire-decode does
    JSON: ClassVar[tuple] = (("message_size", "int", False), ("error", "text", False), ("raw", "hex", False))

    message_size: int
    error: str
    raw: bytes
    extra: bytes = b""

    def encode(self) -> bytes:
        return SIZE_FIELD.pack(self.message_size) + self.raw


def version_number(version: tuple[int, int, int]) -> int:
    """The number FORMS_BY_SIZE's bounds are written in (codegen's ir.version_number)."""
    major, minor, bugfix = version
    return (major * 1000 + minor) * 1000 + min(bugfix, 999)


def form_of(size: int, version: Optional[tuple[int, int, int]]):
    """(low, high, class, enum name tables) a packet of this size is read as, or None: the first
    form of the size whose versions hold `version`, else the last (the newest)."""
    forms = FORMS_BY_SIZE.get(size)
    if forms is None:
        return None
    if version is not None:
        number = version_number(version)
        for form in forms:
            if form[0] <= number <= form[1]:
                return form
    return forms[-1]


def decode_packet(packet, offset: int = 0, version: VersionLike = None, stream_offset: Optional[int] = None):
    """One whole packet (packet[offset:] starts with its size field and holds all of it) -> its
    record. The caller has framed it: the size is read, not checked against len(packet). An
    error names `stream_offset` (default: offset), where the packet starts in its stream."""
    size = SIZE_FIELD.unpack_from(packet, offset)[0]
    form = form_of(size, parse_version(version))
    if form is None:
        at = offset if stream_offset is None else stream_offset
        return UnknownPacket(size, f"packet at offset {at}: size {size} matches no layout",
                             bytes(packet[offset + SIZE_FIELD_BYTES:offset + size]))
    if _C_PACKETS is not None:
        record = _C_PACKETS.decode(form[2], packet, offset)
        if record is not None:
            return record
    return form[2].decode(packet, offset)


def names_of(record, version: VersionLike = None) -> dict:
    """The enum name tables for a record's coded fields (robot_mode -> {7: "RUNNING", ...}), as the
    same_size rule picks its form: what a text view shows beside the numbers."""
    form = form_of(record.SIZE, parse_version(version)) if hasattr(record, "SIZE") else None
    return form[3] if form else {}


def encode(record) -> bytes:
    return record.encode()


class RealtimeFramer:
    """Bytes of one real-time stream in chunks of any size in, records out in order."""

    def __init__(self, version_hint: VersionLike = None):
        self.version = parse_version(version_hint)
        """The software version that chooses among layouts of one size; a capture reader may set
        it from the primary stream of the same robot."""
        self._buffer = bytearray()
        self._offset = 0          # stream offset of the buffer's first byte
        self._scanning = False    # after a size that cannot frame a packet: looking for the next one

    def feed(self, data) -> list:
        data = bytes_of(data, "RealtimeFramer.feed")
        self._buffer += data
        return self._frame(final=False)

    def close(self) -> list:
        """What is left at the end of the stream: whole packets a scan found, and a packet cut short,
        as a StreamError."""
        out = self._frame(final=True)
        tail, self._buffer = self._buffer, bytearray()
        offset, left = self._offset, len(tail)
        self._offset += left
        if not left or self._scanning:
            self._scanning = False
            return out
        needed = SIZE_FIELD.unpack_from(tail, 0)[0] if left >= SIZE_FIELD_BYTES else SIZE_FIELD_BYTES
        return out + [StreamError(offset, f"packet at offset {offset}: needs {needed} bytes, {left} left")]

    def restart(self, offset: int) -> list:
        """The stream lost bytes: what is held is given up (close()'s records), and framing starts
        afresh at stream offset `offset`, the version kept."""
        out = self.close()
        self._offset = offset
        return out

    def _frame(self, final: bool) -> list:
        buf = self._buffer
        out, pos, end = [], 0, len(buf)
        while True:
            if self._scanning:
                pos = _next_packet(buf, pos, final)
                if pos < 0:              # none yet: keep what could still start one
                    pos = -pos - 1
                    break
                self._scanning = False
            if end - pos < SIZE_FIELD_BYTES:
                break
            size = SIZE_FIELD.unpack_from(buf, pos)[0]
            fault = _fault(size)
            if fault is not None:
                out.append(StreamError(self._offset + pos, f"packet at offset {self._offset + pos}: {fault}"))
                self._scanning = True
                pos += 1
                continue
            if end - pos < size:
                break
            out.append(decode_packet(buf, pos, self.version, self._offset + pos))
            pos += size
        del buf[:pos]
        self._offset += pos
        return out


def _fault(size: int) -> Optional[str]:
    if size < MIN_MESSAGE_SIZE:
        return f"size {size} is below {MIN_MESSAGE_SIZE}"
    if size > MAX_MESSAGE_SIZE:
        return f"size {size} is above {MAX_MESSAGE_SIZE}"
    return None


def _next_packet(buf: bytearray, pos: int, final: bool) -> int:
    """Where the next plausible packet starts, from `pos` on: the next size some layout has (a size
    no layout has is not trusted, since the doubles of a packet hold small int32s often enough).
    -1 - p when none is found yet, p being where the scan goes on when more bytes come (-1 -
    len(buf) at the end of the stream)."""
    end = len(buf)
    while end - pos >= SIZE_FIELD_BYTES:
        if SIZE_FIELD.unpack_from(buf, pos)[0] in FORMS_BY_SIZE:
            return pos
        pos += 1
    return -1 - (end if final else pos)


def decode_stream(data: Union[bytes, Iterable[bytes]], version_hint: VersionLike = None) -> list:
    """Every record of a whole real-time stream (bytes, or an iterable of chunks)."""
    framer = RealtimeFramer(version_hint)
    chunks = (data,) if isinstance(data, (bytes, bytearray, memoryview)) else data
    out = []
    for chunk in chunks:
        out += framer.feed(chunk)
    return out + framer.close()


class RealtimeConversation:
    """One TCP connection to 30003/30013: the robot's packets decoded. What a client sends there is
    URScript, which is not decoded."""

    def __init__(self, version_hint: VersionLike = None):
        self.framer = RealtimeFramer(version_hint)
        self.hinted = version_hint is not None

    def feed(self, data: bytes, from_robot: bool) -> list:
        return self.framer.feed(data) if from_robot else []

    def learn_version(self, version: tuple[int, int, int]) -> None:
        """The version the primary stream of the same robot announced: it chooses among layouts of
        one size, unless the caller gave a version (spec framing.same_size)."""
        if not self.hinted:
            self.framer.version = version

    def close(self, from_robot: Optional[bool] = None) -> list:
        """A packet cut short at the end of the robot's stream; the client's is not decoded."""
        return [] if from_robot is False else self.framer.close()

    def lost(self, from_robot: bool, offset: int) -> list:
        """Bytes of one direction are missing before stream offset `offset`: the packet they cut
        short is reported, and the robot's stream is framed afresh from there."""
        return self.framer.restart(offset) if from_robot else []


__all__ = ["UnknownPacket", "RealtimeFramer", "RealtimeConversation", "decode_packet", "decode_stream",
           "encode", "form_of", "names_of", "MIN_MESSAGE_SIZE"]
