"""The real `ur-rtde` client (SDU Robotics, PyPI) against `urwire serve`, on real loopback TCP:
RTDEReceiveInterface reads the served robot's motion (its joints and tool pose equal
urwire.live.motion.Motion's at the package's timestamp), and RTDEIOInterface's inputs (the speed
slider, a standard digital output) change what the robot reports.

ur-rtde connects to the standard ports only, so `serve` listens on an address of 127/8 of its own.
The client comes from the package `ur-rtde` (PyPI); requirements-dev.txt installs it; the test is
skipped, with that reason, where it is missing."""
from __future__ import annotations

import time

import pytest

from tests.python.cell_server import CellServer, loopback_address
from urwire.live.motion import Motion
from urwire.live.robot_models import model_for

rtde_receive = pytest.importorskip("rtde_receive", reason="the ur-rtde client (pip install ur-rtde) is not installed")
rtde_io = pytest.importorskip("rtde_io", reason="the ur-rtde client (pip install ur-rtde) is not installed")


@pytest.mark.parametrize("software", ["3.15", "5.11"])
def test_ur_rtde_receives_the_motion_from_urwire_serve(tmp_path, software):
    with CellServer(tmp_path, "--software", software, host=loopback_address(), port=30001) as server:
        client = rtde_receive.RTDEReceiveInterface(server.host, -1.0, ["timestamp", "actual_q", "actual_TCP_pose",
                                                                       "robot_mode", "safety_mode", "runtime_state"])
        time.sleep(0.5)
        readings = []
        for _ in range(1000):
            if len(readings) == 5:
                break
            # The client takes each data package in a thread of its own: a reading is one package's
            # only when the timestamp is the same before and after the values are read.
            stamp, q, pose = client.getTimestamp(), client.getActualQ(), client.getActualTCPPose()
            if client.getTimestamp() == stamp:
                readings.append((stamp, q, pose))
                time.sleep(0.05)
        modes = client.getRobotMode(), client.getSafetyMode(), client.getRuntimeState()
        client.disconnect()
        assert server.stop() == 0
    motion = Motion(model_for(tuple(int(p) for p in software.split(".")) + (0,)))
    for stamp, q, pose in readings:
        assert stamp > 0
        assert q == list(motion.joints(stamp).q)
        assert pose == pytest.approx(list(motion.tcp_pose(q)), abs=1e-12)
    assert len({r[0] for r in readings}) > 1, "the timestamp did not move"
    assert modes == (7, 1, 2)                    # RUNNING, NORMAL, playing


def test_ur_rtde_io_inputs_change_what_the_robot_reports(tmp_path):
    with CellServer(tmp_path, "--software", "5.11", host=loopback_address(), port=30001) as server:
        receive = rtde_receive.RTDEReceiveInterface(server.host)
        io = rtde_io.RTDEIOInterface(server.host)
        assert receive.getTargetSpeedFraction() == 1.0 and not receive.getDigitalOutState(2)
        assert io.setSpeedSlider(0.3)
        assert io.setStandardDigitalOut(2, True)
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and not receive.getDigitalOutState(2):
            time.sleep(0.05)
        fraction, bits, scaling = (receive.getTargetSpeedFraction(), receive.getActualDigitalOutputBits(),
                                   receive.getSpeedScaling())
        io.disconnect()
        receive.disconnect()
        assert server.stop() == 0
    assert (fraction, bits, scaling) == (0.3, 0b100, 0.3)
