"""`urwire listen`: record a live controller (or `urwire serve`) as it talks.

Connects, frames and decodes the bytes as they arrive and writes each record at once, flushed,
so `tail -f` follows it; `--raw` also keeps the exact bytes, which `urwire decode` reads back.
A dropped or refused connection is retried with a growing pause, said on stderr; each new
connection gets a new framer, since the controller starts it with a Version message.
Exit codes as for decode: 0 everything decoded, 1 some records hold errors, 2 usage or I/O error
(or nothing was ever received).
"""
from __future__ import annotations

import argparse
import csv
import io
import signal
import socket
import sys
import time
from typing import Callable, Optional

from .canonical import has_error, to_json_line
from .framer import Framer
from .human import line as human_line

BACKOFF_FIRST = 0.5
BACKOFF_MAX = 10.0
CHUNK = 1 << 16


def add_parser(sub, version_arg) -> None:
    p = sub.add_parser("listen", help="connect to a controller and record what it sends",
                       description="Connect to a controller's primary/secondary port and write one record "
                                   "per message as it arrives.")
    p.add_argument("address", metavar="HOST[:PORT]", help="controller address (default port 30001)")
    p.add_argument("--out", metavar="FILE", help="write records here (default: standard output)")
    p.add_argument("--format", choices=("jsonl", "csv", "text"), default="jsonl",
                   help="jsonl: canonical JSON Lines (default); csv: position, time, type, JSON; "
                        "text: one readable line per message")
    p.add_argument("--raw", metavar="FILE", help="also keep the exact bytes received (readable by decode)")
    p.add_argument("--count", type=int, metavar="N", help="stop after N records")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds")
    p.set_defaults(run=listen_command)


def split_address(text: str) -> tuple[str, int]:
    host, sep, port = text.rpartition(":")
    if not sep or "]" in port:          # no port, or a bare IPv6 address
        return text.strip("[]"), 30001
    return host.strip("[]"), int(port)


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


def _stop(signum, frame) -> None:
    raise _Stopped()


def listen_command(args: argparse.Namespace) -> int:
    try:
        host, port = split_address(args.address)
    except ValueError:
        print(f"urwire listen: not an address: {args.address}", file=sys.stderr)
        return 2
    try:
        out = open(args.out, "w", encoding="utf-8") if args.out else sys.stdout
        raw = open(args.raw, "wb") if args.raw else None
    except OSError as exc:
        print(f"urwire listen: cannot write {exc.filename}: {exc.strerror}", file=sys.stderr)
        return 2
    if args.format == "csv":
        render = _csv_renderer()
        out.write("position,time,type,record\n")
    else:
        render = to_json_line if args.format == "jsonl" else human_line
    deadline = time.monotonic() + args.duration if args.duration is not None else None
    signal.signal(signal.SIGTERM, _stop)
    state = {"records": 0, "failed": False, "received": 0}

    def write(records: list) -> None:
        for record in records:
            state["failed"] = state["failed"] or has_error(record)
            out.write(render(record))
            out.write("\n")
            state["records"] += 1
            if args.count is not None and state["records"] >= args.count:
                out.flush()
                raise _Stopped()
        out.flush()

    try:
        _run(host, port, deadline, write, raw, state)
    except (_Stopped, KeyboardInterrupt):
        pass
    except OSError as exc:
        print(f"urwire listen: cannot write: {exc.strerror or exc}", file=sys.stderr)
        return 2
    finally:
        if raw:
            raw.close()
        if args.out:
            out.close()
    if not state["received"]:
        return 2
    return 1 if state["failed"] else 0


def _left(deadline: Optional[float]) -> Optional[float]:
    if deadline is None:
        return None
    left = deadline - time.monotonic()
    if left <= 0:
        raise _Stopped()
    return left


def _run(host: str, port: int, deadline: Optional[float], write: Callable, raw, state: dict) -> None:
    pause = BACKOFF_FIRST
    while True:
        try:
            sock = socket.create_connection((host, port), timeout=min(_left(deadline) or 5.0, 5.0))
        except OSError as exc:
            wait = min(pause, _left(deadline) or pause)
            print(f"urwire listen: cannot connect to {host}:{port}: {exc.strerror or exc}; "
                  f"retrying in {wait:.1f} s", file=sys.stderr, flush=True)
            time.sleep(wait)
            pause = min(pause * 2, BACKOFF_MAX)
            continue
        print(f"urwire listen: connected to {host}:{port}", file=sys.stderr, flush=True)
        framer = Framer()
        try:
            with sock:
                while True:
                    sock.settimeout(min(_left(deadline) or 1.0, 1.0))
                    try:
                        chunk = sock.recv(CHUNK)
                    except socket.timeout:
                        continue
                    if not chunk:
                        break
                    pause = BACKOFF_FIRST     # the connection worked: start the backoff again
                    state["received"] += len(chunk)
                    if raw:
                        raw.write(chunk)
                        raw.flush()
                    write(framer.feed(chunk))
        except OSError as exc:
            print(f"urwire listen: connection to {host}:{port} lost: {exc}", file=sys.stderr, flush=True)
        write(framer.close())
        wait = min(pause, _left(deadline) or pause)
        print(f"urwire listen: connection closed; reconnecting in {wait:.1f} s", file=sys.stderr, flush=True)
        time.sleep(wait)
        pause = min(pause * 2, BACKOFF_MAX)
