"""A client of the Foxglove WebSocket protocol written from its specification
(github.com/foxglove/ws-protocol, docs/spec.md), as a viewer uses it, for the tests of
`urwire listen --foxglove`: it subscribes to each channel as it is advertised and keeps what the
server sends, until the server closes the connection."""
from __future__ import annotations

import json
import struct
import time

from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

MESSAGE_DATA = 0x01                 # a binary frame's opcode: subscription id (u32), log time (u64), payload
MESSAGE_HEADER = struct.Struct("<BIQ")


class Viewer:
    """`with Viewer(url) as viewer: viewer.read(...)`, then what it saw in its attributes."""

    def __init__(self, url: str, subprotocol: str = "foxglove.websocket.v1", subscribe: bool = True):
        self._connecting = connect(url, subprotocols=[subprotocol], open_timeout=10, compression=None,
                                   max_queue=None)     # reads on while the test is busy elsewhere
        self.connection = None
        self.subscribe_all = subscribe
        self.server_info: dict = {}
        self.channels: dict[int, dict] = {}         # channel id -> as advertised
        self.subscribed: dict[int, int] = {}        # subscription id -> channel id
        self.messages: list[tuple[str, int, bytes]] = []    # topic, log time, payload
        self.statuses: list[dict] = []
        self.ops: list[str] = []                    # every text message's op, in order
        self.closed = False

    def send(self, request: dict) -> None:
        self.connection.send(json.dumps(request))

    def subscribe(self, channel_id: int) -> int:
        subscription = 100 + channel_id             # any id of the client's choosing
        self.send({"op": "subscribe", "subscriptions": [{"id": subscription, "channelId": channel_id}]})
        self.subscribed[subscription] = channel_id
        return subscription

    def settle(self) -> None:
        """Returns once the server has handled every request sent before: it answers one it does
        not serve (op "settle") with a status, in order. That status is not kept."""
        before = len(self.statuses)
        self.send({"op": "settle"})
        self.read(until=lambda viewer: len(viewer.statuses) > before)
        self.statuses.pop()

    def read(self, until=lambda viewer: False, timeout: float = 30.0) -> "Viewer":
        """Reads until `until(self)` holds or the server closes the connection; fails after `timeout`."""
        deadline = time.monotonic() + timeout
        while not self.closed and not until(self):
            try:
                frame = self.connection.recv(timeout=max(0.0, deadline - time.monotonic()))
            except ConnectionClosed:
                self.closed = True
                break
            if isinstance(frame, bytes):
                opcode, subscription, log_time = MESSAGE_HEADER.unpack_from(frame)
                assert opcode == MESSAGE_DATA and subscription in self.subscribed
                topic = self.channels[self.subscribed[subscription]]["topic"]
                self.messages.append((topic, log_time, frame[MESSAGE_HEADER.size:]))
                continue
            message = json.loads(frame)
            self.ops.append(message["op"])
            if message["op"] == "serverInfo":
                self.server_info = message
            elif message["op"] == "advertise":
                for channel in message["channels"]:
                    self.channels[channel["id"]] = channel
                    if self.subscribe_all:
                        self.subscribe(channel["id"])
            elif message["op"] == "status":
                self.statuses.append(message)
        return self

    def __enter__(self) -> "Viewer":
        self.connection = self._connecting.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        self._connecting.__exit__(*exc)
