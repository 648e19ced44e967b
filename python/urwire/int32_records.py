"""The runtime of an interface of fixed int32 records (the ROS driver's sockets, generated/...
ur_reverse.py, ur_trajectory.py, ur_script_command.py): each direction cut into records of the
size its driver release gives, each record's int32s mapped onto its fields, scaled ones divided
by their scale.

The generated module gives the record classes and their layouts by release (RECORDS); this
module is the same for every such interface.
"""
from __future__ import annotations

import bisect
import struct
from dataclasses import dataclass
from types import ModuleType
from typing import Optional

from ._runtime import StreamError
from .arguments import parse_version

Version = tuple[int, int, int]


@dataclass(frozen=True)
class Slot:
    name: str
    index: int                  # of its first int32 in the record
    count: int                  # 1: a value, more: a list
    scale: Optional[int]        # divide by it; None: the int32 as it is
    enum: Optional[type]        # an IntEnum for known codes


@dataclass(frozen=True)
class Layout:
    size: int                   # bytes
    struct: struct.Struct
    slots: tuple[Slot, ...]


@dataclass(frozen=True)
class RecordKind:
    cls: type
    starts: tuple[Version, ...]       # the first release of every layout but the first
    layouts: tuple[Layout, ...]

    def layout(self, release: Version) -> Layout:
        return self.layouts[bisect.bisect_right(self.starts, release)]


def layout(slots: tuple[Slot, ...]) -> Layout:
    count = sum(s.count for s in slots)
    return Layout(4 * count, struct.Struct(f">{count}i"), slots)


def _value(slot: Slot, ints: tuple):
    if slot.count > 1:
        values = ints[slot.index:slot.index + slot.count]
        return [v / slot.scale for v in values] if slot.scale else list(values)
    v = ints[slot.index]
    if slot.scale:
        return v / slot.scale
    if slot.enum is not None:
        try:
            return slot.enum(v)
        except ValueError:
            return v            # a code the spec does not name stays a number
    return v


def decode_record(kind: RecordKind, data: bytes, release: Version):
    """One whole record (len(data) == its layout's size) -> its instance."""
    lay = kind.layout(release)
    ints = lay.struct.unpack(data)
    return kind.cls(**{slot.name: _value(slot, ints) for slot in lay.slots})


class _Direction:
    def __init__(self, kind: Optional[RecordKind]):
        self.kind = kind
        self.buffer = bytearray()
        self.offset = 0
        self.skip = 0           # after a gap: bytes to the next record's start, still to drop
        self.skipped = 0        # of those, dropped so far


class RecordsConversation:
    """One TCP connection of an int32-record interface: `feed(data, from_robot)` -> records."""

    def __init__(self, tables: ModuleType, version_hint=None):
        self.tables = tables
        self.release: Version = parse_version(version_hint) if version_hint is not None else tables.DEFAULT_RELEASE
        self.directions = {from_robot: _Direction(tables.RECORDS.get(from_robot)) for from_robot in (False, True)}

    def feed(self, data: bytes, from_robot: bool) -> list:
        d = self.directions[from_robot]
        if d.kind is None:
            # Nothing is specified this way: the bytes are counted, and reported when the stream ends.
            d.buffer += data
            return []
        d.buffer += data
        out = self._realign(d) if d.skip else []
        size = d.kind.layout(self.release).size
        whole = len(d.buffer) - len(d.buffer) % size
        out += [decode_record(d.kind, bytes(d.buffer[at:at + size]), self.release) for at in range(0, whole, size)]
        del d.buffer[:whole]
        d.offset += whole
        return out

    def close(self, from_robot: Optional[bool] = None) -> list:
        """What one direction's end leaves (both, to_robot's first, when from_robot is None)."""
        if from_robot is None:
            return self.close(False) + self.close(True)
        d = self.directions[from_robot]
        if d.skipped:                       # the stream ended before the next record's start
            return self._realigned(d)
        if not d.buffer:
            return []
        left, at = len(d.buffer), d.offset
        d.offset += left
        d.buffer.clear()
        if d.kind is None:
            return [StreamError(at, f"{left} bytes {_side(from_robot)}, where none are specified")]
        size = d.kind.layout(self.release).size
        return [StreamError(at, f"{left} bytes left, short of a {size}-byte record")]

    def lost(self, from_robot: bool, offset: int) -> list:
        """Bytes of one direction are missing before `offset`: its partial record is given up as
        close() gives it, and its records are cut afresh from the next record's start: records
        are all one size from the stream's start, so bytes before it are the end of a record
        whose start is lost, named by an error record, not read as one misaligned."""
        out = self.close(from_robot)
        d = self.directions[from_robot]
        d.offset = offset
        if d.kind is not None:
            d.skip = -offset % d.kind.layout(self.release).size
        return out

    def _realign(self, d: _Direction) -> list:
        n = min(d.skip, len(d.buffer))
        del d.buffer[:n]
        d.offset += n
        d.skip -= n
        d.skipped += n
        return [] if d.skip else self._realigned(d)

    @staticmethod
    def _realigned(d: _Direction) -> list:
        n, d.skipped, d.skip = d.skipped, 0, 0
        return [StreamError(d.offset - n, f"{n} bytes after bytes lost from the capture: the end of a record "
                                          f"whose start is lost")]


def _side(from_robot: bool) -> str:
    return "from the robot" if from_robot else "to the robot"
