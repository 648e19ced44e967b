"""python-urx, the CB2-era client, reads the messages `urwire serve` sends a CB2 and a CB3 client:
each one without an exception, with the joints, the tool pose and the modes urwire reads. (urx
knows the packages of its own time only: it skips kinematics and configuration data.)"""
from __future__ import annotations

import pytest
import urwire
from urwire.live.simulated import Controller

ursecmon = pytest.importorskip("urx.ursecmon")


@pytest.mark.parametrize("version", [(1, 8, 0), (3, 15, 0)])
def test_urx_reads_the_simulated_robot(version):
    sim = Controller(version, 10)
    messages = [sim.version_message()] + [m for _ in range(120) for m in sim.step()]
    parser = ursecmon.ParserUtils()
    compared = 0
    for message in messages:
        theirs = parser.parse(message)
        ours = next(iter(urwire.decode_stream(message, version_hint=version)))
        if not isinstance(ours, urwire.RobotStateMessage):
            continue
        joints = ours.package(urwire.JointData).joints
        assert [theirs["JointData"][f"q_actual{j}"] for j in range(6)] == [x.q_actual for x in joints]
        assert [theirs["JointData"][f"jointMode{j}"] for j in range(6)] == [int(x.joint_mode) for x in joints]
        pose = ours.package(urwire.CartesianInfo)
        assert [theirs["CartesianInfo"][k] for k in ("X", "Y", "Z", "Rx", "Ry", "Rz")] == \
            [pose.x, pose.y, pose.z, pose.rx, pose.ry, pose.rz]
        assert theirs["RobotModeData"]["robotMode"] == int(ours.package(urwire.RobotModeData).robot_mode)
        assert theirs["ToolData"]["toolMode"] == int(ours.package(urwire.ToolData).tool_mode)
        compared += 1
    assert compared == 120
