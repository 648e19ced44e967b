"""`urwire streams`: the TCP payloads of a capture as raw streams, one file per conversation and
direction, named by interface, addresses and ports: what `urwire decode FILE`, `urwire-decode`
and a firmware read, byte for byte as the robot (or the client) sent them.

The capture is read and each direction reassembled by capture.timed_streams, as `urwire decode`
reads it; a gap the capture does not hold is left out of the file and said on stderr.
"""
from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Iterator, Optional, Union

from .arguments import port_number
from .capture import Differs, Gap, OtherConversations, head_of, is_capture, timed_streams
from .capture_records import CaptureFault
from .envelope import FROM_ROBOT, TO_ROBOT
from .interfaces import INTERFACES, Interface
from .reading import ports_read, say_unclaimed, unclaimed_of


@dataclass(frozen=True)
class Direction:
    """One direction of one TCP conversation of an interface: (server address, server port, client
    address, client port), as capture.timed_streams keys conversations."""

    interface: str
    conversation: tuple
    direction: str          # FROM_ROBOT or TO_ROBOT

    @property
    def file_name(self) -> str:
        """e.g. ur_192.168.56.101_30002_192.168.56.1_50100_from_robot.bin (an IPv6 address's colons
        become dashes)."""
        parts = [self.interface, *(str(part).replace(":", "-") for part in self.conversation), self.direction]
        return "_".join(parts) + ".bin"


Payload = Union[bytes, Gap, Differs, CaptureFault]


def payloads(fh: BinaryIO, by_port: dict[int, Interface],
             others: Optional[OtherConversations] = None) -> Iterator[tuple[Optional[Direction], Payload]]:
    """(direction, bytes) of both directions of every conversation on the ports of `by_port`, in
    capture order; where a direction's bytes are not whole, a Gap or Differs in their place, and a
    block of the capture file that cannot be read as (None, CaptureFault)."""
    for item in timed_streams(fh, set(by_port), frozenset(by_port), others):
        if isinstance(item, CaptureFault):
            yield None, item
            continue
        key, from_port, piece, _, _ = item
        interface = by_port[key[1]]
        from_robot = from_port != interface.robot_is_client
        if piece or not isinstance(piece, bytes):
            yield Direction(interface.name, key, FROM_ROBOT if from_robot else TO_ROBOT), piece


def write_streams(fh: BinaryIO, out: Path, by_port: dict[int, Interface],
                  others: Optional[OtherConversations] = None) -> tuple[dict[Path, int], list[str]]:
    """Write each direction's bytes to out/<Direction.file_name>: the files with their sizes, and
    what is not in them (gaps, differing retransmissions, unreadable blocks), a line each."""
    out.mkdir(parents=True, exist_ok=True)
    files: dict[Path, BinaryIO] = {}
    sizes: dict[Path, int] = {}
    problems: list[str] = []
    try:
        for direction, piece in payloads(fh, by_port, others):
            if direction is None:
                problems.append(f"capture file at offset {piece.offset}: {piece.error}")
                continue
            path = out / direction.file_name
            if not isinstance(piece, bytes):
                problems.append(f"{path.name}: {piece.error}")
                continue
            if path not in files:
                files[path] = path.open("wb")
                sizes[path] = 0
            files[path].write(piece)
            sizes[path] += len(piece)
    finally:
        for handle in files.values():
            handle.close()
    return sizes, problems


def add_parser(sub) -> None:
    p = sub.add_parser("streams", help="write a capture's TCP payloads as raw streams, a file per direction",
                       description="Reassemble every TCP conversation of a .pcap/.pcapng that an interface of "
                                   "the cell reads (by its ports) and write each direction's payload to "
                                   "OUTDIR/<interface>_<server address>_<port>_<client address>_<port>_"
                                   "<from_robot|to_robot>.bin: the raw streams `urwire decode`, "
                                   "`urwire-decode` and the C parser read. Bytes the capture lacks are "
                                   "left out and named on stderr (exit status 1).")
    p.add_argument("capture", help="a .pcap or .pcapng file")
    p.add_argument("outdir", help="the folder to write the streams in (made if missing)")
    p.add_argument("--protocol", choices=sorted(INTERFACES), default=None,
                   help="only this interface's conversations (default: every interface of the cell)")
    p.add_argument("--port", type=port_number, action="append", metavar="PORT",
                   help="robot-side TCP port(s) to read as the --protocol interface (default: its own ports)")
    p.set_defaults(run=streams_command)


def streams_command(args: argparse.Namespace) -> int:
    try:
        with open(args.capture, "rb") as fh:
            if not is_capture(head_of(fh)):
                print(f"urwire streams: {args.capture} is not a .pcap or .pcapng capture", file=sys.stderr)
                return 2
            others = OtherConversations()
            sizes, problems = write_streams(fh, Path(args.outdir), ports_read(args.protocol, args.port), others)
    except OSError as exc:
        print(f"urwire streams: {exc.filename or args.capture}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except ValueError as exc:
        print(f"urwire streams: cannot read capture {args.capture}: {exc}", file=sys.stderr)
        return 2
    for path, size in sizes.items():
        print(f"{path}\t{size}")
    for problem in problems:
        print(f"urwire streams: not in the files: {problem}", file=sys.stderr)
    say_unclaimed(unclaimed_of(others))
    return 1 if problems else 0
