"""UR's own client library (URCL) as RTDE and dashboard client of `urwire serve`, over real TCP on
loopback: RTDEClient negotiates, reads the controller version, sets up its output and input
recipes at the generation's highest frequency (its default), starts and reads data packages whose
joints and tool pose are the motion's at their timestamp, and sends an input; DashboardClient reads
the banner and gets the replies' texts. URCL logs no warning or error.

URCL is built from the checkout URCL_SOURCE names (tests/tools/urcl.py); without one these tests
are skipped."""
from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.python.cell_server import ROOT, CellServer, loopback_address
from tests.tools import urcl
from urwire.live.motion import Motion
from urwire.live.robot_models import model_for

COUNT = 50
pytestmark = pytest.mark.skipif(urcl.source_dir() is None or shutil.which("g++") is None,
                                reason="URCL_SOURCE names no checkout of Universal_Robots_Client_Library")


@pytest.fixture(scope="module")
def client() -> Path:
    return urcl.rtde_dashboard_client(urcl.source_dir(), ROOT / "build" / "urcl")


@pytest.mark.parametrize("software,frequency", [("3.15", 125), ("5.11", 500)])
def test_urcl_reads_rtde_and_the_dashboard_from_serve(client, tmp_path, software, frequency):
    # The dashboard client takes port 29999 only: serve listens on an address of its own.
    with CellServer(tmp_path, "--software", software, host=loopback_address(), port=30001) as server:
        res = subprocess.run([str(client), server.host, str(server.ports["rtde"]), "0", str(COUNT)],
                             capture_output=True, text=True, timeout=60)
        assert server.stop() == 0
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    lines = [json.loads(line) for line in res.stdout.splitlines()]
    assert [line for line in lines if "urcl_log" in line or "error" in line] == []
    version = tuple(int(p) for p in software.split(".")) + (0,)
    assert lines[0] == {"type": "version", "major": version[0], "minor": version[1], "bugfix": 0, "build": 108318,
                        "frequency": frequency}
    data = [line for line in lines if line["type"] == "data_package"]
    assert len(data) == COUNT
    motion = Motion(model_for(version))
    stamps = [d["timestamp"] for d in data]
    assert all(abs(b - a - 1 / frequency) < 1e-9 for a, b in zip(stamps, stamps[1:]))
    for d in data:
        assert d["actual_q"] == list(motion.joints(d["timestamp"]).q)
        assert d["actual_TCP_pose"] == pytest.approx(list(motion.tcp_pose(d["actual_q"])), abs=1e-12)
        assert (d["robot_mode"], d["runtime_state"]) == (7, 2)
    assert {"type": "speed_slider", "sent": True} in lines
    replies = [line["reply"] for line in lines if line["type"] == "dashboard"]
    assert replies == [f"URSoftware {software}.0.108318 (Nov 26 2021)", "Robotmode: RUNNING", "PLAYING demo.urp",
                       "Stopped", "STOPPED demo.urp"]
