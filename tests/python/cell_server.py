"""`urwire serve` in a subprocess for the live tests: every interface on a free port (or the
standard ports on an address of its own), the port of each read from its log line, and small
blocking clients that read one interface's records off a socket."""
from __future__ import annotations

import os
import random
import re
import signal
import socket
import subprocess
import sys
import shutil
import time
from pathlib import Path
from typing import Callable

from urwire import rtde
from urwire.arguments import software_version
from urwire.live.serve import FIXED, HAS, OFFSETS

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
# The words each interface's log line opens with.
LOG_NAMES = {"rtde": "RTDE", "realtime": "real-time", "dashboard": "dashboard", "interpreter": "interpreter mode",
             "gripper": "Robotiq gripper"}


def loopback_address() -> str:
    """An address of 127/8 of its own, so that a test can take the standard ports (30004, ...),
    which clients such as ur-rtde cannot be told to leave, beside other tests."""
    return f"127.{random.randrange(1, 255)}.{random.randrange(1, 255)}.{random.randrange(2, 255)}"


class CellServer:
    """`urwire serve` with its stderr in a file; `ports` maps primary, rtde, realtime, dashboard,
    interpreter (from 5.10) and gripper to where each listens."""

    def __init__(self, tmp: Path, *args: str, host: str = "127.0.0.1", port: int = 0, duration: float = 60,
                 env: dict = ENV):
        self.host = host
        software = software_version(args[args.index("--software") + 1]) if "--software" in args else (5, 11, 0)
        # The interfaces serve says a port of: those the served version has.
        self.expected = {"primary"} | {name for name in (*OFFSETS, *FIXED) if HAS.get(name, lambda _: True)(software)}
        self.log = tmp / f"serve-{random.randrange(1 << 30)}.log"
        with open(self.log, "w") as log:
            self.proc = subprocess.Popen([sys.executable, "-m", "urwire", "serve", "--host", host, "--port", str(port),
                                          "--duration", str(duration), *args], stderr=log, env=env)
        self.ports = self.wait_for_ports()

    def wait_for_ports(self, timeout: float = 15) -> dict:
        deadline = time.monotonic() + timeout
        pattern = re.compile(r"urwire serve: (.*) on [\d.]+:(\d+)$")
        while time.monotonic() < deadline:
            lines = [pattern.search(line) for line in self.log.read_text().splitlines()]
            found = {}
            for match in filter(None, lines):
                name = next((k for k, v in LOG_NAMES.items() if match.group(1) == v), "primary")
                found[name] = int(match.group(2))
            if set(found) == self.expected:
                return found
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        raise AssertionError(f"serve did not start: {self.log.read_text()}")

    def connect(self, interface: str, timeout: float = 5.0) -> socket.socket:
        return socket.create_connection((self.host, self.ports[interface]), timeout=timeout)

    def stop(self) -> int:
        self.proc.send_signal(signal.SIGTERM)
        return self.proc.wait(timeout=10)

    def __enter__(self) -> "CellServer":
        return self

    def __exit__(self, *exc) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(timeout=10)


class RtdeClient:
    """A blocking RTDE client that keeps both directions in one urwire Conversation."""

    def __init__(self, server: CellServer):
        self.sock = server.connect("rtde")
        self.conversation = rtde.Conversation(protocol=1)     # a controller starts in protocol 1
        self.pending: list = []

    def send(self, data: bytes) -> None:
        self.conversation.feed(data, False)
        self.sock.sendall(data)

    def ask(self, data: bytes, reply_type: type, timeout: float = 5.0):
        """Sends a request and returns its reply; data packages that come first are kept."""
        self.send(data)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for i, record in enumerate(self.pending):
                if isinstance(record, reply_type):
                    del self.pending[i]
                    return record
            self.pending += self.conversation.feed(self.sock.recv(65536), True)
        raise AssertionError(f"no {reply_type.__name__} within {timeout} s")

    def packages(self, count: int, timeout: float = 10.0) -> list:
        out = [r for r in self.pending if type(r).__name__.startswith("DataPackage")]
        self.pending = []
        deadline = time.monotonic() + timeout
        while len(out) < count and time.monotonic() < deadline:
            out += [r for r in self.conversation.feed(self.sock.recv(65536), True)
                    if type(r).__name__.startswith("DataPackage")]
        assert len(out) >= count, f"{len(out)} data packages of {count}"
        return out[:count]

    def close(self) -> None:
        self.sock.close()


def read_until(sock: socket.socket, feed, done, timeout: float = 5.0) -> list:
    """Records fed from the socket until done(records) or the timeout."""
    records: list = []
    deadline = time.monotonic() + timeout
    while not done(records) and time.monotonic() < deadline:
        chunk = sock.recv(65536)
        if not chunk:
            break
        records += feed(chunk)
    return records


def generated_from_edited_spec(tmp: Path, spec: str, edit: Callable[[str], str]) -> dict:
    """The environment of a `urwire serve` built from an edited copy of spec/<spec>: the copy's
    Python written by `python -m codegen` into a copy of generated/python, which PYTHONPATH takes
    in its place. Its "GENERATED" is that copy's urwire/generated folder."""
    text = (ROOT / "spec" / spec).read_text(encoding="utf-8")
    edited = edit(text)
    assert edited != text, "the edit changed nothing"
    (tmp / spec).write_text(edited, encoding="utf-8")
    subprocess.run([sys.executable, "-m", "codegen", "--spec", str(tmp / spec), "--target", "python", "--out",
                    str(tmp / "out")], cwd=ROOT, check=True, timeout=60)
    package = tmp / "python" / "urwire" / "generated"
    shutil.copytree(ROOT / "generated" / "python" / "urwire" / "generated", package)
    for written in (tmp / "out" / "python" / "urwire" / "generated").iterdir():
        shutil.copy(written, package / written.name)
    return dict(ENV, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(tmp / "python")]), GENERATED=str(package))
