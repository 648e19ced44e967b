"""The real `ur-rtde` client (SDU Robotics, PyPI) against a small RTDE server built from urwire's
encoder (tests/tools/rtde_server.py, in a process of its own), on real loopback TCP: the client
reads what the server sent, and urwire's Conversation decodes the whole exchange with no error.

The client comes from the package `ur-rtde` (PyPI);
requirements-dev.txt installs it; the test is skipped, with that reason, where it is missing."""
from __future__ import annotations

import json
import os
import random
import subprocess
import sys
import time
from pathlib import Path

import pytest

import urwire
from urwire import rtde
from urwire._runtime import StreamError
from urwire.typed_records import RawMessage

rtde_receive = pytest.importorskip("rtde_receive", reason="the ur-rtde client (pip install ur-rtde) is not installed")
ROOT = Path(__file__).resolve().parents[2]


def test_ur_rtde_receives_from_the_urwire_server(tmp_path):
    host = f"127.{random.randrange(1, 255)}.{random.randrange(1, 255)}.{random.randrange(2, 255)}"
    out = str(tmp_path / "wire")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "python"),
                                                        str(ROOT / "generated" / "python")]))
    server = subprocess.Popen([sys.executable, str(ROOT / "tests" / "tools" / "rtde_server.py"), host, "20", out],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env)
    try:
        assert server.stdout.readline().strip() == "listening"
        client = rtde_receive.RTDEReceiveInterface(host, 125.0, ["timestamp", "actual_q", "robot_mode"])
        time.sleep(0.6)                  # about 75 packages at 125 Hz
        q, stamp = client.getActualQ(), client.getTimestamp()
        client.disconnect()
    finally:
        server.communicate("done\n", timeout=30)
    report = json.loads(Path(out + ".json").read_text())
    sent = report["sent"]
    assert not report["errors"], report["errors"]
    assert len(sent) >= 20
    assert any(s["actual_q"] == q and s["timestamp"] == stamp for s in sent), (q, stamp)

    conversation = rtde.Conversation()
    records = conversation.feed(Path(out + ".client").read_bytes(), False)
    records += conversation.feed(Path(out + ".robot").read_bytes(), True) + conversation.close()
    bad = [urwire.to_json_line(r) for r in records if isinstance(r, (RawMessage, StreamError))]
    assert not bad, bad[:3]
    data = [r for r in records if type(r).__name__ == "DataPackage"]
    assert [d.values["actual_q"] for d in data] == [s["actual_q"] for s in sent]
    setup = [urwire.to_dict(r) for r in records if type(r).__name__ == "SetupOutputs"]
    assert setup and setup[0]["variables"] == ["timestamp", "actual_q", "robot_mode", ""]   # its trailing comma
    assert setup[0]["output_frequency"] == 125.0
