"""The robot behind `urwire serve` is a believable one: the chosen arm's published DH parameters,
its robot type, a controller board of its generation, nonzero kinematics checksums, valid modes
of each version's tables, and a tool pose that is the forward kinematics of its joints."""
from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import pytest
import urwire
from urwire.generated import enums as e
from urwire.live.motion import Motion
from urwire.live.robot_models import MODELS, model_for
from urwire.live.simulated import Controller

ROOT = Path(__file__).resolve().parents[2]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
HALF_PI = math.pi / 2

# From UR's article "DH Parameters for calculations of kinematics and dynamics": (a, d) per joint.
PUBLISHED = {
    "ur5": ([0, -0.425, -0.39225, 0, 0, 0], [0.089159, 0, 0, 0.10915, 0.09465, 0.0823]),
    "ur10": ([0, -0.612, -0.5723, 0, 0, 0], [0.1273, 0, 0, 0.163941, 0.1157, 0.0922]),
    "ur3": ([0, -0.24365, -0.21325, 0, 0, 0], [0.1519, 0, 0, 0.11235, 0.08535, 0.0819]),
    "ur5e": ([0, -0.425, -0.3922, 0, 0, 0], [0.1625, 0, 0, 0.1333, 0.0997, 0.0996]),
    "ur16e": ([0, -0.4784, -0.36, 0, 0, 0], [0.1807, 0, 0, 0.17415, 0.11985, 0.11655]),
    "ur30": ([0, -0.637, -0.5037, 0, 0, 0], [0.2363, 0, 0, 0.201, 0.1593, 0.1543]),
}
ALPHA = [HALF_PI, 0, 0, HALF_PI, -HALF_PI, 0]
# Robot type codes (URCL datatypes.h): UR5 1, UR10 2, UR3 3, UR16 4, UR30 8.
ROBOT_TYPE = {"ur5": 1, "ur10": 2, "ur3": 3, "ur5e": 1, "ur16e": 4, "ur30": 8}
CASES = [((1, 8, 0), "ur5"), ((1, 8, 0), "ur10"), ((3, 15, 0), "ur3"), ((3, 15, 0), "ur5"), ((5, 11, 0), "ur5e"),
         ((5, 26, 0), "ur16e"), ((10, 14, 0), "ur30"), ((10, 14, 0), "ur5e")]


def session(version, model=None, ticks=120, start=0.0):
    sim = Controller(version, 10, model and MODELS[model], start=start)
    data = sim.opening() + b"".join(b for _ in range(ticks) for b in sim.step())
    records = list(urwire.decode_stream(data))
    assert not any(urwire.canonical.has_error(r) for r in records)
    return [r for r in records if isinstance(r, urwire.RobotStateMessage)]


@pytest.mark.parametrize("version,model", CASES, ids=[f"{'.'.join(map(str, v[:2]))}-{m}" for v, m in CASES])
def test_the_arm_is_the_chosen_model(version, model):
    first = session(version, model, ticks=1)[0]
    a, d = PUBLISHED[model]
    kinematics, configuration = first.package(urwire.KinematicsInfo), first.package(urwire.ConfigurationData)
    for dh in (kinematics, configuration):
        assert dh.dh_a == pytest.approx(a, abs=1e-12) and dh.dh_d == pytest.approx(d, abs=1e-12)
        assert dh.dh_alpha == pytest.approx(ALPHA, abs=1e-12) and dh.dh_theta == [0.0] * 6
    assert all(kinematics.checksum) and len(set(kinematics.checksum)) == 6
    assert kinematics.calibration_status == 2
    assert configuration.robot_type == ROBOT_TYPE[model]
    # The board of the generation: CB2 5/2/1 (a real 1.8 UR5), e-Series 6/4/3 (URSim 5.8's UR5e).
    board = {1: (5, 2, 1), 3: (5, 3, 2), 5: (6, 4, 3), 10: (6, 4, 3)}[version[0]]
    assert (configuration.masterboard_version, configuration.controller_box_type,
            configuration.robot_sub_type) == board


@pytest.mark.parametrize("version", [(1, 8, 0), (3, 15, 0), (5, 0, 0), (5, 11, 0), (10, 14, 0)])
def test_every_mode_is_a_valid_one(version):
    states = session(version, ticks=270)  # the third program run stops at its tick 50
    running = {1: 0}.get(version[0], 7)  # RUNNING: 0 in the CB2 table, 7 from 3.0
    stops = 0
    for state in states:
        mode = state.package(urwire.RobotModeData)
        assert int(mode.robot_mode) == running and mode.robot_mode.name == "RUNNING"
        assert all(j.joint_mode.name == "RUNNING" for j in state.package(urwire.JointData).joints)
        assert state.package(urwire.ToolData).tool_mode == e.ToolMode.RUNNING
        board = state.package(urwire.MasterboardData)
        if version[0] == 1:
            assert board.master_safety_state == e.MasterSafetyState.OK
            assert board.master_on_off_state == e.MasterOnOffState.ON
        else:
            expected = e.SafetyMode.PROTECTIVE_STOP if mode.is_protective_stopped else e.SafetyMode.NORMAL
            assert board.safety_mode == expected
            stops += mode.is_protective_stopped
    assert version[0] == 1 or stops  # the protective stop of every third run shows


def test_default_model_per_generation():
    assert [model_for(v).name for v in [(1, 8, 0), (3, 15, 0), (5, 11, 0), (10, 14, 0)]] == \
        ["ur5", "ur5", "ur5e", "ur5e"]
    configuration = session((5, 11, 0), ticks=1)[0].package(urwire.ConfigurationData)
    assert configuration.dh_d == pytest.approx(PUBLISHED["ur5e"][1])


def test_the_tool_pose_is_the_forward_kinematics_of_the_joints():
    model = MODELS["ur10e"]
    motion = Motion(model)
    states = session((5, 11, 0), "ur10e", ticks=60)
    poses = set()
    for state in states:
        q = [j.q_actual for j in state.package(urwire.JointData).joints]
        info = state.package(urwire.CartesianInfo)
        reported = (info.x, info.y, info.z, info.rx, info.ry, info.rz)
        assert reported == pytest.approx(motion.tcp_pose(q), abs=1e-12)
        # Within reach of the shoulder: no joint set puts the flange farther.
        shoulder = (0.0, 0.0, model.d1)
        assert math.dist(reported[:3], shoulder) < model.reach + model.d4 + model.d5 + model.d6
        poses.add(round(info.x, 6))
    assert len(poses) > 50  # the arm moves


def test_sessions_started_later_join_the_same_motion():
    # A client that connects 3 s after another sees, from its first state, the joints the first
    # one sees at that time.
    early = session((5, 11, 0), "ur5e", ticks=40)
    late = session((5, 11, 0), "ur5e", ticks=10, start=3.0)
    for k, state in enumerate(late):
        assert [j.q_actual for j in state.package(urwire.JointData).joints] == \
            [j.q_actual for j in early[30 + k].package(urwire.JointData).joints]


def test_serve_refuses_an_arm_of_another_generation():
    res = subprocess.run([sys.executable, "-m", "urwire", "serve", "--port", "0", "--software", "3.15",
                          "--model", "ur5e"], capture_output=True, text=True, env=ENV, timeout=60)
    assert res.returncode == 2
    assert "ur5e is not a CB3 arm" in res.stderr and "ur3, ur5, ur10" in res.stderr


@pytest.mark.parametrize("version,sent", [((3, 15, 0), False), ((5, 25, 1), False), ((5, 26, 0), True),
                                          ((10, 12, 0), False), ((10, 13, 0), True), ((10, 14, 0), True)])
def test_hardware_info_follows_the_version_message_from_5_26_and_10_13(version, sent):
    sim = Controller(version, 10, MODELS["ur16e"] if version[0] >= 5 else None)
    records = [r for r in urwire.decode_stream(sim.opening()) if r.TYPE != "robot_message_12"]
    assert records[0].TYPE == "version"
    if not sent:
        assert len(records) == 1
        return
    (info,) = records[1:]
    assert info.TYPE == "hardware_info" and info.robot_type == 4  # UR16
    assert info.control_box_type == e.ControlBoxType.CB5 and info.tool_flange_type == e.ToolFlangeType.V1


@pytest.mark.parametrize("version,sent", [((1, 8, 0), False), ((3, 2, 0), False), ((3, 3, 0), True),
                                          ((5, 13, 0), True), ((5, 14, 0), False), ((10, 14, 0), False)])
def test_robot_message_12_follows_the_version_message_from_3_3_to_5_13(version, sent):
    records = list(urwire.decode_stream(Controller(version, 10).opening()))
    assert records[0].TYPE == "version"
    assert (len(records) > 1 and records[1].TYPE == "robot_message_12") == sent


@pytest.mark.parametrize("version,sent", [((5, 10, 0), False), ((5, 11, 0), True), ((10, 14, 0), True)])
def test_payload_info_is_sent_from_5_11_with_a_real_robots_values(version, sent):
    sim = Controller(version, 10)
    (state,) = [r for r in urwire.decode_stream(b"".join(sim.step())) if r.TYPE == "robot_state"]
    payload = state.package(urwire.PayloadInfo)
    assert (payload is not None) == sent
    if sent:
        assert payload.mass == 1.0 and payload.inertia[:3] == [0.001539] * 3


def test_serial_numbers_are_eleven_digits_of_the_generation():
    from urwire.live.robot_models import serial_number

    ur5e, ur10 = serial_number(MODELS["ur5e"], (5, 11, 0)), serial_number(MODELS["ur10"], (3, 15, 0))
    assert ur5e.isdigit() and len(ur5e) == 11 and ur5e.startswith("2021")
    assert ur10.isdigit() and len(ur10) == 11 and ur10.startswith("2018") and ur5e != ur10
