"""Records out of files: raw streams read in chunks, captures split into robot->client streams.

Captures need dpkt, which is imported only when a capture is read.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import BinaryIO, Callable, Iterable, Iterator, Optional, Union

from .arguments import VersionLike
from .capture import is_capture, timed_robot_streams
from .capture_records import CaptureFault
from ._runtime import StreamError
from .framer import Framer
from .generated.spec import PORTS

CHUNK = 1 << 20


def records_of_raw(fh: BinaryIO, hint: VersionLike, advance: Callable[[int], None]) -> Iterator:
    framer = Framer(hint)
    while True:
        chunk = fh.read(CHUNK)
        if not chunk:
            break
        advance(len(chunk))
        yield from framer.feed(chunk)
    yield from framer.close()


def records_of_capture(fh: BinaryIO, hint: VersionLike, ports: Iterable[int],
                       advance: Callable[[int], None]) -> Iterator:
    for _, record in timed_records_of_capture(fh, hint, ports, advance):
        yield record


def timed_records_of_capture(fh: BinaryIO, hint: VersionLike, ports: Iterable[int],
                             advance: Callable[[int], None] = lambda n: None) -> Iterator[tuple]:
    """(capture time, record): each robot->client TCP stream gets its own framer, so each learns
    its own version; a record's time is that of the frame that completed it. A capture record
    that cannot be read gives an error record (no time) naming its offset in the capture file."""
    framers: dict = {}
    last = 0
    for item in timed_robot_streams(fh, set(ports)):
        if isinstance(item, CaptureFault):  # its offset is the capture file's, not a stream's
            yield None, StreamError(item.offset, item.error)
            continue
        key, data, ended, time = item
        framer = framers.get(key) or framers.setdefault(key, Framer(hint))
        if data:
            for record in framer.feed(data):
                yield time, record
        if ended:
            for record in framer.close():
                yield time, record
            del framers[key]
        if fh.seekable():
            pos = fh.tell()
            advance(pos - last)
            last = pos


def records_of(fh: BinaryIO, hint: VersionLike = None, ports: Iterable[int] = PORTS,
               advance: Callable[[int], None] = lambda n: None) -> Iterator:
    """Records of an open binary file: a raw stream, a .pcap or a .pcapng (told by its magic)."""
    head = fh.peek(4)[:4] if hasattr(fh, "peek") else b""
    if is_capture(head):
        return records_of_capture(fh, hint, ports, advance)
    return records_of_raw(fh, hint, advance)


def decode_file(path: Union[str, os.PathLike], version_hint: VersionLike = None,
                ports: Optional[Iterable[int]] = None) -> Iterator:
    """Every record of a raw stream, .pcap or .pcapng file, in order."""
    with open(Path(path), "rb") as fh:
        yield from records_of(fh, version_hint, ports or PORTS)


def timed_records(path: Union[str, os.PathLike], version_hint: VersionLike = None,
                  ports: Optional[Iterable[int]] = None) -> Iterator[tuple]:
    """(capture time in seconds since the epoch, record) of a .pcap or .pcapng file; a raw
    stream has no times (None)."""
    with open(Path(path), "rb") as fh:
        head = fh.peek(4)[:4] if hasattr(fh, "peek") else b""
        if is_capture(head):
            yield from timed_records_of_capture(fh, version_hint, ports or PORTS)
        else:
            for record in records_of_raw(fh, version_hint, lambda n: None):
                yield None, record


def input_kind(path: Union[str, os.PathLike]) -> str:
    """"capture" or "stream": what a file is read as, for messages that name it."""
    try:
        with open(Path(path), "rb") as fh:
            return "capture" if is_capture(fh.read(4)) else "stream"
    except OSError:
        return "file"
