"""`urwire serve`: a simulated controller on a TCP port, one session per client.

Every client gets its own simulated.Controller: the Version message first, then robot states at
the given rate. Loopback by default; SIGINT and SIGTERM close every connection and stop.
"""
from __future__ import annotations

import argparse
import asyncio
import signal
import sys
from typing import Optional

from .simulated import Controller


def add_parser(sub, version_arg) -> None:
    p = sub.add_parser("serve", help="simulate a controller of any software version on a TCP port",
                       description="Serve the primary interface of a simulated controller: its Version "
                                   "message, then robot states and program messages, to every client.")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    p.add_argument("--port", type=int, default=30001, help="TCP port; 0 picks a free one (default: 30001)")
    p.add_argument("--software", type=version_arg, default=(5, 11, 0), metavar="X.Y[.Z]",
                   help="software version to simulate, e.g. 1.8, 3.15 or 5.11 (default: 5.11)")
    p.add_argument("--rate", type=float, default=10.0, help="robot states per second (default: 10)")
    p.add_argument("--duration", type=float, metavar="S", help="stop after S seconds (default: run until stopped)")
    p.set_defaults(run=serve_command)


async def _session(writer: asyncio.StreamWriter, version: tuple, rate: float, stop: asyncio.Event) -> None:
    controller = Controller(version, rate)
    loop = asyncio.get_running_loop()
    start = loop.time()
    try:
        writer.write(controller.version_message())
        while not stop.is_set():
            writer.write(b"".join(controller.step()))
            await writer.drain()
            due = start + controller.tick / rate
            try:
                await asyncio.wait_for(stop.wait(), max(0.0, due - loop.time()))
            except asyncio.TimeoutError:
                pass
    except (ConnectionError, OSError):
        pass  # the client went away
    finally:
        writer.close()


async def serve(host: str, port: int, version: tuple, rate: float, duration: Optional[float]) -> None:
    stop = asyncio.Event()
    sessions: set = set()

    async def client(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        sessions.add(task)
        try:
            await _session(writer, version, rate, stop)
        finally:
            sessions.discard(task)

    loop = asyncio.get_running_loop()
    for signum in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(signum, stop.set)
    server = await asyncio.start_server(client, host, port)
    bound = server.sockets[0].getsockname()
    print(f"urwire serve: software {'.'.join(map(str, version))} on {bound[0]}:{bound[1]}",
          file=sys.stderr, flush=True)
    try:
        await asyncio.wait_for(stop.wait(), duration)
    except asyncio.TimeoutError:
        stop.set()
    server.close()
    if sessions:
        await asyncio.wait(set(sessions), timeout=2.0)
    await server.wait_closed()


def serve_command(args: argparse.Namespace) -> int:
    if args.rate <= 0:
        print("urwire serve: --rate must be above 0", file=sys.stderr)
        return 2
    try:
        asyncio.run(serve(args.host, args.port, args.software, args.rate, args.duration))
    except OSError as exc:
        print(f"urwire serve: cannot listen on {args.host}:{args.port}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0
