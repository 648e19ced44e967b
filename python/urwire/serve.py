"""`urwire serve`: a simulated controller on a TCP port, one session per client.

Every client gets its own simulated.Controller: the Version message first (and the hardware info
message, from 5.26 and 10.13), then robot states at the given rate. The arm is --model's
(default: the generation's usual one), and every client sees the same motion at the same time:
the motion's clock starts with the server. Loopback by default. SIGINT and SIGTERM abort every
connection and stop within a second or two, whatever the clients do (exit status 0). A client
that stops reading is dropped once its unsent data passes --max-unsent, so it costs bounded
memory and never holds the others back. Whatever a client sends is read and thrown away.
"""
from __future__ import annotations

import argparse
import asyncio
import signal
import sys
from typing import Optional

from .robot_models import MODELS, RobotModel, model_for
from .simulated import Controller

# Connections the kernel queues before `accept`: asyncio's default of 100 turns away a crowd.
BACKLOG = 4096
DEFAULT_MAX_UNSENT_KB = 256
# How long a stop waits for the aborted sessions to finish before giving up on them.
STOP_GRACE_SECONDS = 1.0


def add_parser(sub, version_arg) -> None:
    p = sub.add_parser("serve", help="simulate a controller of any software version on a TCP port",
                       description="Serve the primary interface of a simulated controller: its Version "
                                   "message, then robot states and program messages, to every client.")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    p.add_argument("--port", type=int, default=30001, help="TCP port; 0 picks a free one (default: 30001)")
    p.add_argument("--software", type=version_arg, default=(5, 11, 0), metavar="X.Y[.Z]",
                   help="software version to simulate, e.g. 1.8, 3.15 or 5.11 (default: 5.11)")
    p.add_argument("--model", type=str.lower, choices=list(MODELS), metavar="MODEL",
                   help="the arm: ur3 (CB3), ur5, ur10 (CB2, CB3), ur3e, ur5e, ur10e, ur16e, ur20, ur30 (e-Series, "
                        "PolyScope X) (default: ur5 on CB2 and CB3, ur5e on e-Series and PolyScope X)")
    p.add_argument("--rate", type=float, default=10.0, help="robot states per second (default: 10)")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds (default: run until stopped)")
    p.add_argument("--max-unsent", type=int, default=DEFAULT_MAX_UNSENT_KB, metavar="KB",
                   help="drop a client once this much data waits unsent for it "
                        f"(default: {DEFAULT_MAX_UNSENT_KB})")
    p.set_defaults(run=serve_command)


def raise_open_file_limit() -> None:
    """Every client is a file descriptor: take the hard limit so a crowd of clients fits."""
    try:
        import resource
    except ImportError:  # not on this platform
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft != hard:
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
        except (ValueError, OSError):
            pass  # keep the soft limit we were given


def log(text: str) -> None:
    print(f"urwire serve: {text}", file=sys.stderr, flush=True)


class Session(asyncio.Protocol):
    """One client: writes without ever waiting on the client, so no session can block a stop."""

    def __init__(self, version: tuple, rate: float, max_unsent: int, sessions: set, model: RobotModel,
                 clock_start: float):
        self.controller = Controller(version, rate, model, start=asyncio.get_running_loop().time() - clock_start)
        self.rate = rate
        self.max_unsent = max_unsent
        self.sessions = sessions
        self.transport: Optional[asyncio.Transport] = None
        self.task: Optional[asyncio.Task] = None

    def connection_made(self, transport) -> None:
        self.transport = transport
        self.sessions.add(self)
        self.task = asyncio.get_running_loop().create_task(self.run())

    def data_received(self, data: bytes) -> None:
        pass  # a controller's primary interface ignores what the client sends here

    def eof_received(self) -> bool:
        return True  # a half-closed client still reads: keep sending

    def connection_lost(self, exc) -> None:
        self.sessions.discard(self)
        if self.task is not None:
            self.task.cancel()

    def send(self, data: bytes) -> bool:
        """Write, or drop the client and return False when it has stopped reading."""
        self.transport.write(data)
        unsent = self.transport.get_write_buffer_size()
        if unsent <= self.max_unsent:
            return True
        peer = self.transport.get_extra_info("peername") or ("?", 0)
        log(f"dropped {peer[0]}:{peer[1]}: not reading ({unsent // 1024} KB unsent)")
        self.transport.abort()
        return False

    async def run(self) -> None:
        loop = asyncio.get_running_loop()
        start = loop.time()
        if not self.send(self.controller.opening()):
            return
        while not self.transport.is_closing():
            if not self.send(b"".join(self.controller.step())):
                return
            due = start + self.controller.tick / self.rate
            await asyncio.sleep(max(0.0, due - loop.time()))

    def abort(self) -> None:
        self.transport.abort()


async def serve(host: str, port: int, version: tuple, rate: float, duration: Optional[float],
                max_unsent_kb: int = DEFAULT_MAX_UNSENT_KB, model: Optional[RobotModel] = None) -> None:
    stop = asyncio.Event()
    sessions: set = set()
    loop = asyncio.get_running_loop()
    model = model or model_for(version)
    clock_start = loop.time()
    for signum in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(signum, stop.set)
    server = await loop.create_server(
        lambda: Session(version, rate, max_unsent_kb * 1024, sessions, model, clock_start), host, port, backlog=BACKLOG)
    bound = server.sockets[0].getsockname()
    log(f"{model.name}, software {'.'.join(map(str, version))} on {bound[0]}:{bound[1]}")
    try:
        await asyncio.wait_for(stop.wait(), duration)
    except asyncio.TimeoutError:
        pass
    server.close()
    # Abort rather than close: a closing transport waits for its unsent data, which a client
    # that never reads never takes (and Server.wait_closed waits for every connection from 3.12).
    tasks = [s.task for s in sessions if s.task is not None]
    for session in list(sessions):
        session.abort()
    if tasks:
        await asyncio.wait(tasks, timeout=STOP_GRACE_SECONDS)
    try:
        await asyncio.wait_for(server.wait_closed(), STOP_GRACE_SECONDS)
    except asyncio.TimeoutError:
        pass


def serve_command(args: argparse.Namespace) -> int:
    if args.rate <= 0:
        print("urwire serve: --rate must be above 0", file=sys.stderr)
        return 2
    if args.max_unsent <= 0:
        print("urwire serve: --max-unsent must be above 0", file=sys.stderr)
        return 2
    try:
        model = model_for(args.software, args.model)
    except ValueError as exc:
        print(f"urwire serve: --model: {exc}", file=sys.stderr)
        return 2
    raise_open_file_limit()
    try:
        asyncio.run(serve(args.host, args.port, args.software, args.rate, args.duration, args.max_unsent, model))
    except OSError as exc:
        print(f"urwire serve: cannot listen on {args.host}:{args.port}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
