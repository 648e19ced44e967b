"""A scripted controller on loopback for the `urwire listen` tests: it accepts one connection per
script, in order, and each script does what it likes with its socket (send, cut, stay silent).
Every wait is bounded, so a test never hangs on a peer."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Callable, Iterable, Optional

from urwire.live.simulated import Controller

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
VERSION = (5, 11, 0)


def session_bytes(states: int, version: tuple = VERSION) -> bytes:
    """What a controller sends a new client: its Version message, then `states` ticks."""
    controller = Controller(version, rate=10)
    parts = [controller.version_message()]
    for _ in range(states):
        parts.extend(controller.step())
    return b"".join(parts)


class Peer:
    """Runs the scripts, one accepted connection each, on a thread; `port` is where it listens."""

    def __init__(self, scripts: Iterable[Callable[[socket.socket], None]], accept_timeout: float = 10.0):
        self.scripts = list(scripts)
        self.accept_timeout = accept_timeout
        self.server = socket.create_server(("127.0.0.1", 0))
        self.server.settimeout(0.1)     # short waits, so that the test's end stops the thread at once
        self.port = self.server.getsockname()[1]
        self.served = 0
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._serve, daemon=True)

    def _accept(self) -> Optional[socket.socket]:
        give_up = time.monotonic() + self.accept_timeout
        while not self.done.is_set() and time.monotonic() < give_up:
            try:
                conn, _ = self.server.accept()
            except socket.timeout:
                continue
            except OSError:
                return None
            conn.settimeout(None)
            return conn
        return None

    def _serve(self) -> None:
        for script in self.scripts:
            conn = self._accept()
            if conn is None:
                return
            with conn:
                try:
                    script(conn)
                except OSError:
                    pass        # the client went away: the next script waits for it again
            self.served += 1
        self.server.close()

    def __enter__(self) -> "Peer":
        self.thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self.done.set()
        self.thread.join(timeout=5)
        self.server.close()


def listen(port: int, *options: str, timeout: float = 20) -> subprocess.CompletedProcess:
    """`urwire listen` on the peer's port, run to its end (bound its options by --duration)."""
    return subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", *options],
                          capture_output=True, text=True, env=ENV, timeout=timeout)
