"""A small RTDE server for tests, built from urwire's RTDE encoder: it answers a real client on
loopback as a controller of the given version would (protocol 1 or 2, setup replies with the
types of the variable table or NOT_FOUND, start and pause, data packages at the asked frequency)
and records every byte of both directions, for the decoder to read back afterwards.

It is test scaffolding with bounded lifetime: one client, stopped by `stop()` or after `seconds`."""
from __future__ import annotations

import math
import socket
import struct
import threading
import time
from typing import Optional

from urwire import rtde
from urwire.generated import rtde as g


def values_for(recipe: rtde.Recipe, tick: int) -> dict:
    """Believable values of each variable at a tick: joints moving on a sine, counters counting."""
    out = {}
    for name, type_name in zip(recipe.names, recipe.types):
        vt = g.VALUE_TYPES[type_name]
        if name == "actual_q" or name == "target_q":
            item = [0.1 * j + 0.5 * math.sin(tick / 100.0 + j) for j in range(vt.count)]
        elif name == "timestamp":
            item = tick * 0.002
        elif vt.kind == "float":
            item = [0.25 * j for j in range(vt.count)] if vt.count > 1 else 1.5
        elif vt.kind == "bool":
            item = tick % 2 == 0
        elif name == "robot_mode":
            item = 7
        elif name == "safety_mode":
            item = 1
        else:
            item = [j for j in range(vt.count)] if vt.count > 1 else tick % 200
        out[name] = item
    return out


class RtdeServer:
    """Listens on (host, 30004); serves one client; `robot_bytes` and `client_bytes` keep the wire."""

    def __init__(self, host: str, port: int = 30004, version=(5, 11, 1, 0), seconds: float = 20.0):
        self.version = version
        self.deadline = time.monotonic() + seconds
        self.listener = socket.create_server((host, port))
        self.listener.settimeout(0.2)
        self.robot_bytes = bytearray()
        self.client_bytes = bytearray()
        self.sent: list[dict] = []              # the values of each data package sent
        self.errors: list[str] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(5)
        self.listener.close()

    # ---- the controller's side ----

    def _run(self) -> None:
        while not self._stop.is_set() and time.monotonic() < self.deadline:
            try:
                conn, _ = self.listener.accept()
            except OSError:
                continue
            with conn:
                self._serve(conn)
            return

    def _send(self, conn, data: bytes) -> None:
        self.robot_bytes += data
        conn.sendall(data)

    def _serve(self, conn) -> None:
        conn.settimeout(0.001)
        conversation = rtde.Conversation(protocol=1)     # a controller starts in protocol 1
        protocol, recipe, frequency, streaming = 1, None, 125.0, False
        next_id, tick, next_at = 1, 0, time.monotonic()
        while not self._stop.is_set() and time.monotonic() < self.deadline:
            try:
                data = conn.recv(65536)
                if not data:
                    return
            except socket.timeout:
                data = b""
            except OSError:
                return
            self.client_bytes += data
            for message in conversation.feed(data, False) if data else []:
                reply, recipe_made = self._answer(message, protocol, next_id)
                if isinstance(message, g.RequestProtocolVersion) and message.protocol_version in g.PROTOCOL_VERSIONS:
                    protocol = message.protocol_version
                if isinstance(message, (g.SetupOutputs, g.SetupOutputsV1)) and recipe_made is not None:
                    recipe = recipe_made
                    frequency = getattr(message, "output_frequency", 125.0)
                    next_id += 1
                if isinstance(message, g.SetupInputs) and recipe_made is not None:
                    next_id += 1
                if isinstance(message, g.Start):
                    streaming = recipe is not None
                if isinstance(message, g.Pause):
                    streaming = False
                if reply is not None:
                    self._send(conn, reply)
                    conversation.feed(reply, True)      # the connection's state follows its own replies
            if streaming and time.monotonic() >= next_at:
                values = values_for(recipe, tick)
                package = (g.DataPackage(recipe.id, values) if protocol == 2 else g.DataPackageV1(values))
                self.sent.append(values)
                try:
                    self._send(conn, package.encode(recipe))
                except OSError:
                    return
                tick += 1
                next_at += 1.0 / max(frequency, 1.0)

    def _answer(self, message, protocol: int, next_id: int):
        """The reply to one client message, and the recipe a setup makes (None if refused)."""
        if isinstance(message, g.RequestProtocolVersion):
            return g.RequestProtocolVersionReply(message.protocol_version in g.PROTOCOL_VERSIONS).encode(), None
        if isinstance(message, g.GetUrcontrolVersion):
            return g.GetUrcontrolVersionReply(*self.version).encode(), None
        if isinstance(message, (g.SetupOutputs, g.SetupOutputsV1, g.SetupInputs)):
            direction = "input" if isinstance(message, g.SetupInputs) else "output"
            names = [n for n in message.variables if n]      # ur-rtde ends its list with a comma
            types = [(rtde.variable(n, direction) or _missing).type for n in names]
            refused = any(t in g.REFUSALS for t in types)
            recipe_id = 0 if refused else next_id
            if isinstance(message, g.SetupOutputsV1):
                reply = g.SetupOutputsReplyV1(types)
            elif isinstance(message, g.SetupOutputs):
                reply = g.SetupOutputsReply(recipe_id, types)
            else:
                reply = g.SetupInputsReply(recipe_id, types)
            recipe = None if refused else rtde.Recipe(
                None if isinstance(message, g.SetupOutputsV1) else recipe_id, direction + "s", names,
                types, g.VALUE_TYPES)
            return reply.encode(), recipe
        if isinstance(message, g.Start):
            return g.StartReply(True).encode(), None
        if isinstance(message, g.Pause):
            return g.PauseReply(True).encode(), None
        if isinstance(message, g.SendTextMessage):
            return None, None
        if isinstance(message, g.InputDataPackage):
            return None, None
        self.errors.append(f"unexpected {message!r}"[:200])
        return None, None


class _Missing:
    type = "NOT_FOUND"


_missing = _Missing()


def main(argv=None) -> int:
    """python tests/tools/rtde_server.py HOST SECONDS OUT: serve one client, then write OUT.robot,
    OUT.client (the wire) and OUT.json (the values sent). Prints "listening" once it listens.
    A client library that holds Python's lock while it waits (ur-rtde does) needs the server in a
    process of its own."""
    import json
    import sys
    from pathlib import Path
    host, seconds, out = (argv or sys.argv[1:])[:3]
    server = RtdeServer(host, seconds=float(seconds))
    print("listening", flush=True)
    sys.stdin.readline()                 # the test says when it is done (or closes stdin)
    server.stop()
    Path(out + ".robot").write_bytes(bytes(server.robot_bytes))
    Path(out + ".client").write_bytes(bytes(server.client_bytes))
    Path(out + ".json").write_text(json.dumps({"sent": server.sent, "errors": server.errors}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
