"""UR's own client library (URCL) reads what `urwire serve` sends, over real TCP on loopback, for
every generation it supports (3.15 to 10.14): its stream and strict-mode parser log no warning
and no error, and every value it decodes equals urwire's reading of the same session, including
the arm's DH parameters, robot type, board, checksums and modes.

URCL is built from the checkout URCL_SOURCE names (tests/tools/urcl.py); without one these
tests are skipped.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest
import urwire
from urwire.live.robot_models import MODELS
from urwire.live.simulated import Controller

from tests.tools import urcl

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
RATE = 250
# 320 messages take in the third program run's protective stop and its safety mode messages.
COUNT = 320
CASES = [("3.15", "ur5"), ("3.15", "ur10"), ("5.4", "ur3e"), ("5.8", "ur5e"), ("5.11", "ur10e"),
         ("5.25.1", "ur16e"), ("5.26", "ur20"), ("10.14", "ur30"), ("10.14", None)]

pytestmark = pytest.mark.skipif(urcl.source_dir() is None or shutil.which("g++") is None,
                                reason="URCL_SOURCE names no checkout of Universal_Robots_Client_Library")


@pytest.fixture(scope="module")
def client() -> Path:
    return urcl.primary_client(urcl.source_dir(), ROOT / "build" / "urcl")


def version_of(text: str) -> tuple:
    return tuple(int(p) for p in (text.split(".") + ["0"])[:3])


def urwire_view(version: tuple, model: str | None) -> list:
    """What URCL prints, read by urwire from the same simulated session."""
    sim = Controller(version, RATE, model and MODELS[model])
    data = sim.opening() + b"".join(b for _ in range(COUNT) for b in sim.step())
    lines = []
    for record in list(urwire.decode_stream(data))[:COUNT]:
        if isinstance(record, urwire.RobotStateMessage):
            for p in record.packages:
                lines.extend(package_view(p))
        elif record.TYPE == "version":
            lines.append({"type": "version", "project_name": record.project_name, "major_version": record.major_version,
                          "minor_version": record.minor_version, "bugfix_version": record.bugfix_version,
                          "build_number": record.build_number})
        elif record.TYPE == "safety_mode":
            lines.append({"type": "safety_mode", "safety_mode_type": int(record.safety_mode_type)})
        elif record.TYPE == "key":
            lines.append({"type": "key", "title": record.title})
    return lines


def package_view(p) -> list:
    if isinstance(p, urwire.RobotModeData):
        return [{"type": "robot_mode_data", "timestamp": p.timestamp, "robot_mode": int(p.robot_mode),
                 "control_mode": int(p.control_mode), "is_protective_stopped": p.is_protective_stopped,
                 "target_speed_fraction": p.target_speed_fraction}]
    if isinstance(p, urwire.MasterboardData):
        return [{"type": "masterboard_data", "safety_mode": int(p.safety_mode),
                 "master_board_temperature": p.master_board_temperature}]
    if isinstance(p, urwire.KinematicsInfo):
        return [{"type": "kinematics_info", "checksum": p.checksum, "dh_theta": p.dh_theta, "dh_a": p.dh_a,
                 "dh_d": p.dh_d, "dh_alpha": p.dh_alpha, "calibration_status": p.calibration_status}]
    if isinstance(p, urwire.ConfigurationData):
        return [{"type": "configuration_data", "dh_a": p.dh_a, "dh_d": p.dh_d, "dh_alpha": p.dh_alpha,
                 "dh_theta": p.dh_theta, "masterboard_version": p.masterboard_version,
                 "controller_box_type": p.controller_box_type, "robot_type": p.robot_type,
                 "robot_sub_type": p.robot_sub_type}]
    return []


def urcl_reading(client: Path, software: str, model: str | None) -> list:
    args = [sys.executable, "-m", "urwire", "serve", "--port", "0", "--software", software, "--rate", str(RATE),
            "--duration", "30"] + (["--model", model] if model else [])
    server = subprocess.Popen(args, stderr=subprocess.PIPE, text=True, env=ENV)
    try:
        port = re.search(r":(\d+)$", server.stderr.readline().strip()).group(1)
        res = subprocess.run([str(client), "127.0.0.1", port, str(COUNT)], capture_output=True, text=True,
                             timeout=60)
    finally:
        server.send_signal(signal.SIGTERM)
        server.wait(timeout=10)
    assert res.returncode == 0, res.stdout[-2000:] + res.stderr[-2000:]
    return [json.loads(line) for line in res.stdout.splitlines()]


@pytest.mark.parametrize("software,model", CASES, ids=[f"{s}-{m or 'default'}" for s, m in CASES])
def test_urcl_reads_serve_with_no_warning_and_equal_values(client, software, model):
    got = urcl_reading(client, software, model)
    assert [line for line in got if "urcl_log" in line] == []
    assert got == urwire_view(version_of(software), model)
    # The believable robot arrived: a real arm's kinematics, a robot type, valid modes.
    kinematics = next(line for line in got if line["type"] == "kinematics_info")
    configuration = next(line for line in got if line["type"] == "configuration_data")
    arm = MODELS[model or "ur5e"]
    assert kinematics["dh_d"] == list(arm.dh_d) and configuration["dh_a"] == list(arm.dh_a)
    assert all(kinematics["checksum"]) and configuration["robot_type"] == arm.robot_type
    assert configuration["masterboard_version"] and configuration["robot_sub_type"]
    assert {line["robot_mode"] for line in got if line["type"] == "robot_mode_data"} == {7}  # RUNNING
    assert {line["safety_mode"] for line in got if line["type"] == "masterboard_data"} == {1, 3}  # NORMAL, stop
    assert [line["safety_mode_type"] for line in got if line["type"] == "safety_mode"] == [3, 1]
