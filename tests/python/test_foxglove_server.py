"""The live view's server (urwire.foxglove_server) alone, on loopback, with a client of the Foxglove
WebSocket protocol written from its specification (foxglove_viewer): the protocol's two names,
advertise, subscribe and unsubscribe, the status of a request it does not serve, the log time of
each message, the messages queued when it closes, and the backlog of a slow client."""
from __future__ import annotations

import json
import socket
import subprocess
import sys

import pytest

pytest.importorskip("websockets")
from websockets.exceptions import InvalidStatus  # noqa: E402

from tests.python.foxglove_viewer import Viewer  # noqa: E402
from tests.python.test_live import ENV  # noqa: E402
from urwire.foxglove_server import BACKLOG, FoxgloveServer, _Client  # noqa: E402
from urwire.mcap_recording import Message  # noqa: E402

SCHEMA = b'{"type": "object", "properties": {"n": {"type": "integer"}}}'


def message(topic: str, n: int) -> Message:
    return Message(topic, "test.N", SCHEMA, json.dumps({"n": n}).encode(), 1_700_000_000_000_000_000 + n)


@pytest.fixture
def server():
    live = FoxgloveServer("127.0.0.1", 0, "test")
    yield live
    live.close()


@pytest.mark.parametrize("subprotocol", ["foxglove.websocket.v1", "foxglove.sdk.v1"])
def test_either_name_of_the_protocol_is_served(server, subprotocol):
    server.publish(message("/a", 0))
    with Viewer(f"ws://127.0.0.1:{server.port}", subprotocol) as viewer:
        viewer.read(until=lambda v: v.channels)
        assert viewer.connection.subprotocol == subprotocol
    assert viewer.ops == ["serverInfo", "advertise"] and viewer.server_info["name"] == "test"
    (channel,) = viewer.channels.values()
    assert channel == {"id": channel["id"], "topic": "/a", "encoding": "json", "schemaName": "test.N",
                       "schema": SCHEMA.decode(), "schemaEncoding": "jsonschema"}


def test_another_protocol_is_refused(server):
    with pytest.raises(InvalidStatus):
        with Viewer(f"ws://127.0.0.1:{server.port}", "chat"):
            pass


def test_a_subscription_gets_each_message_with_its_log_time_until_it_ends(server):
    with Viewer(f"ws://127.0.0.1:{server.port}") as viewer:
        viewer.read(until=lambda v: v.ops)                      # serverInfo: the client is known
        server.publish(message("/a", 1))                        # before any subscription: not sent
        server.publish(message("/b", 1))
        viewer.read(until=lambda v: len(v.channels) == 2)
        viewer.settle()                                         # subscribed to both
        server.publish(message("/a", 2))
        server.publish(message("/b", 2))
        viewer.read(until=lambda v: len(v.messages) == 2)
        (a,) = [s for s, c in viewer.subscribed.items() if viewer.channels[c]["topic"] == "/a"]
        viewer.send({"op": "unsubscribe", "subscriptionIds": [a]})
        viewer.send({"op": "subscribe", "subscriptions": [{"id": 9, "channelId": 999}]})
        viewer.connection.send("not JSON")
        viewer.send({"op": "advertise", "channels": []})
        viewer.read(until=lambda v: len(v.statuses) == 3)
        server.publish(message("/a", 3))
        server.publish(message("/b", 3))
        viewer.read(until=lambda v: len(v.messages) == 3)
    assert [(topic, time, json.loads(data)) for topic, time, data in viewer.messages] == \
        [(topic, message(topic, n).log_time, {"n": n}) for topic, n in (("/a", 2), ("/b", 2), ("/b", 3))]
    assert [s["level"] for s in viewer.statuses] == [1, 2, 2]
    assert "999" in viewer.statuses[0]["message"] and "advertise" in viewer.statuses[2]["message"]


def test_what_is_queued_is_sent_before_the_server_closes():
    server = FoxgloveServer("127.0.0.1", 0, "test")
    with Viewer(f"ws://127.0.0.1:{server.port}") as viewer:
        server.publish(message("/a", 0))
        viewer.read(until=lambda v: v.subscribed)
        viewer.settle()
        for n in range(1, 301):
            server.publish(message("/a", n))
        server.close()
        viewer.read()
    assert viewer.closed and [json.loads(data)["n"] for _, _, data in viewer.messages][-1] == 300


def test_a_slow_client_loses_the_oldest_messages_and_is_told():
    client = _Client(connection=None)
    for n in range(BACKLOG + 3):
        client.send_data(b"%d" % n)
    assert client.dropped == 3 and client.data[0] == b"3" and len(client.data) == BACKLOG


def test_listen_says_when_the_port_is_taken():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        done = subprocess.run([sys.executable, "-m", "urwire", "listen", "127.0.0.1:9", "--foxglove",
                               "--foxglove-port", str(taken.getsockname()[1]), "--duration", "1"],
                              capture_output=True, text=True, env=ENV, timeout=60)
    assert done.returncode == 2
    assert "cannot serve the live view on 127.0.0.1:" in done.stderr and "in use" in done.stderr
