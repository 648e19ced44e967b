"""urwire.message_kinds on its own, over made-up tables rather than the spec's: the robot-state
loop frames sub-packages by their lengths and keeps what it cannot read, and a subtype message
dispatches on its subtype byte, converts enum header fields and encodes back to the same bytes."""
from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import IntEnum
from typing import ClassVar

from urwire import _runtime as rt
from urwire.message_kinds import PackageList, PackageListMessage, Subtype, SubtypeMessage
from urwire.generated.spec import HEADER, PACKAGE_HEADER

DEMO_CODE = 99
VERSION = (5, 9, 0)
ONE_SEGMENT = ()  # no segment starts: every version is in segment 0


@dataclass(slots=True)
class DemoState(PackageListMessage):
    TYPE: ClassVar[str] = "demo_state"
    CODE: ClassVar[int] = DEMO_CODE
    LABEL: ClassVar[str] = "Demo state"


def message(code: int, body: bytes) -> bytes:
    return HEADER.pack(HEADER.size + len(body), code) + body


def package(code: int, body: bytes) -> bytes:
    return PACKAGE_HEADER.pack(PACKAGE_HEADER.size + len(body), code) + body


def test_package_list_frames_by_length_and_keeps_what_it_cannot_read():
    kind = PackageList(DemoState, rt.Forms({}, ONE_SEGMENT, ((),), {}, header=PACKAGE_HEADER.size), body_offset=HEADER.size)
    first, second = package(42, b"\x01\x02"), package(43, b"")
    buf = message(DEMO_CODE, first + second + b"\x00\x00\x00")
    state = kind.decode(buf, VERSION, True)
    assert state.packages == [rt.UnknownPackage(42, b"\x01\x02"), rt.UnknownPackage(43, b"")]
    at = HEADER.size + len(first) + len(second)
    assert state.error == f"package at offset {at}: needs {PACKAGE_HEADER.size} bytes, 3 left"
    assert state.raw == b"\x00\x00\x00"
    assert state.encode() == buf


def test_package_list_stops_at_a_length_that_overruns():
    kind = PackageList(DemoState, rt.Forms({}, ONE_SEGMENT, ((),), {}, header=PACKAGE_HEADER.size), body_offset=HEADER.size)
    bad = PACKAGE_HEADER.pack(100, 42) + b"\x01"
    state = kind.decode(message(DEMO_CODE, bad), VERSION, True)
    assert state.packages == [] and state.raw == bad
    assert state.error == f"package at offset {HEADER.size}: length 100 exceeds the {len(bad)} bytes left"


class Source(IntEnum):
    ROBOT = 1


@dataclass(slots=True)
class Note(Subtype):
    TYPE: ClassVar[str] = "note"
    CODE: ClassVar[int] = 7
    timestamp: int
    source: int
    value: int
    extra: bytes = b""
    decoded_version: tuple = None

    @classmethod
    def _decode(cls, buf, pos, end, version, header):
        if pos + 2 > end:
            raise rt.short("value", pos, 2, end)
        (value,) = struct.unpack_from(">H", buf, pos)
        return cls(*header, value, b"", version), pos + 2

    def _encode(self, out, version):
        out += struct.pack(">H", self.value) + self.extra


def note_message() -> SubtypeMessage:
    header = struct.Struct(">QbB")
    forms = rt.Forms({Note.CODE: (rt.Form(Note, Note._decode, frozenset({2}), 2, VERSION, "every version"),)},
                     ONE_SEGMENT, ((0,),), {Note.CODE: {}})
    return SubtypeMessage(DEMO_CODE, header, ("timestamp", "source"),
                          (("timestamp", 5, 8), ("source", 13, 1), ("subtype", 14, 1)),
                          header_offset=HEADER.size, body_offset=HEADER.size + header.size, subtype="subtype",
                          converts=((1, {1: Source.ROBOT}, False),), forms=forms, layouts=(Note,))


def test_subtype_message_dispatches_converts_and_encodes_back():
    kind = note_message()
    buf = message(DEMO_CODE, struct.pack(">QbB", 5, 1, Note.CODE) + b"\x01\x02" + b"\xff")
    note = kind.decode(buf, VERSION, True)
    assert note == Note(5, Source.ROBOT, 0x0102, b"\xff", VERSION)
    assert note.source is Source.ROBOT and Note.MESSAGE is kind and Note.MESSAGE_TYPE == DEMO_CODE
    assert note.encode() == buf


def test_subtype_message_keeps_unknown_and_malformed_subtypes():
    kind = note_message()
    unknown = kind.decode(message(DEMO_CODE, struct.pack(">QbB", 5, 1, 8) + b"\x01"), VERSION, True)
    assert isinstance(unknown, rt.UnknownSubtype) and unknown.subtype == 8 and unknown.raw == b"\x01"
    short = message(DEMO_CODE, struct.pack(">QbB", 5, 1, Note.CODE) + b"\x01")
    malformed = kind.decode(short, VERSION, True)
    assert isinstance(malformed, rt.MalformedSubtype) and "value" in malformed.error
    assert kind.encode(malformed, VERSION) == short
    cut = kind.decode(message(DEMO_CODE, b"\x00\x00"), VERSION, True)
    assert isinstance(cut, rt.UnknownMessage) and "timestamp" in cut.error
