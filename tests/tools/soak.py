"""Soak `urwire serve` and `urwire listen` on loopback for minutes (`make soak`, not `make test`).

`serve` feeds CLIENTS clients that count robot states, and `listen` records through a proxy that
drops its connections every DROP_SECONDS, so listen keeps reconnecting. Every REPORT_SECONDS the
driver prints each process's resident memory (VmRSS) and peak (VmHWM), then a summary: memory at
the start against the end, states per second per client, and the records listen wrote.

    PYTHONPATH=python:generated/python python3 tests/tools/soak.py --seconds 60 --clients 500
"""
from __future__ import annotations

import argparse
import asyncio
import os
import re
import resource
import signal
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
HEADER = struct.Struct(">iB")  # every message: its length (header included), then its type
ROBOT_STATE = 16


def memory_kb(pid: int) -> tuple[int, int]:
    """A process's resident memory now and its peak so far, in KiB (Linux /proc)."""
    fields = dict(line.split(":", 1) for line in Path(f"/proc/{pid}/status").read_text().splitlines())
    return int(fields["VmRSS"].split()[0]), int(fields["VmHWM"].split()[0])


class StateCounter:
    """Counts robot states by their headers alone: decoding 500 streams would measure the driver."""

    def __init__(self):
        self.buffer = b""
        self.states = 0

    def feed(self, chunk: bytes) -> None:
        data = self.buffer + chunk
        at = 0
        while len(data) - at >= HEADER.size:
            length, kind = HEADER.unpack_from(data, at)
            if length < HEADER.size or len(data) - at < length:
                break
            self.states += kind == ROBOT_STATE
            at += length
        self.buffer = data[at:]


async def client(port: int, counter: StateCounter, stop: asyncio.Event) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        while not stop.is_set():
            chunk = await reader.read(65536)
            if not chunk:
                return
            counter.feed(chunk)
    finally:
        writer.close()


class DroppingProxy:
    """Forwards loopback connections to `target`, and cuts every one of them every `period` s."""

    def __init__(self, target: int, period: float):
        self.target = target
        self.period = period
        self.writers: set = set()
        self.drops = 0

    async def pipe(self, reader, writer) -> None:
        try:
            while chunk := await reader.read(65536):
                writer.write(chunk)
                await writer.drain()
        except (ConnectionError, OSError):
            pass
        finally:
            writer.close()

    async def handle(self, reader, writer) -> None:
        try:
            up_reader, up_writer = await asyncio.open_connection("127.0.0.1", self.target)
        except OSError:
            writer.close()
            return
        self.writers.update((writer, up_writer))
        try:
            await asyncio.gather(self.pipe(reader, up_writer), self.pipe(up_reader, writer))
        finally:
            self.writers.difference_update((writer, up_writer))

    def cut(self) -> None:
        for writer in list(self.writers):
            writer.transport.abort()

    async def cut_now_and_then(self) -> None:
        while True:
            await asyncio.sleep(self.period)
            self.drops += bool(self.writers)
            self.cut()


async def soak(args: argparse.Namespace, serve_port: int, pids: dict, out: Path) -> dict:
    proxy = DroppingProxy(serve_port, args.drop_seconds)
    proxy_server = await asyncio.start_server(proxy.handle, "127.0.0.1", 0)
    proxy_port = proxy_server.sockets[0].getsockname()[1]
    cutter = asyncio.ensure_future(proxy.cut_now_and_then())
    listen = subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{proxy_port}", "--out", str(out)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
    pids["listen"] = listen.pid
    stop = asyncio.Event()
    counters = [StateCounter() for _ in range(args.clients)]
    clients = [asyncio.ensure_future(client(serve_port, c, stop)) for c in counters]
    samples = []
    loop = asyncio.get_running_loop()
    start = loop.time()
    states_at_start = None
    try:
        while (elapsed := loop.time() - start) < args.seconds:
            await asyncio.sleep(min(args.report_seconds, args.seconds - elapsed))
            sample = {name: memory_kb(pid) for name, pid in pids.items()}
            states = sum(c.states for c in counters)
            if states_at_start is None:
                states_at_start = (loop.time(), states)
            samples.append(sample)
            memory = ", ".join(f"{name} {rss // 1024} MiB (peak {peak // 1024})" for name, (rss, peak) in sample.items())
            print(f"soak {loop.time() - start:6.0f} s: {memory}; {states} states; "
                  f"{sum(1 for c in clients if not c.done())} clients connected; proxy drops {proxy.drops}",
                  flush=True)
        end = loop.time(), sum(c.states for c in counters)
    finally:
        stop.set()
        cutter.cancel()
        listen.send_signal(signal.SIGTERM)
        try:
            listen.wait(timeout=10)
        except subprocess.TimeoutExpired:
            listen.kill()
        for task in clients:
            task.cancel()
        await asyncio.gather(*clients, return_exceptions=True)
        proxy_server.close()
        proxy.cut()
        await asyncio.sleep(0.1)  # the proxy's sessions end on their own
    # The rate is measured from the first sample, after every client has connected.
    seconds = end[0] - states_at_start[0]
    return {"samples": samples, "rate": (end[1] - states_at_start[1]) / seconds / args.clients if seconds else 0.0,
            "drops": proxy.drops}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=float(os.environ.get("SOAK_SECONDS", 300)))
    parser.add_argument("--clients", type=int, default=500)
    parser.add_argument("--rate", type=float, default=10.0, help="robot states per second that serve sends")
    parser.add_argument("--drop-seconds", type=float, default=5.0, help="how often the proxy cuts listen off")
    parser.add_argument("--report-seconds", type=float, default=10.0)
    args = parser.parse_args()

    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # the clients are file descriptors
    with tempfile.TemporaryDirectory() as tmp:
        log, out = Path(tmp) / "serve.log", Path(tmp) / "listen.jsonl"
        with open(log, "w") as err:
            serve = subprocess.Popen([sys.executable, "-m", "urwire", "serve", "--port", "0", "--rate", str(args.rate)],
                                     stderr=err, env=ENV)
        try:
            deadline = time.monotonic() + 10
            while not (match := re.search(r":(\d+)$", log.read_text().split("\n")[0])):
                if time.monotonic() > deadline or serve.poll() is not None:
                    print(f"soak: serve did not start: {log.read_text()}", file=sys.stderr)
                    return 1
                time.sleep(0.05)
            result = asyncio.run(soak(args, int(match.group(1)), {"serve": serve.pid}, out))
        finally:
            serve.send_signal(signal.SIGTERM)
            serve_status = serve.wait(timeout=10)
        records = sum(1 for _ in out.open()) if out.exists() else 0
        dropped_clients = log.read_text().count("dropped ")

    first, last = result["samples"][0], result["samples"][-1]
    print(f"soak: {args.seconds:.0f} s, {args.clients} clients at {args.rate:g} Hz, proxy cut listen off "
          f"{result['drops']} times")
    for name in first:
        print(f"soak: {name} memory: {first[name][0] // 1024} MiB at the first sample, {last[name][0] // 1024} MiB "
              f"at the end (peak {last[name][1] // 1024} MiB)")
    print(f"soak: {result['rate']:.2f} states/s per client; listen wrote {records} records "
          f"({records / args.seconds:.1f}/s); serve dropped {dropped_clients} clients and exited {serve_status}")
    return 0 if serve_status == 0 and dropped_clients == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
