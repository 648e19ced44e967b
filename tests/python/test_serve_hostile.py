"""`urwire serve` against hostile clients, over real TCP on loopback: clients that never read,
send garbage, half-close, connect and vanish, or come a thousand at once. The server must keep
serving the others, drop whoever stops reading, and stop within 2 s of SIGINT or SIGTERM
whatever its clients do. Every process and socket is bounded in count and time."""
from __future__ import annotations

import asyncio
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
import urwire

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
CROWD = 1000


class Server:
    """`urwire serve` in a subprocess, its stderr in a file so that nothing it logs can block it."""

    def __init__(self, tmp: Path, *args: str):
        self.log = tmp / "serve.log"
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen([sys.executable, "-m", "urwire", "serve", "--port", "0",
                                          "--duration", "60", *args], stderr=log, env=ENV)
        self.port = int(self.wait_for_log(r"on 127\.0\.0\.1:(\d+)$").group(1))

    def wait_for_log(self, pattern: str, timeout: float = 10) -> re.Match:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for line in self.log.read_text().splitlines():
                match = re.search(pattern, line)
                if match:
                    return match
            assert self.proc.poll() is None, self.log.read_text()
            time.sleep(0.05)
        raise AssertionError(f"serve never logged {pattern!r}: {self.log.read_text()!r}")

    def stop(self, signum: int = signal.SIGTERM) -> tuple[int, float]:
        """Send the signal; the exit status and the seconds the server took to exit."""
        start = time.monotonic()
        self.proc.send_signal(signum)
        try:
            status = self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise AssertionError("serve still ran 10 s after the signal")
        return status, time.monotonic() - start

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


@pytest.fixture
def servers(tmp_path):
    started: list[Server] = []

    def start(*args: str) -> Server:
        started.append(Server(tmp_path, *args))
        return started[-1]

    yield start
    for server in started:
        server.close()


def stalled_client(port: int) -> socket.socket:
    """A client that never reads, with a receive buffer small enough to stall the server fast."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1024)
    sock.connect(("127.0.0.1", port))
    return sock


def states_in(sock: socket.socket, seconds: float) -> int:
    """How many robot states arrive on a reading client within `seconds`."""
    framer = urwire.Framer()
    sock.settimeout(0.2)
    count = 0
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            chunk = sock.recv(65536)
        except socket.timeout:
            continue
        if not chunk:
            break
        count += sum(isinstance(r, urwire.RobotStateMessage) for r in framer.feed(chunk))
    return count


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_stops_within_2s_while_a_client_never_reads(servers, signum):
    # The highest rate fills the kernel's buffers and the server's own within a second; the cap on
    # unsent data is set out of reach so that the stalled session is still there at the signal.
    server = servers("--rate", "500", "--max-unsent", "1000000")
    with stalled_client(server.port), stalled_client(server.port):
        time.sleep(2)
        status, seconds = server.stop(signum)
    assert status == 0  # a signal is a clean stop
    assert seconds < 2


def test_stops_within_2s_whatever_the_clients_do(servers):
    server = servers("--rate", "500")
    socks = [stalled_client(server.port) for _ in range(3)]
    half_closed = socket.create_connection(("127.0.0.1", server.port))
    half_closed.shutdown(socket.SHUT_WR)
    talker = socket.create_connection(("127.0.0.1", server.port))
    talker.sendall(os.urandom(4096))
    socks += [half_closed, talker]
    try:
        time.sleep(1)
        status, seconds = server.stop()
    finally:
        for sock in socks:
            sock.close()
    assert status == 0
    assert seconds < 2


def test_drops_a_client_that_stops_reading_and_keeps_the_others_rate(servers):
    server = servers("--rate", "500", "--max-unsent", "16")
    reader = socket.create_connection(("127.0.0.1", server.port))
    stalled = stalled_client(server.port)
    try:
        port = stalled.getsockname()[1]
        match = server.wait_for_log(rf"dropped 127\.0\.0\.1:{port}: not reading \((\d+) KB unsent\)")
        assert int(match.group(1)) >= 16
        assert states_in(reader, 1.0) >= 250  # the reader still gets (about) its 500 states a second
        assert server.proc.poll() is None
    finally:
        reader.close()
        stalled.close()
    assert server.stop()[0] == 0


def test_garbage_half_close_and_vanishing_clients_leave_the_others_served(servers):
    server = servers("--rate", "10")
    for _ in range(50):  # connect and vanish, some with a reset
        sock = socket.create_connection(("127.0.0.1", server.port))
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
        sock.close()
    talker = socket.create_connection(("127.0.0.1", server.port))
    talker.sendall(os.urandom(1 << 20))  # the server reads and discards what clients send
    half_closed = socket.create_connection(("127.0.0.1", server.port))
    half_closed.shutdown(socket.SHUT_WR)
    try:
        assert states_in(half_closed, 1.0) >= 8  # a half-closed client still gets 10 Hz
        assert states_in(talker, 1.0) >= 8
    finally:
        talker.close()
        half_closed.close()
    assert server.stop()[0] == 0


def raise_open_file_limit(need: int) -> None:
    import resource
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < need:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, need), hard))


async def version_of_one_client(port: int) -> tuple:
    reader, writer = await asyncio.open_connection("127.0.0.1", port)
    try:
        framer = urwire.Framer()
        while True:
            chunk = await reader.read(65536)
            assert chunk, "serve closed the connection before its Version message"
            for record in framer.feed(chunk):
                if isinstance(record, urwire.VersionMessage):
                    return (record.major_version, record.minor_version)
    finally:
        writer.close()


async def crowd(port: int, count: int) -> list:
    return await asyncio.wait_for(asyncio.gather(*(version_of_one_client(port) for _ in range(count))), 20)


def test_a_thousand_clients_at_once_each_get_the_version_message(servers):
    raise_open_file_limit(CROWD + 100)
    server = servers("--software", "3.15")
    start = time.monotonic()
    versions = asyncio.run(crowd(server.port, CROWD))
    assert versions == [(3, 15)] * CROWD
    assert time.monotonic() - start < 10  # no client waited out a SYN retry (1 s, then 3 s, ...)
    status, seconds = server.stop()
    assert status == 0 and seconds < 2
