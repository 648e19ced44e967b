"""Records out of files: raw streams read in chunks, captures split into the TCP conversations of
the interfaces asked for, each decoded by its interface (cell.py).

`decode_file` gives the primary interface's records of a raw stream or a capture, as they are;
`decode_capture` every interface's records of a capture, each with its interface, direction,
conversation and capture time. Captures need dpkt, which is imported only when a capture is read.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import BinaryIO, Callable, Iterable, Iterator, Optional, Union

from .arguments import VersionLike
from .capture import HEAD_BYTES, OtherConversations, head_of, is_capture
from .cell import PRIMARY, cell_records, interface_named, ports_of, timed_cell_records
from .envelope import Endpoints, Enveloped
from .framer import Framer
from .generated.spec import PORTS
from .interfaces import INTERFACES, Interface, interface_of_port

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
    """The primary interface's records of a raw stream, .pcap or .pcapng file, in order, as they
    are (RobotStateMessage, VersionMessage, ...). In a capture these are the robot->client
    streams on `ports` (default: the primary interface's), every robot's interleaved, with no
    word of which conversation each came from: decode_capture gives that, and every other
    interface's records."""
    with open(Path(path), "rb") as fh:
        yield from records_of(fh, version_hint, ports or PORTS)


def ports_read(protocol: Optional[str] = None, ports: Optional[Iterable[int]] = None) -> dict[int, Interface]:
    """Which interface reads each port of a capture: `ports` as `protocol`'s (default the primary
    interface's); without them, `protocol`'s own ports, or every interface's."""
    interface = interface_named(protocol or PRIMARY)
    if ports:
        return {port: interface for port in ports}
    return ports_of([interface] if protocol else INTERFACES.values())


def unclaimed_of(others: OtherConversations) -> dict[Endpoints, int]:
    """The conversations of `others` that no interface reads on either port, with the bytes each
    carried: what decode_capture and `urwire decode` did not decode because nothing claims them
    (those on another interface's ports were left out as asked)."""
    return {Endpoints(*key): count for key, count in others.bytes.items()
            if interface_of_port(key[1]) is None and interface_of_port(key[3]) is None}


class CaptureRecords:
    """The records of a capture, decoded as they are iterated (see decode_capture).

    `unclaimed`: the TCP conversations of the capture that no interface of the cell reads (none
    of its ports is one of theirs), each with the bytes it carried, as far as the capture has
    been read: complete once the records are. `--protocol NAME --port PORT` (or decode_capture's
    `protocol` and `ports`) reads such a conversation as an interface's."""

    def __init__(self, read: Callable[[OtherConversations], Iterator[Enveloped]]):
        self._others = OtherConversations()
        self._records = read(self._others)      # read(others): the records, telling others what it skips

    def __iter__(self) -> "CaptureRecords":
        return self

    def __next__(self) -> Enveloped:
        return next(self._records)

    @property
    def unclaimed(self) -> dict[Endpoints, int]:
        return unclaimed_of(self._others)


def capture_records(fh: BinaryIO, hint: VersionLike = None, by_port: Optional[dict[int, Interface]] = None,
                    advance: Callable[[int], None] = lambda n: None) -> CaptureRecords:
    """decode_capture's records of an open capture (by default, every interface by its ports)."""
    return CaptureRecords(lambda others: cell_records(fh, hint, by_port or ports_read(), advance, others))


def decode_capture(path: Union[str, os.PathLike], version_hint: VersionLike = None, *, protocol: Optional[str] = None,
                   ports: Optional[Iterable[int]] = None) -> CaptureRecords:
    """Every record of a .pcap or .pcapng capture of a cell, in capture order: each TCP
    conversation whose server port is one of an interface's (urwire.interfaces.INTERFACES) is
    decoded by that interface, each with a decoder of its own, so each learns its own robot's
    version. Each record is an Enveloped: `interface` ("ur", "ur_realtime", "rtde", ...),
    `direction` ("from_robot", "to_robot"), `conversation` (Endpoints: both addresses and ports),
    `capture_time`, and `record`, what the interface decoded. A block of the capture file that
    cannot be read gives a StreamError with no interface, direction or conversation.

    `protocol` keeps one interface's conversations; `ports` reads those ports as `protocol`'s
    (default the primary interface's), as `urwire decode --protocol --port` does. The result's
    `unclaimed` names the conversations no interface reads. A file that is not a capture is a
    ValueError: decode_file reads raw streams."""
    by_port = ports_read(protocol, ports)
    if input_kind(path) != "capture":
        with open(Path(path), "rb"):      # an OSError of its own when it cannot be read
            pass
        raise ValueError(f"{os.fspath(path)} is not a .pcap or .pcapng capture: urwire.decode_file reads a raw stream")

    def read(others: OtherConversations) -> Iterator[Enveloped]:
        with open(Path(path), "rb") as fh:
            yield from cell_records(fh, version_hint, by_port, lambda n: None, others)

    return CaptureRecords(read)


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


UNCLAIMED_NAMED = 10     # conversations named in the line that says what no interface read


def say_unclaimed(unclaimed: Optional[dict]) -> None:
    """Once, on stderr: the conversations of a capture that no interface reads."""
    if not unclaimed:
        return
    named = [f"{ends} ({count} bytes)" for ends, count in list(unclaimed.items())[:UNCLAIMED_NAMED]]
    more = f" and {len(unclaimed) - len(named)} more" if len(unclaimed) > len(named) else ""
    print(f"urwire: not decoded, {len(unclaimed)} TCP conversation(s) on ports no interface reads "
          f"(--protocol NAME --port PORT reads one): {', '.join(named)}{more}", file=sys.stderr)
