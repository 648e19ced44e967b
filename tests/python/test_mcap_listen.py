"""`urwire listen --mcap FILE` against `urwire serve` on loopback: the MCAP file holds what listen
wrote as JSON Lines, record for record (a robot state's sub-packages each on their own channel),
on the connection's conversation, with the robot's pose, joints and metadata (docs/mcap.md); and
Foxglove's TypeScript reader reads it as Python's does (test_mcap_node)."""
from __future__ import annotations

import json
import subprocess
import sys
import time

import pytest

from tests.python.test_live import ENV, start_server, stop
from tests.python.test_mcap import read_back
from tests.python.test_mcap_node import assert_both_read_alike

pytest.importorskip("mcap")
RECORDS = 20


def test_listen_writes_what_it_records_as_mcap(tmp_path):
    out, recording = tmp_path / "records.jsonl", tmp_path / "session.mcap"
    server, port = start_server("5.11")
    began = time.time_ns()
    try:
        done = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--out", str(out),
                               "--mcap", str(recording), "--count", str(RECORDS), "--duration", "20"],
                              capture_output=True, text=True, env=ENV, timeout=60)
    finally:
        assert stop(server) == 0
    ended = time.time_ns()
    assert done.returncode == 0, done.stderr
    lines = [json.loads(line) for line in out.read_text().splitlines()]
    assert len(lines) == RECORDS
    expected = [part for line in lines for part in line.get("packages") or [line]]

    summary, messages, metadata = read_back(recording)
    records = [(topic, json.loads(m.data), m.log_time) for topic, _, m in messages
               if not topic.endswith(("/tcp_pose", "/joint_positions"))]
    conversation = records[0][1]["conversation"]
    assert conversation.startswith(f"127.0.0.1:{port}-127.0.0.1:")
    envelope = {"interface": "ur", "direction": "from_robot", "conversation": conversation}
    assert [record for _, record, _ in records] == [{**envelope, **part} for part in expected]
    assert [topic for topic, _, _ in records] == [f"/ur/{conversation}/{part['type']}" for part in expected]
    times = [t for _, _, t in records]
    assert times == sorted(times) and began <= times[0] and times[-1] <= ended
    states = sum(1 for line in lines if "packages" in line)
    poses = [m for topic, _, m in messages if topic == f"/ur/{conversation}/tcp_pose"]
    joints = [m for topic, _, m in messages if topic == f"/ur/{conversation}/joint_positions"]
    assert len(poses) == len(joints) == states > 0
    assert summary.statistics.message_count == len(messages)
    (name, robot), = metadata
    assert name == "robot" and robot["address"] == "127.0.0.1" and robot["software_version"].startswith("5.11.")


def test_listen_mcap_as_foxglove_reads_it(tmp_path):
    server, port = start_server("5.11")
    try:
        done = subprocess.run([sys.executable, "-m", "urwire", "listen", f"127.0.0.1:{port}", "--out", "/dev/null",
                               "--mcap", str(tmp_path / "session.mcap"), "--count", "5", "--duration", "20"],
                              capture_output=True, text=True, env=ENV, timeout=60)
    finally:
        assert stop(server) == 0
    assert done.returncode == 0, done.stderr
    assert assert_both_read_alike(tmp_path / "session.mcap")["messages"]
