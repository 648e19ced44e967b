"""The server side of the Foxglove WebSocket protocol (github.com/foxglove/ws-protocol,
docs/spec.md), for `urwire listen --foxglove`: a live view of what listen records, on the channels
and with the schemas and messages of its MCAP file (mcap_recording.Message), so that a running
Foxglove (Open connection, Foxglove WebSocket) or any client of the protocol sees the robot move.

What a viewer needs of the protocol and no more: serverInfo on connecting, an advertise of every
channel (and of each new one as it appears), subscribe and unsubscribe, each message of a
subscribed channel as a binary messageData frame with its log time, and a status for what the
server does not do. The protocol is accepted under both its names: foxglove.websocket.v1 (the
clients of @foxglove/ws-protocol, Lichtblick) and foxglove.sdk.v1 (the same protocol as Foxglove's
SDK servers name it; the Foxglove app offers both). Foxglove's own Python server (foxglove-sdk
0.30) takes only the second, which older clients cannot reach: hence this one, on `websockets`.

The server runs on an event loop in a thread of its own. publish() is called from listen's thread
and never waits for a viewer: each client keeps at most BACKLOG messages, and one that reads slower
than the robot sends loses the oldest (a status warning says how many), as Foxglove's servers do.
"""
from __future__ import annotations

import asyncio
import json
import struct
import threading
import time
from collections import deque
from typing import Optional

from .mcap_recording import Message

SUBPROTOCOLS = ["foxglove.websocket.v1", "foxglove.sdk.v1"]
DEFAULT_PORT = 8765
BACKLOG = 1024              # messages kept per client, as Foxglove's SDK servers keep by default
DRAIN = 1.0                 # seconds close() gives the clients to receive what is queued for them
MESSAGE_DATA = struct.Struct("<BIQ")    # opcode 0x01, subscription id, log time (ns since the epoch)
_OPCODE_MESSAGE_DATA = 0x01
_WARNING, _ERROR = 1, 2                 # status levels (0 is info, which nothing here sends)


def foxglove_missing() -> Optional[str]:
    """Why the live view cannot be served here, or None when the websockets package is installed."""
    try:
        import websockets.asyncio.server  # noqa: F401
    except ImportError:
        return "--foxglove needs the websockets package (13 or later): pip install urwire[foxglove]"
    return None


def _status(level: int, text: str) -> str:
    return json.dumps({"op": "status", "level": level, "message": text})


class _Client:
    """One viewer: its subscriptions and what waits to be sent to it, the control messages
    (never dropped) before the data (at most BACKLOG, the oldest dropped)."""

    def __init__(self, connection) -> None:
        self.connection = connection
        self.subscriptions: dict[int, int] = {}     # channel id -> the client's subscription id
        self.control: deque[str] = deque()
        self.data: deque[bytes] = deque(maxlen=BACKLOG)
        self.dropped = 0
        self.waiting = asyncio.Event()

    def send_control(self, text: str) -> None:
        self.control.append(text)
        self.waiting.set()

    def send_data(self, frame: bytes) -> None:
        if len(self.data) == BACKLOG:
            self.dropped += 1
        self.data.append(frame)
        self.waiting.set()

    def idle(self) -> bool:
        return not self.control and not self.data

    async def sending(self) -> None:
        """Sends what waits, in order, for as long as the connection lasts."""
        from websockets.exceptions import ConnectionClosed
        try:
            while True:
                await self.waiting.wait()
                self.waiting.clear()
                while self.control or self.data:
                    if self.dropped:
                        self.control.append(_status(_WARNING, f"{self.dropped} messages dropped: this client "
                                                              f"reads slower than the robot sends"))
                        self.dropped = 0
                    await self.connection.send(self.control.popleft() if self.control else self.data.popleft())
        except ConnectionClosed:
            pass


class FoxgloveServer:
    """The live view: listening on host:port (port 0: one the system picks, then `port`) until close()."""

    def __init__(self, host: str, port: int, name: str) -> None:
        self.name = name
        self._channels: dict[str, dict] = {}        # topic -> its advertised channel (on the loop only)
        self._topics: dict[int, str] = {}           # channel id -> topic
        self._clients: set[_Client] = set()
        self._session = str(time.time_ns())
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name="foxglove", daemon=True)
        self._thread.start()
        try:
            self._server = self._call(self._start(host, port))
        except BaseException:
            self._stop_loop()
            raise
        self.host = host
        self.port = self._server.sockets[0].getsockname()[1]

    def _call(self, coroutine):
        return asyncio.run_coroutine_threadsafe(coroutine, self._loop).result()

    async def _start(self, host: str, port: int):
        from websockets.asyncio.server import serve
        # Loopback is the usual case: compressing would only cost time at both ends. A client that
        # does not answer the closing handshake holds listen's exit for DRAIN at most, not 10 s.
        return await serve(self._serve, host, port, subprotocols=SUBPROTOCOLS, compression=None,
                           close_timeout=DRAIN)

    def publish(self, message: Message) -> None:
        """Sends a message to every client subscribed to its channel; a new topic is advertised first."""
        self._loop.call_soon_threadsafe(self._publish, message)

    def _publish(self, message: Message) -> None:
        channel = self._channels.get(message.topic)
        if channel is None:
            channel = self._advertise(message)
        for client in self._clients:
            subscription = client.subscriptions.get(channel["id"])
            if subscription is not None:
                client.send_data(MESSAGE_DATA.pack(_OPCODE_MESSAGE_DATA, subscription, message.log_time)
                                 + message.data)

    def _advertise(self, message: Message) -> dict:
        channel = {"id": len(self._channels) + 1, "topic": message.topic, "encoding": "json",
                   "schemaName": message.schema_name, "schema": message.schema.decode(),
                   "schemaEncoding": "jsonschema"}
        self._channels[message.topic] = channel
        self._topics[channel["id"]] = message.topic
        text = json.dumps({"op": "advertise", "channels": [channel]})
        for client in self._clients:
            client.send_control(text)
        return channel

    async def _serve(self, connection) -> None:
        from websockets.exceptions import ConnectionClosed
        client = _Client(connection)
        client.send_control(json.dumps({"op": "serverInfo", "name": self.name, "capabilities": [],
                                        "supportedEncodings": [], "metadata": {}, "sessionId": self._session}))
        if self._channels:
            client.send_control(json.dumps({"op": "advertise", "channels": list(self._channels.values())}))
        self._clients.add(client)
        sender = asyncio.create_task(client.sending())
        try:
            async for text in connection:
                self._handle(client, text)
        except ConnectionClosed:    # a connection that ends badly ends this client only
            pass
        finally:
            self._clients.discard(client)
            sender.cancel()

    def _handle(self, client: _Client, text) -> None:
        """A client's request: subscribe or unsubscribe; anything else gets a status saying so."""
        try:
            request = json.loads(text) if isinstance(text, str) else None
            op = request.get("op") if isinstance(request, dict) else None
            if op is None:
                client.send_control(_status(_ERROR, "not a request: a JSON object with an op was expected"))
            elif op == "subscribe":
                for subscription in request["subscriptions"]:
                    channel, wanted = subscription["channelId"], subscription["id"]
                    if channel in self._topics:
                        client.subscriptions[channel] = wanted
                    else:
                        client.send_control(_status(_WARNING, f"no channel {channel}: subscription {wanted} ignored"))
            elif op == "unsubscribe":
                gone = set(request["subscriptionIds"])
                client.subscriptions = {c: s for c, s in client.subscriptions.items() if s not in gone}
            else:
                client.send_control(_status(_ERROR, f"not served here: {op}"))
        except (ValueError, KeyError, TypeError) as exc:
            client.send_control(_status(_ERROR, f"a malformed request: {exc!r}"))

    def close(self) -> None:
        """Gives the clients up to DRAIN seconds to receive what is queued, then closes every connection."""
        try:
            self._call(self._close())
        finally:
            self._stop_loop()

    async def _close(self) -> None:
        deadline = self._loop.time() + DRAIN
        while not all(client.idle() for client in self._clients) and self._loop.time() < deadline:
            await asyncio.sleep(0.01)
        self._server.close()
        await self._server.wait_closed()

    def _stop_loop(self) -> None:
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()
