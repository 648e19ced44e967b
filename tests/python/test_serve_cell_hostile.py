"""`urwire serve`'s promises on the cell's other ports, over real TCP on loopback: a real-time or
RTDE client that stops reading is dropped and the others keep their rate; garbage on RTDE and the
dashboard leaves the server answering the next client; a signal stops the server within 2 s with
clients on every port, whatever they do; a thousand dashboard and RTDE clients at once each get
their answers. Every process and socket is bounded in count and time."""
from __future__ import annotations

import asyncio
import os
import re
import signal
import socket
import time

from tests.python.cell_server import CellServer, read_until
from urwire import rtde
from urwire.generated import rtde as g
from urwire.generated import ur_dashboard
from urwire.realtime import RealtimeFramer
from urwire.live.serve_rtde import offers


def stalled_client(server: CellServer, interface: str) -> socket.socket:
    """A client that never reads, with a receive buffer small enough to stall the server fast."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1024)
    sock.connect((server.host, server.ports[interface]))
    return sock


def wait_for_log(server: CellServer, pattern: str, timeout: float = 15) -> re.Match:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        match = re.search(pattern, server.log.read_text())
        if match:
            return match
        time.sleep(0.05)
    raise AssertionError(f"serve never logged {pattern!r}: {server.log.read_text()!r}")


# Every output a 5.11 controller has: a few KB a package, so a stalled client fills its buffers in seconds.
EVERY_OUTPUT = [v.name for v in rtde.VARIABLES.values() if v.direction == "output" and offers(v, (5, 11, 0))]


def streaming_rtde(sock: socket.socket, frequency: float = 500.0) -> None:
    """Asks for protocol 2 and a 500 Hz recipe of every output and starts it, reading nothing back."""
    sock.sendall(rtde.request_protocol_version(2) + g.SetupOutputs(frequency, EVERY_OUTPUT).encode() + rtde.start())


def test_drops_a_realtime_and_an_rtde_client_that_stop_reading(tmp_path):
    with CellServer(tmp_path, "--software", "5.11", "--max-unsent", "16") as server:
        stalled = stalled_client(server, "realtime")
        stalled_rtde = stalled_client(server, "rtde")
        streaming_rtde(stalled_rtde)
        reader = None
        try:
            for sock in (stalled, stalled_rtde):
                port = sock.getsockname()[1]
                match = wait_for_log(server, rf"dropped [\d.]+:{port}: not reading \((\d+) KB unsent\)")
                assert int(match.group(1)) >= 16
            reader = server.connect("realtime")
            framer = RealtimeFramer((5, 11, 0))
            read_until(reader, framer.feed, lambda r: False, timeout=0.3)        # what was queued
            start = time.monotonic()
            packets = read_until(reader, framer.feed, lambda r: False, timeout=1.0)
            assert len(packets) >= 250 * (time.monotonic() - start)          # about 500 a second still
        finally:
            for sock in (reader, stalled, stalled_rtde):
                if sock is not None:
                    sock.close()
        assert server.stop() == 0


def test_garbage_on_rtde_and_the_dashboard_leaves_the_server_answering(tmp_path):
    with CellServer(tmp_path, "--software", "5.11") as server:
        for interface in ("rtde", "dashboard"):
            with server.connect(interface) as sock:
                sock.sendall(os.urandom(64 * 1024) + b"\xff" * 10000)
                time.sleep(0.2)
        with server.connect("rtde") as sock:
            conversation = rtde.Conversation(protocol=1)
            sock.sendall(rtde.request_protocol_version(2))
            replies = read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) >= 1)
            assert isinstance(replies[0], g.RequestProtocolVersionReply) and replies[0].accepted
        with server.connect("dashboard") as sock:
            conversation = ur_dashboard.conversation()
            sock.sendall(b"robotmode\n")
            replies = read_until(sock, lambda chunk: conversation.feed(chunk, True), lambda r: len(r) >= 2)
            assert [r.reply for r in replies[:2]] == ["Connected: Universal Robots Dashboard Server",
                                                      "Robotmode: RUNNING"]
        assert server.stop() == 0


def test_stops_within_2s_with_clients_on_every_port(tmp_path):
    with CellServer(tmp_path, "--software", "5.11", "--rate", "500", "--max-unsent", "1000000") as server:
        socks = [stalled_client(server, name) for name in ("primary", "realtime", "rtde", "dashboard")]
        streaming_rtde(socks[2])
        socks[3].sendall(b"play\n" * 100000)                      # replies it never reads
        half_closed = server.connect("rtde")
        streaming_rtde(half_closed)
        half_closed.shutdown(socket.SHUT_WR)
        socks.append(half_closed)
        try:
            time.sleep(1.5)
            start = time.monotonic()
            server.proc.send_signal(signal.SIGTERM)
            status = server.proc.wait(timeout=10)
            seconds = time.monotonic() - start
        finally:
            for sock in socks:
                sock.close()
    assert status == 0
    assert seconds < 2


CROWD = 1000


async def dashboard_reply(host: str, port: int) -> str:
    reader, writer = await asyncio.open_connection(host, port)
    try:
        writer.write(b"robotmode\n")
        await reader.readline()                                  # the banner
        return (await reader.readline()).decode().strip()
    finally:
        writer.close()


async def rtde_version(host: str, port: int) -> tuple:
    reader, writer = await asyncio.open_connection(host, port)
    try:
        writer.write(rtde.request_protocol_version(2) + rtde.get_controller_version())
        conversation = rtde.Conversation(protocol=1)
        records: list = []
        while len(records) < 2:
            chunk = await reader.read(65536)
            assert chunk, "serve closed the connection before its replies"
            records += conversation.feed(chunk, True)
        return records[0].accepted, (records[1].major, records[1].minor)
    finally:
        writer.close()


async def crowd(make, count: int) -> list:
    return await asyncio.wait_for(asyncio.gather(*(make() for _ in range(count))), 30)


def test_a_thousand_dashboard_and_rtde_clients_at_once_each_get_their_answers(tmp_path):
    import resource
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < CROWD + 100:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, CROWD + 100), hard))
    with CellServer(tmp_path, "--software", "5.11") as server:
        start = time.monotonic()
        replies = asyncio.run(crowd(lambda: dashboard_reply(server.host, server.ports["dashboard"]), CROWD))
        assert replies == ["Robotmode: RUNNING"] * CROWD
        versions = asyncio.run(crowd(lambda: rtde_version(server.host, server.ports["rtde"]), CROWD))
        assert versions == [(True, (5, 11))] * CROWD
        assert time.monotonic() - start < 20
        assert server.stop() == 0
