"""`urwire listen --mcap FILE --foxglove` against `urwire serve` on loopback, watched by a client of
the Foxglove WebSocket protocol (foxglove_viewer) as a viewer watches: the live view advertises
every channel of the MCAP file recorded in the same session, with its schema, and each message a
channel sends after the viewer subscribed to it is the file's, byte for byte and with its log time
(the messages before a subscription are not sent: the protocol keeps no history)."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.python.cell_server import CellServer
from tests.python.test_live import ENV, start_server, stop
from tests.python.test_mcap import read_back
from tests.python.test_mcap_node import NODE_DIR, node

pytest.importorskip("mcap")
pytest.importorskip("websockets")
from tests.python.foxglove_viewer import Viewer  # noqa: E402  (needs websockets)
from urwire.mcap_robot import JOINTS  # noqa: E402

RECORDS = 150           # 3 s of states at serve's --rate 50: the viewer subscribes within the first
WS_PROTOCOL = NODE_DIR / "node_modules" / "@foxglove" / "ws-protocol"


def node_with(package: Path) -> str:
    """Node.js, with the npm package of tests/node that a test needs (skipped without, but in CI)."""
    found = node()
    if not package.is_dir():
        missing = f"{package.relative_to(NODE_DIR)} is not installed: npm ci --prefix tests/node"
        if os.environ.get("CI") == "true":
            pytest.fail(missing)
        pytest.skip(missing)
    return found


def start_listen(port: int, *options: str) -> tuple[subprocess.Popen, str]:
    """listen with the live view on a port the system picks, and the URL it says it serves on."""
    proc = subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--foxglove",
                             "--foxglove-port", "0", "--duration", "30", *options],
                            stderr=subprocess.PIPE, text=True, env=ENV)
    line = proc.stderr.readline()
    match = re.search(r"live view on (ws://127\.0\.0\.1:\d+) ", line)
    assert match, f"listen said: {line!r}"
    return proc, match.group(1)


def watch_a_session(tmp_path, watch) -> tuple[Path, Path]:
    """listen --mcap --foxglove recording `urwire serve`, and `watch(url)` watching it till it ends."""
    out, recording = tmp_path / "records.jsonl", tmp_path / "session.mcap"
    server, port = start_server("5.11")
    try:
        listen, url = start_listen(port, "--out", str(out), "--mcap", str(recording), "--count", str(RECORDS))
        try:
            watch(url)
        finally:
            assert listen.wait(timeout=60) == 0, listen.stderr.read()
    finally:
        assert stop(server) == 0
    assert len(out.read_text().splitlines()) == RECORDS
    return out, recording


def assert_seen_as_recorded(recording: Path, channels: list[dict], seen: list[tuple[str, int, bytes]]) -> None:
    """The channels advertised are the file's, with its schemas; on each, the messages seen (topic,
    log time, data) are the last the file holds, in order: all those since the subscription."""
    summary, messages, _ = read_back(recording)
    recorded = {channel.topic: (summary.schemas[channel.schema_id].name,
                                summary.schemas[channel.schema_id].data.decode(), channel.message_encoding)
                for channel in summary.channels.values()}
    advertised = {c["topic"]: (c["schemaName"], c["schema"], c["encoding"]) for c in channels}
    assert advertised == recorded and len(channels) == len(advertised)
    assert {c["schemaEncoding"] for c in channels} == {"jsonschema"}
    for topic in recorded:
        written = [(m.log_time, bytes(m.data)) for t, _, m in messages if t == topic]
        received = [(log_time, data) for t, log_time, data in seen if t == topic]
        assert received == written[len(written) - len(received):], topic
    conversation = json.loads(messages[0][2].data)["conversation"]
    for kind in ("joint_data", "cartesian_info", "tcp_pose", "joint_positions"):
        topic = f"/ur/{conversation}/{kind}"
        assert any(t == topic for t, _, _ in seen), f"nothing seen on {topic}"
    pose = next(json.loads(data) for t, _, data in seen if t.endswith("/tcp_pose"))
    assert pose["frame_id"] == "base" and set(pose["pose"]["orientation"]) == {"x", "y", "z", "w"}


def test_the_live_view_sends_what_the_mcap_file_holds(tmp_path):
    def watch(url: str) -> None:
        with Viewer(url) as viewer:
            viewer.read(timeout=60)                 # until listen ends and closes the connection
        watched.append(viewer)

    watched: list[Viewer] = []
    _, recording = watch_a_session(tmp_path, watch)
    (viewer,) = watched
    assert viewer.closed and viewer.ops[0] == "serverInfo" and "urwire" in viewer.server_info["name"]
    assert not viewer.statuses
    assert_seen_as_recorded(recording, list(viewer.channels.values()), viewer.messages)


def test_foxglove_own_client_sees_what_the_mcap_file_holds(tmp_path):
    """The same with FoxgloveClient of @foxglove/ws-protocol under Node.js (tests/node/watch_foxglove.mjs)."""
    node = node_with(WS_PROTOCOL)
    watched: list[subprocess.Popen] = []
    _, recording = watch_a_session(tmp_path, lambda url: watched.append(
        subprocess.Popen([node, str(NODE_DIR / "watch_foxglove.mjs"), url], cwd=NODE_DIR, text=True,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)))
    stdout, stderr = watched[0].communicate(timeout=60)
    assert watched[0].returncode == 0, stderr
    seen = json.loads(stdout)
    assert seen["subprotocol"] == "foxglove.websocket.v1" and "urwire" in seen["serverInfo"]["name"]
    assert not seen["statuses"]
    assert_seen_as_recorded(recording, seen["channels"],
                            [(m["topic"], int(m["logTime"]), m["data"].encode()) for m in seen["messages"]])


def test_the_live_view_alone_of_an_rtde_recipe(tmp_path):
    """--foxglove without --mcap (no file, no mcap package needed): an RTDE recipe's data packages,
    pose and joints, each package as listen wrote it, enveloped."""
    out = tmp_path / "records.jsonl"
    with CellServer(tmp_path, "--software", "5.11") as server:
        listen, url = start_listen(server.ports["rtde"], "--out", str(out), "--rtde", "actual_q,actual_TCP_pose",
                                   "--frequency", "50", "--count", str(RECORDS))
        try:
            with Viewer(url, subprotocol="foxglove.sdk.v1") as viewer:
                viewer.read(timeout=60)
        finally:
            assert listen.wait(timeout=60) == 0, listen.stderr.read()
        assert server.stop() == 0
    topics = {c["topic"].rsplit("/", 1)[1]: c for c in viewer.channels.values()}
    assert {"data_package", "tcp_pose", "joint_positions"} <= set(topics)
    assert topics["tcp_pose"]["schemaName"] == "foxglove.PoseInFrame"
    packages = [json.loads(data) for topic, _, data in viewer.messages if topic.endswith("/data_package")]
    written = [json.loads(line) for line in out.read_text().splitlines()]
    written = [line for line in written if line["type"] == "data_package"]
    assert packages and all(p.pop("interface") == "rtde" and p.pop("conversation") and p.pop("direction")
                            for p in packages)
    assert packages == written[len(written) - len(packages):]
    joints = [json.loads(data) for topic, _, data in viewer.messages if topic.endswith("/joint_positions")]
    assert [[j[name] for name in JOINTS] for j in joints] == [p["actual_q"] for p in packages]
    times = [t for topic, t, _ in viewer.messages if topic.endswith("/data_package")]
    assert times == sorted(times)
