"""Records out of files: raw streams read in chunks, captures split into the TCP conversations of
the interfaces asked for (by default the primary one), each decoded by its interface (cell.py).

Captures need dpkt, which is imported only when a capture is read.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import BinaryIO, Callable, Iterable, Iterator, Optional, Union

from .arguments import VersionLike
from .capture import HEAD_BYTES, head_of, is_capture
from .cell import timed_cell_records
from .framer import Framer
from .generated.spec import PORTS
from .interfaces import INTERFACES, Interface

CHUNK = 1 << 20


def records_of_raw(fh: BinaryIO, hint: VersionLike, advance: Callable[[int], None]) -> Iterator:
    framer = Framer(hint)
    while True:
        chunk = fh.read(CHUNK)
        if not chunk:
            break
        advance(len(chunk))
        yield from framer.feed_lazily(chunk)
    yield from framer.close()


def records_of_capture(fh: BinaryIO, hint: VersionLike, ports: Iterable[int],
                       advance: Callable[[int], None], by_port: Optional[dict[int, Interface]] = None) -> Iterator:
    for _, record in timed_records_of_capture(fh, hint, ports, advance, by_port):
        yield record


def timed_records_of_capture(fh: BinaryIO, hint: VersionLike, ports: Iterable[int],
                             advance: Callable[[int], None] = lambda n: None,
                             by_port: Optional[dict[int, Interface]] = None) -> Iterator[tuple]:
    """(capture time, record): each TCP conversation gets its own decoder, so each learns its own
    version; a record's time is that of the frame that completed it. `ports` are read as the
    primary interface, unless `by_port` says which interface each port is. A capture record that
    cannot be read gives an error record (no time) naming its offset in the capture file."""
    if by_port is None:
        by_port = {port: INTERFACES["ur"] for port in ports}
    yield from timed_cell_records(fh, hint, by_port, advance)


def records_of(fh: BinaryIO, hint: VersionLike = None, ports: Iterable[int] = PORTS,
               advance: Callable[[int], None] = lambda n: None,
               by_port: Optional[dict[int, Interface]] = None) -> Iterator:
    """Records of an open binary file: a raw stream of the primary interface, a .pcap or a .pcapng
    (told by its magic; `ports` and `by_port` as timed_records_of_capture takes them)."""
    head = head_of(fh)
    if is_capture(head):
        return records_of_capture(fh, hint, ports, advance, by_port)
    return records_of_raw(fh, hint, advance)


def decode_file(path: Union[str, os.PathLike], version_hint: VersionLike = None,
                ports: Optional[Iterable[int]] = None) -> Iterator:
    """Every record of a raw stream, .pcap or .pcapng file, in order."""
    with open(Path(path), "rb") as fh:
        yield from records_of(fh, version_hint, ports or PORTS)


def timed_records(path: Union[str, os.PathLike], version_hint: VersionLike = None,
                  ports: Optional[Iterable[int]] = None,
                  by_port: Optional[dict[int, Interface]] = None) -> Iterator[tuple]:
    """(capture time in seconds since the epoch, record) of a .pcap or .pcapng file (`ports` and
    `by_port` as timed_records_of_capture takes them); a raw stream has no times (None)."""
    with open(Path(path), "rb") as fh:
        head = head_of(fh)
        if is_capture(head):
            yield from timed_records_of_capture(fh, version_hint, ports or by_port or PORTS, by_port=by_port)
        else:
            for record in records_of_raw(fh, version_hint, lambda n: None):
                yield None, record


def input_kind(path: Union[str, os.PathLike]) -> str:
    """"capture" or "stream": what a file is read as, for messages that name it."""
    try:
        with open(Path(path), "rb") as fh:
            return "capture" if is_capture(fh.read(HEAD_BYTES)) else "stream"
    except OSError:
        return "file"
