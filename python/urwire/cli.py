"""The `urwire` command: decode raw streams and .pcap/.pcapng captures to canonical JSON Lines.

Exit codes: 0 everything decoded, 1 the output holds error records, 2 usage or I/O error.
"""
from __future__ import annotations

import argparse
import os
import sys
from typing import BinaryIO, Callable, Optional

from . import __version__
from .arguments import port_number, software_version
from .backends import JsonLines, backend
from .capture import head_of, is_capture
from .capture_json import CaptureJsonLines
from .canonical import fails, to_json_line
from .human import line as human_line
from .human import tree as human_tree
from .cell import interface_named, records_of_raw_protocol
from .interfaces import INTERFACES
from .reading import CHUNK, capture_records, input_kind, ports_read, records_of_raw, say_unclaimed
from .generated.spec import DEFAULT_VERSION, PORTS
from .data import export, plot, spark
from .live import listen, serve
from . import streams

PROGRESS_MIN_BYTES = 8 << 20


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # one line on stderr, exit 2, as the contract says
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    default = f"{DEFAULT_VERSION[0]}.{DEFAULT_VERSION[1]}"
    parser = _Parser(prog="urwire", description="Decode every interface of a Universal Robots cell: "
                                                "captures, streams and live robots.")
    parser.add_argument("--version", action="version", version=f"urwire {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    dec = sub.add_parser("decode", help="decode a raw stream, .pcap or .pcapng to canonical JSON Lines",
                         description="Decode a raw robot->client stream, or every TCP conversation of a "
                                     ".pcap/.pcapng capture that an interface of the cell reads (each record "
                                     "naming its interface, direction and conversation), and print one JSON "
                                     "object per message.")
    dec.add_argument("file", help="a raw stream, a .pcap or a .pcapng file; - for standard input")
    dec.add_argument("--protocol", choices=sorted(INTERFACES), default=None,
                     help="the interface a raw stream is from (default: ur, the primary/secondary interface); "
                          "for a capture, decode only this interface's conversations (default: every interface "
                          "of the cell, each by its ports)")
    dec.add_argument("--to-robot", metavar="FILE2",
                     help="with a raw stream: the client->robot stream of the same connection, read first; "
                          "each record then names its interface, direction and file")
    dec.add_argument("--version-hint", type=software_version, metavar="X.Y[.Z]",
                     help=f"software version to assume until a Version message is seen (e.g. 3.2 or 5.25.1): it "
                          f"chooses each part's layout and the meaning of version-dependent codes, such as the "
                          f"value types of global variables (default: {default}, i.e. {default} and later, "
                          f"unless the layout sizes of a robot state tell the version)")
    dec.add_argument("--format", choices=("json", "text", "tree"), default="json",
                     help="json: canonical JSON Lines (default); text: one readable line per message; "
                          "tree: every field of every message on a line of its own, with its label and unit")
    dec.add_argument("--port", type=port_number, action="append", metavar="PORT",
                     help=f"robot-side TCP port(s) to decode in captures, as the --protocol interface (default: "
                          f"each interface's own ports, the primary's {' '.join(map(str, PORTS))} among them)")
    dec.add_argument("--no-progress", action="store_true", help="never show a progress bar")
    dec.set_defaults(run=decode_command)
    for tool in (serve, listen, export, plot, spark, streams):
        tool.add_parser(sub)
    return parser


def _open(path: str) -> tuple[BinaryIO, Optional[int]]:
    if path == "-":
        return sys.stdin.buffer, None
    fh = open(path, "rb")
    size = os.fstat(fh.fileno()).st_size
    return fh, size


def _progress(size: Optional[int], disabled: bool) -> Callable[[int], None]:
    if disabled or size is None or size < PROGRESS_MIN_BYTES or not sys.stderr.isatty():
        return lambda n: None
    from tqdm import tqdm  # needed only when a bar is shown

    bar = tqdm(total=size, unit="B", unit_scale=True, desc="decoding", file=sys.stderr, leave=False)
    return bar.update


def _records(fh: BinaryIO, args: argparse.Namespace, advance: Callable[[int], None]):
    """The records of the input: a capture's conversations by port, each in its envelope, or a raw
    stream of one interface."""
    interface = interface_named(args.protocol or "ur")
    if args.to_robot is None and is_capture(head_of(fh)):
        return capture_records(fh, args.version_hint, ports_read(args.protocol, args.port), advance)
    if args.to_robot is None and interface.name == "ur":
        return records_of_raw(fh, args.version_hint, advance)
    to_robot = open(args.to_robot, "rb") if args.to_robot else None
    return records_of_raw_protocol(fh, interface, args.version_hint, CHUNK, advance, to_robot,
                                   (args.file, args.to_robot or ""))


def _c_json_lines(fh: BinaryIO, args: argparse.Namespace) -> Optional[str]:
    """What the C backend prints, as JSON Lines: "stream", a raw primary/secondary stream; "capture",
    a capture's primary conversations (capture_json.py); else None."""
    if backend() != "c" or args.format != "json" or args.to_robot is not None or not hasattr(fh, "peek"):
        return None
    if is_capture(head_of(fh)):
        return "capture"
    return "stream" if (args.protocol or "ur") == "ur" else None


def _bytes_sink(out) -> Callable[[bytes], object]:
    """Where UTF-8 lines go: stdout's bytes underneath, else (an io.StringIO put in its place) as text."""
    out.flush()
    return out.buffer.write if hasattr(out, "buffer") else lambda data: out.write(data.decode())


def _write_json_lines(fh: BinaryIO, hint, advance: Callable[[int], None], out) -> bool:
    """The C backend's JSON Lines of a raw primary/secondary stream, written as they come; True
    when one of the records held an error."""
    lines = JsonLines(hint)
    sink = _bytes_sink(out)
    while chunk := fh.read(CHUNK):
        advance(len(chunk))
        sink(lines.feed(chunk))
    sink(lines.close())
    out.flush()
    return lines.errors


def _write_capture_lines(lines: CaptureJsonLines, out) -> bool:
    """A capture's JSON Lines, written as they come; True when one of the records held an error."""
    sink = _bytes_sink(out)
    for piece in lines:
        sink(piece)
    out.flush()
    return lines.errors


def decode_command(args: argparse.Namespace) -> int:
    if args.to_robot is not None and not interface_named(args.protocol or "ur").both_directions:
        # As the C command: an interface that reads the robot's side only has no client stream to take.
        both = sorted(name for name, i in INTERFACES.items() if i.both_directions)
        print(f"urwire: --to-robot reads a client's stream, which only {', '.join(both)} decode; "
              f"{args.protocol or 'ur'} reads the robot's side only", file=sys.stderr)
        return 2
    try:
        fh, size = _open(args.file)
    except OSError as exc:
        print(f"urwire: cannot read {args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    advance = _progress(size, args.no_progress)
    render = {"json": to_json_line, "text": human_line, "tree": human_tree}[args.format]
    try:
        c_lines = _c_json_lines(fh, args)
        records = None if c_lines else _records(fh, args, advance)
    except OSError as exc:
        print(f"urwire: cannot read {args.to_robot}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    failed = False
    out = sys.stdout
    try:
        if c_lines == "stream":
            failed = _write_json_lines(fh, args.version_hint, advance, out)
        elif c_lines == "capture":
            records = CaptureJsonLines(fh, args.version_hint, ports_read(args.protocol, args.port), advance)
            failed = _write_capture_lines(records, out)
        else:
            for record in records:
                failed = failed or fails(record)
                out.write(render(record))
                out.write("\n")
        out.flush()
        say_unclaimed(getattr(records, "unclaimed", None))
    except BrokenPipeError:
        # The reader went away (| head): stop quietly, as command-line tools do.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except OSError as exc:
        print(f"urwire: cannot decode {args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except ValueError as exc:
        print(f"urwire: cannot read {input_kind(args.file) if fh is not sys.stdin.buffer else 'input'} "
              f"{args.file}: {exc}", file=sys.stderr)
        return 2
    return 1 if failed else 0


def main(argv: Optional[list[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
