"""`urwire listen`: record a live controller (or `urwire serve`) as it talks: its primary interface,
or with `--rtde NAMES` an RTDE output recipe (listen_rtde sets it up on each connection).

Connects, frames and decodes the bytes as they arrive and writes each record at once, flushed,
so `tail -f` follows it. `--raw FILE` also keeps the exact bytes, one file per connection that
received any (`FILE`, then `session.1.raw`, `session.2.raw`, ... for `session.raw`), so that each
file is one controller session that `urwire decode` reads back into exactly the records listen
wrote. `--mcap FILE` also writes them as MCAP for Foxglove, and `--foxglove` serves the same
messages live over the Foxglove WebSocket protocol (listen_views, docs/mcap.md).
A dropped, refused or silent connection is retried with a pause that doubles up to 10 s, said on
stderr, and starts again from 0.5 s only after a connection whose data flowed (a robot state, an
RTDE data package); each new connection gets a new framer, since the controller starts it with a
Version message.
A peer that sends nothing for the idle timeout (10 Hz robots send ten states a second) is
dropped; TCP keepalive also finds a dead link where the platform supports it.
Exit codes as for decode: 0 everything decoded, 1 some records hold errors, 2 usage or I/O error
(a file that cannot be written, or nothing was ever received). A write error on an output is
never taken for a lost connection.
"""
from __future__ import annotations

import argparse
import csv
import glob
import io
import re
import signal
import socket
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator, Optional

from .. import __version__
from ..arguments import finite_number, port_number, port_of
from ..canonical import fails, to_json_line
from ..cell import PRIMARY
from ..foxglove_server import DEFAULT_PORT as FOXGLOVE_PORT
from ..foxglove_server import FoxgloveServer, foxglove_missing
from ..framer import Framer
from ..human import line as human_line
from ..mcap_recording import mcap_missing
from .listen_rtde import PORT as RTDE_PORT
from .listen_rtde import RtdeRecorder
from .listen_views import Views, endpoints_of
from .serve_rtde import MAX_FREQUENCY

BACKOFF_FIRST = 0.5
BACKOFF_MAX = 10.0
CHUNK = 1 << 16
IDLE_TIMEOUT = 2.0          # 20 periods of the controller's 10 Hz state
CONNECT_TIMEOUT = 5.0
KEEPALIVE = {"TCP_KEEPIDLE": 5, "TCP_KEEPINTVL": 2, "TCP_KEEPCNT": 3}   # seconds, seconds, probes
HIGHEST_FREQUENCY = max(MAX_FREQUENCY.values())   # RTDE: what an e-Series runs; a CB3 refuses above 125


def add_parser(sub) -> None:
    p = sub.add_parser("listen", help="connect to a controller and record what it sends",
                       description="Connect to a controller's primary/secondary port and write one record "
                                   "per message as it arrives.")
    p.add_argument("address", metavar="HOST[:PORT]",
                   help="controller address (default port 30001, or 30004 with --rtde)")
    p.add_argument("--out", metavar="FILE", help="write records here (default: standard output)")
    p.add_argument("--format", choices=("jsonl", "csv", "text"), default="jsonl",
                   help="jsonl: canonical JSON Lines (default); csv: position, time, type, JSON; "
                        "text: one readable line per message")
    p.add_argument("--raw", metavar="FILE",
                   help="also keep the exact bytes received, one file per connection that received any: FILE, "
                        "then FILE with "
                        ".1, .2, ... before its extension (each readable by decode); with --rtde, what listen "
                        "sent too, in FILE with .to_robot before its extension (decode's --to-robot)")
    p.add_argument("--mcap", metavar="FILE",
                   help="also write what is recorded as one MCAP file for Foxglove (docs/mcap.md; urwire[mcap])")
    p.add_argument("--foxglove", action="store_true",
                   help="also serve what is recorded live over the Foxglove WebSocket protocol: the channels and "
                        "messages --mcap writes (docs/mcap.md, Live view; urwire[foxglove])")
    p.add_argument("--foxglove-port", type=port_number, default=FOXGLOVE_PORT, metavar="PORT",
                   help=f"with --foxglove: the port to serve on (default: {FOXGLOVE_PORT}; 0: one the system picks)")
    p.add_argument("--foxglove-host", default="127.0.0.1", metavar="HOST",
                   help="with --foxglove: the address to serve on (default: 127.0.0.1, this machine only; "
                        "0.0.0.0 for every network)")
    p.add_argument("--count", type=int, metavar="N", help="stop after N records")
    p.add_argument("--duration", type=finite_number, metavar="S", help="stop after S seconds")
    p.add_argument("--idle-timeout", type=finite_number, default=IDLE_TIMEOUT, metavar="S",
                   help=f"drop and reconnect a connection that sends nothing for S seconds "
                        f"(default: {IDLE_TIMEOUT})")
    p.add_argument("--rtde", metavar="NAMES",
                   help="record RTDE instead: set up an output recipe of these variables (comma-separated, e.g. "
                        "actual_q,actual_TCP_pose), start it and write each message the robot sends")
    p.add_argument("--frequency", type=finite_number, default=125.0, metavar="HZ",
                   help=f"with --rtde: data packages per second under protocol 2, above 0 and at most "
                        f"{HIGHEST_FREQUENCY:g} (CB3: 125) (default: 125)")
    p.set_defaults(run=listen_command)


def split_address(text: str, default_port: int = 30001) -> tuple[str, int]:
    host, sep, port = text.rpartition(":")
    if not sep or "]" in port:          # no port, or a bare IPv6 address
        return text.strip("[]"), default_port
    return host.strip("[]"), port_of(port, lowest=1)   # no robot listens on port 0


def raw_path(first: str, connection: int) -> str:
    """The raw file of the connection numbered from 0: `session.raw`, `session.1.raw`, ..."""
    if connection == 0:
        return first
    path = Path(first)
    return str(path.with_name(f"{path.stem}.{connection}{path.suffix}"))


def to_robot_path(raw: str) -> str:
    """The file of what listen sent on the connection whose received bytes are in `raw`."""
    path = Path(raw)
    return str(path.with_name(f"{path.stem}.to_robot{path.suffix}"))


def earlier_raw_files(first: str) -> list[Path]:
    """The numbered raw files a longer earlier run left next to `first`, which this run replaces
    as it replaces `first`: left in place, they would read as connections of this run."""
    path = Path(first)
    pattern = re.compile(re.escape(path.stem) + r"\.[1-9][0-9]*(\.to_robot)?" + re.escape(path.suffix))
    return [p for p in path.parent.glob(f"{glob.escape(path.stem)}.*{glob.escape(path.suffix)}")
            if pattern.fullmatch(p.name)]


def connect(host: str, port: int, timeout: float) -> socket.socket:
    """A connection with TCP keepalive on, so that a pulled cable ends in an error."""
    sock = socket.create_connection((host, port), timeout=timeout)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_KEEPALIVE, 1)
        for name, value in KEEPALIVE.items():
            if hasattr(socket, name):       # Linux names; other platforms keep their defaults
                sock.setsockopt(socket.IPPROTO_TCP, getattr(socket, name), value)
    except OSError:
        sock.close()
        raise
    return sock


def _csv_renderer() -> Callable:
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="")
    state = {"position": 0}

    def render(record) -> str:
        buf.seek(0)
        buf.truncate()
        writer.writerow([state["position"], f"{time.time():.6f}", getattr(record, "TYPE", "unknown"),
                         to_json_line(record)])
        state["position"] += 1
        return buf.getvalue()
    return render


class _Stopped(Exception):
    """The count or the duration is reached, or SIGTERM came."""


class OutputError(Exception):
    """An output file could not be written: the run ends with exit 2, the connection is not at fault."""

    def __init__(self, path: str, error: OSError):
        super().__init__(f"cannot write {path}: {error.strerror or error}")


def _stop(signum, frame) -> None:
    raise _Stopped()


class Outputs:
    """The records file (or standard output) and the raw files, each write error an OutputError."""

    def __init__(self, args: argparse.Namespace, live: Optional[FoxgloveServer] = None):
        self.out_name = args.out or "standard output"
        self.out = sys.stdout
        self.owns_out = bool(args.out)
        if args.out:
            with self.writing(args.out):
                self.out = open(args.out, "w", encoding="utf-8")
        self.raw_first: Optional[str] = args.raw
        for earlier in earlier_raw_files(args.raw) if args.raw else ():
            with self.writing(str(earlier)):
                earlier.unlink()
        self.raw = None
        self.raw_name = ""
        self.raw_files = 0                       # connections that received bytes so far
        self.unsent_kept = bytearray()           # sent on this connection before its first byte came
        self.keeps_sent = args.rtde is not None
        self.sent = None
        self.sent_name = ""
        self.count = args.count
        self.records = 0
        self.failed = False
        self.views = None
        self.views_name = args.mcap or "the live view"
        if args.mcap or live:
            with self.writing(self.views_name):
                self.views = Views("rtde" if args.rtde is not None else PRIMARY, args.mcap, live)
        if args.format == "csv":
            self.render = _csv_renderer()
            with self.writing(self.out_name):
                self.out.write("position,time,type,record\n")
        else:
            self.render = to_json_line if args.format == "jsonl" else human_line

    @contextmanager
    def writing(self, name: str) -> Iterator[None]:
        """An OSError inside is the file's fault: raised again as OutputError, naming the file."""
        try:
            yield
        except OSError as exc:
            raise OutputError(name, exc) from None

    def new_connection(self, sock: Optional[socket.socket] = None) -> None:
        """Closes the last connection's raw files. This one's are made with its first byte
        received: a connection that got none leaves no files (what listen sent on it is dropped)."""
        if self.views and sock is not None:
            self.views.conversation = endpoints_of(sock)
        self.close_raw()
        self.unsent_kept = bytearray()

    def _open_raw(self) -> None:
        self.raw_name = raw_path(self.raw_first, self.raw_files)
        self.raw_files += 1
        with self.writing(self.raw_name):
            self.raw = open(self.raw_name, "wb")
        if self.keeps_sent:
            self.sent_name = to_robot_path(self.raw_name)
            with self.writing(self.sent_name):
                self.sent = open(self.sent_name, "wb")
            self.keep_sent(bytes(self.unsent_kept))

    def keep_sent(self, data: bytes) -> None:
        if self.sent:
            with self.writing(self.sent_name):
                self.sent.write(data)
                self.sent.flush()
        elif self.keeps_sent and self.raw_first:
            self.unsent_kept += data             # written once the robot has sent a byte

    def keep_raw(self, chunk: bytes) -> None:
        if self.raw_first and not self.raw:
            self._open_raw()
        if self.raw:
            with self.writing(self.raw_name):
                self.raw.write(chunk)
                self.raw.flush()

    def write(self, records: list) -> None:
        with self.writing(self.out_name):
            for record in records:
                self.failed = self.failed or fails(record)
                if self.views:
                    with self.writing(self.views_name):
                        self.views.add(self.records, record)
                self.out.write(self.render(record))
                self.out.write("\n")
                self.records += 1
                if self.count_reached():
                    self.out.flush()
                    raise _Stopped()
            self.out.flush()

    def count_reached(self) -> bool:
        return self.count is not None and self.records >= self.count

    def close_raw(self) -> None:
        sent, self.sent = self.sent, None
        if sent:
            with self.writing(self.sent_name):
                sent.close()
        raw, self.raw = self.raw, None
        if raw:
            with self.writing(self.raw_name):
                raw.close()

    def close(self) -> None:
        """Closes every file, each in turn; the first error is raised once all are closed."""
        errors = []
        try:
            self.close_raw()
        except OutputError as exc:
            errors.append(exc)
        try:
            if self.views:
                with self.writing(self.views_name):
                    self.views.close()
        except OutputError as exc:
            errors.append(exc)
        try:
            with self.writing(self.out_name):
                if self.owns_out:
                    self.out.close()
                else:
                    self.out.flush()
        except OutputError as exc:
            errors.append(exc)
        if errors:
            raise errors[0]


class PrimaryReader:
    """The primary interface: nothing to ask, every byte framed (a new framer per connection,
    since the controller starts each with a Version message)."""

    refused: Optional[str] = None
    send_failed: Optional[OSError] = None

    def __init__(self, send: Callable[[bytes], None]):
        self.framer = Framer()
        self.streaming = False                   # a robot state came: the session worked

    def opening(self) -> None:
        pass

    def feed(self, chunk: bytes) -> list:
        records = self.framer.feed(chunk)
        self.streaming = self.streaming or any(hasattr(r, "packages") for r in records)
        return records

    def close(self) -> list:
        return self.framer.close()


class _Refused(Exception):
    """The robot refused what this listen asks (an RTDE recipe): reconnecting would not help."""


def reader_factory(args: argparse.Namespace) -> Callable:
    """What reads each connection: the primary interface's framer, or an RTDE recorder."""
    if args.rtde is None:
        return PrimaryReader
    names = [name.strip() for name in args.rtde.split(",") if name.strip()]
    return lambda send: RtdeRecorder(names, args.frequency, send)


def listen_command(args: argparse.Namespace) -> int:
    try:
        host, port = split_address(args.address, RTDE_PORT if args.rtde is not None else 30001)
    except ValueError as exc:
        print(f"urwire listen: not an address: {args.address}: {exc}", file=sys.stderr)
        return 2
    if args.idle_timeout <= 0:
        print("urwire listen: --idle-timeout must be more than 0", file=sys.stderr)
        return 2
    if args.duration is not None and args.duration < 0 or args.count is not None and args.count < 1:
        print("urwire listen: --duration must be 0 or more and --count 1 or more", file=sys.stderr)
        return 2
    if args.rtde is not None and (not args.rtde.strip(", ") or not 0 < args.frequency <= HIGHEST_FREQUENCY):
        print(f"urwire listen: --rtde needs variable names and --frequency a rate above 0 and at most "
              f"{HIGHEST_FREQUENCY:g}, as a robot runs (CB3: 125)", file=sys.stderr)
        return 2
    missing = (args.mcap and mcap_missing()) or (args.foxglove and foxglove_missing())
    if missing:
        print(f"urwire listen: {missing}", file=sys.stderr)
        return 2
    live = None
    if args.foxglove:
        try:
            live = serve_live(args, f"{host}:{port}")
        except OSError as exc:
            print(f"urwire listen: cannot serve the live view on {args.foxglove_host}:{args.foxglove_port}: "
                  f"{exc.strerror or exc}", file=sys.stderr)
            return 2
    try:
        outputs = Outputs(args, live)
    except OutputError as exc:
        if live:
            live.close()
        print(f"urwire listen: {exc}", file=sys.stderr)
        return 2
    deadline = time.monotonic() + args.duration if args.duration is not None else None
    signal.signal(signal.SIGTERM, _stop)
    link = Link(host, port, args.idle_timeout, deadline, outputs, reader_factory(args))
    error: Optional[Exception] = None
    try:
        link.run()
    except (_Stopped, KeyboardInterrupt):
        pass
    except (OutputError, _Refused) as exc:
        error = exc
    try:
        outputs.close()
    except OutputError as exc:
        error = error or exc
    if error:
        print(f"urwire listen: {error}", file=sys.stderr)
        return 2
    if not link.received:
        print(f"urwire listen: nothing was received from {host}:{port}", file=sys.stderr)
        return 2
    return 1 if outputs.failed else 0


def serve_live(args: argparse.Namespace, robot: str) -> FoxgloveServer:
    """`--foxglove`: the live view, started before the robot is asked for anything, and its address said."""
    live = FoxgloveServer(args.foxglove_host, args.foxglove_port, f"urwire {__version__} listen {robot}")
    host = f"[{live.host}]" if ":" in live.host else live.host
    print(f"urwire listen: live view on ws://{host}:{live.port} (Foxglove: Open connection, Foxglove WebSocket)",
          file=sys.stderr, flush=True)
    return live


def _left(deadline: Optional[float]) -> Optional[float]:
    if deadline is None:
        return None
    left = deadline - time.monotonic()
    if left <= 0:
        raise _Stopped()
    return left


class Link:
    """The connection to the controller, made again with a growing pause whenever it ends."""

    def __init__(self, host: str, port: int, idle_timeout: float, deadline: Optional[float], outputs: Outputs,
                 new_reader: Callable = PrimaryReader):
        self.new_reader = new_reader
        self.host, self.port = host, port
        self.idle_timeout = idle_timeout
        self.deadline = deadline
        self.outputs = outputs
        self.pause = BACKOFF_FIRST
        self.connections = 0
        self.received = 0

    def say(self, text: str) -> None:
        print(f"urwire listen: {text}", file=sys.stderr, flush=True)

    def wait(self, why: str, then: str = "reconnecting") -> None:
        wait = min(self.pause, _left(self.deadline) or self.pause)
        self.say(f"{why}; {self.outputs.records} records so far; {then} in {wait:.1f} s")
        time.sleep(wait)
        self.pause = min(self.pause * 2, BACKOFF_MAX)

    def run(self) -> None:
        where = f"{self.host}:{self.port}"
        while True:
            try:
                sock = connect(self.host, self.port, min(_left(self.deadline) or CONNECT_TIMEOUT, CONNECT_TIMEOUT))
            except OSError as exc:
                self.wait(f"cannot connect to {where}: {exc.strerror or exc}", then="retrying")
                continue
            self.connections += 1
            if self.connections == 1:
                self.say(f"connected to {where}")
            else:
                self.say(f"reconnected to {where} (connection {self.connections}); "
                         f"{self.outputs.records} records so far")
            self.outputs.new_connection(sock)
            reader = self.new_reader(lambda data, sock=sock: self.send(sock, data))
            with sock:
                try:
                    why = self.session(sock, reader)
                except (_Stopped, KeyboardInterrupt):
                    if not self.outputs.count_reached():
                        self.outputs.write(reader.close())   # the cut tail, as decode reads the raw file
                    raise
            self.outputs.write(reader.close())
            self.wait(why)

    def send(self, sock: socket.socket, data: bytes) -> None:
        sock.sendall(data)
        self.outputs.keep_sent(data)

    def session(self, sock: socket.socket, reader) -> str:
        """Records one connection until it ends; returns why it ended."""
        where = f"{self.host}:{self.port}"
        try:
            reader.opening()
        except OSError as exc:
            return f"connection to {where} lost: {exc.strerror or exc}"
        quiet_since = time.monotonic()
        while True:
            sock.settimeout(min(_left(self.deadline) or self.idle_timeout, self.idle_timeout))
            try:
                chunk = sock.recv(CHUNK)
            except socket.timeout:
                if time.monotonic() - quiet_since >= self.idle_timeout:
                    return f"no data from {where} for {self.idle_timeout:.1f} s: connection dropped"
                continue
            except OSError as exc:
                return f"connection to {where} lost: {exc.strerror or exc}"
            if not chunk:
                return f"connection to {where} lost: closed by the peer"
            quiet_since = time.monotonic()
            self.received += len(chunk)
            self.outputs.keep_raw(chunk)
            self.outputs.write(reader.feed(chunk))     # every byte decoded and written first
            if reader.streaming:
                self.pause = BACKOFF_FIRST     # data flowed: the next failure starts the backoff again
            if reader.send_failed is not None:  # a request the reader sent back failed
                return f"connection to {where} lost: {reader.send_failed.strerror or reader.send_failed}"
            if reader.refused:
                raise _Refused(reader.refused)
