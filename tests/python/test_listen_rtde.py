"""`urwire listen --rtde NAMES --frequency HZ` over real TCP on loopback: against `urwire serve`
it negotiates protocol 2, sets up the recipe, starts it and writes each message the robot sends
(data packages at the asked frequency, with the motion's values); the raw files of both directions
decode to the same records; a robot that refuses protocol 2 gets protocol 1; a refused recipe ends
listen with exit 2; a lost connection is made again, each in raw files of its own."""
from __future__ import annotations

import json
import socket
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

from tests.python.cell_server import ENV, CellServer
from urwire import rtde
from urwire.generated import rtde as g
from urwire.live.motion import Motion
from urwire.live.robot_models import model_for


def listen(port: int, tmp: Path, *args: str, timeout: float = 60) -> tuple[subprocess.CompletedProcess, list]:
    out = tmp / "records.jsonl"
    res = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--out", str(out),
                          "--raw", str(tmp / "session.raw"), "--duration", "30", *args],
                         capture_output=True, text=True, env=ENV, timeout=timeout)
    return res, [json.loads(line) for line in out.read_text().splitlines()] if out.exists() else []


def test_listen_rtde_records_a_recipe_from_serve(tmp_path):
    with CellServer(tmp_path, "--software", "5.11") as server:
        res, records = listen(server.ports["rtde"], tmp_path, "--rtde", "timestamp,actual_q,actual_TCP_pose",
                              "--frequency", "250", "--count", "40")
        assert server.stop() == 0
    assert res.returncode == 0, res.stderr
    assert [r["type"] for r in records[:3]] == ["request_protocol_version_reply", "setup_outputs_reply",
                                                "start_reply"]
    assert records[0]["accepted"] and records[2]["accepted"]
    assert records[1]["types"] == ["DOUBLE", "VECTOR6D", "VECTOR6D"]
    data = records[3:]
    assert len(data) == 37 and {r["type"] for r in data} == {"data_package"}
    stamps = [r["timestamp"] for r in data]
    assert all(abs(b - a - 1 / 250) < 1e-9 for a, b in zip(stamps, stamps[1:]))
    motion = Motion(model_for((5, 11, 0)))
    for r in data:
        sample = motion.joints(r["timestamp"])
        assert r["actual_q"] == list(sample.q)
        assert all(abs(a - b) < 1e-12 for a, b in zip(r["actual_TCP_pose"], motion.tcp_pose(sample.q)))
    # The raw files of both directions read back into the same records of the robot's side.
    decoded = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "rtde",
                              str(tmp_path / "session.raw"), "--to-robot", str(tmp_path / "session.to_robot.raw")],
                             capture_output=True, text=True, env=ENV, timeout=60)
    assert decoded.returncode == 0, decoded.stderr
    lines = [json.loads(line) for line in decoded.stdout.splitlines()]
    assert [r["type"] for r in lines if r["direction"] == "to_robot"] == ["request_protocol_version",
                                                                          "setup_outputs", "start"]
    robot = [{k: v for k, v in r.items() if k not in ("interface", "direction", "conversation")}
             for r in lines if r["direction"] == "from_robot"]
    assert robot[:len(records)] == records


class ProtocolOnePeer:
    """A robot that speaks protocol 1 only, built from urwire's RTDE encoder: it refuses protocol 2,
    answers a setup and a start, then sends `count` data packages."""

    def __init__(self, count: int):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.count = count
        self.received: list = []
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        self.listener.settimeout(20)
        conn, _ = self.listener.accept()
        conversation = rtde.Conversation(protocol=1)
        conn.settimeout(20)
        with conn:
            recipe = None
            while True:
                data = conn.recv(65536)
                if not data:
                    return
                for message in conversation.feed(data, False):
                    self.received.append(message)
                    if isinstance(message, g.RequestProtocolVersion):
                        reply = g.RequestProtocolVersionReply(False).encode()
                    elif isinstance(message, g.SetupOutputsV1):
                        reply = g.SetupOutputsReplyV1(["DOUBLE"] * len(message.variables)).encode()
                        recipe = rtde.Recipe(None, "outputs", message.variables, ["DOUBLE"] * len(message.variables),
                                             g.VALUE_TYPES)
                    elif isinstance(message, g.Start):
                        reply = g.StartReply(True).encode()
                        for tick in range(self.count):
                            reply += g.DataPackageV1({n: tick * 0.5 for n in recipe.names}).encode(recipe)
                    else:
                        continue
                    conn.sendall(reply)

    def close(self) -> None:
        self.listener.close()
        self.thread.join(5)


def test_listen_rtde_falls_back_to_protocol_1(tmp_path):
    peer = ProtocolOnePeer(count=5)
    try:
        res, records = listen(peer.port, tmp_path, "--rtde", "timestamp,speed_scaling", "--count", "8")
    finally:
        peer.close()
    assert res.returncode == 0, res.stderr
    assert [type(m).__name__ for m in peer.received] == ["RequestProtocolVersion", "SetupOutputsV1", "Start"]
    assert peer.received[1].variables == ["timestamp", "speed_scaling"]
    assert [r["type"] for r in records] == ["request_protocol_version_reply", "setup_outputs_reply_v1",
                                            "start_reply"] + ["data_package_v1"] * 5
    assert records[0]["accepted"] is False
    assert [r["timestamp"] for r in records[3:]] == [0.0, 0.5, 1.0, 1.5, 2.0]


def test_listen_rtde_ends_on_a_refused_recipe(tmp_path):
    with CellServer(tmp_path, "--software", "3.15") as server:
        res, records = listen(server.ports["rtde"], tmp_path, "--rtde", "actual_q,safety_status_bits,no_such_name",
                              timeout=30)
        assert server.stop() == 0
    assert res.returncode == 2
    assert "refused the recipe: no_such_name NOT_FOUND" in res.stderr
    assert records[-1]["type"] == "setup_outputs_reply"


def free_port() -> int:
    with socket.create_server(("127.0.0.1", 0)) as sock:
        return sock.getsockname()[1]


def test_listen_rtde_reconnects(tmp_path):
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--rtde", "timestamp",
                             "--frequency", "50", "--out", str(tmp_path / "records.jsonl"),
                             "--raw", str(tmp_path / "session.raw"), "--duration", "12"],
                            stderr=subprocess.PIPE, text=True, env=ENV)
    try:
        for _ in range(2):
            with CellServer(tmp_path, "--software", "5.11", "--rtde-port", str(port)) as server:
                time.sleep(2.0)
                assert server.stop() == 0
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert "reconnected" in err, err
    records = [json.loads(line) for line in (tmp_path / "records.jsonl").read_text().splitlines()]
    assert [r["type"] for r in records].count("start_reply") == 2
    for raw in ("session.raw", "session.1.raw", "session.to_robot.raw", "session.1.to_robot.raw"):
        assert (tmp_path / raw).stat().st_size > 0, raw


class ResettingPeer:
    """A robot that answers the protocol request of each connection and resets it at once
    (SO_LINGER 0: an RST, not a FIN), so that listen's next request fails."""

    def __init__(self):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.connections = 0
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        self.listener.settimeout(0.2)
        while self.listener.fileno() >= 0:
            try:
                conn, _ = self.listener.accept()
            except socket.timeout:
                continue
            except OSError:
                return
            self.connections += 1
            conn.settimeout(5)
            try:
                conversation = rtde.Conversation(protocol=1)
                while not any(isinstance(m, g.RequestProtocolVersion) for m in conversation.feed(conn.recv(4096), False)):
                    pass
                conn.sendall(g.RequestProtocolVersionReply(True).encode())
            finally:
                conn.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
                conn.close()

    def close(self) -> None:
        self.listener.close()
        self.thread.join(5)


def test_listen_rtde_against_a_robot_that_resets_after_each_reply(tmp_path):
    # Every reply received is written though the request after it fails; the pause between
    # connections grows (0.5, 1, 2 s), as no data ever flowed; a raw file pair per connection.
    peer = ResettingPeer()
    try:
        res, records = listen(peer.port, tmp_path, "--rtde", "timestamp", "--duration", "4", timeout=30)
    finally:
        peer.close()
    assert 2 <= peer.connections <= 4, (peer.connections, res.stderr)
    assert res.returncode == 0, res.stderr
    assert [r["type"] for r in records] == ["request_protocol_version_reply"] * len(records)
    assert len(records) >= 2
    raws = sorted(tmp_path.glob("session*.raw"))
    assert len(raws) == 2 * len(records) and all(p.stat().st_size > 0 for p in raws)
    decoded = []
    for n in range(len(records)):
        raw = tmp_path / ("session.raw" if n == 0 else f"session.{n}.raw")
        out = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "rtde", str(raw),
                              "--to-robot", str(raw.with_name(raw.stem + ".to_robot.raw"))],
                             capture_output=True, text=True, env=ENV, timeout=60)
        decoded += [{k: v for k, v in json.loads(line).items() if k not in ("interface", "direction", "conversation")}
                    for line in out.stdout.splitlines() if '"from_robot"' in line]
    assert decoded == records
