"""The simulated arm's motion: forward kinematics checked against poses worked out by hand from
UR's published DH parameters, rotation vectors against an independent Rodrigues formula, and one
motion sampled at different rates giving the same joints."""
from __future__ import annotations

import math
import random

import pytest

from urwire.live.motion import Motion, forward_kinematics, rotation_vector
from urwire.live.robot_models import MODELS

# UR5e, from UR's article "DH Parameters for calculations of kinematics and dynamics":
# d1 0.1625, a2 -0.425, a3 -0.3922, d4 0.1333, d5 0.0997, d6 0.0996; alpha pi/2, 0, 0, pi/2, -pi/2, 0.
D1, A2, A3, D4, D5, D6 = 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996


def rodrigues(v) -> list:
    """The rotation matrix of a rotation vector, written out apart from the code under test."""
    angle = math.sqrt(sum(x * x for x in v))
    if angle == 0:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    x, y, z = (c / angle for c in v)
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


def assert_matrix(actual, expected):
    for row_a, row_e in zip(actual, expected):
        assert row_a == pytest.approx(row_e, abs=1e-9)


def test_ur5e_at_zero_is_where_its_dh_parameters_put_it():
    # All joints at 0: the links lie along the base's -x (a2 + a3); wrist 1 and wrist 3 offsets
    # (d4, d6) point along -y, wrist 2's (d5) down. The only turn is the alphas' sum, pi/2 about x.
    pose = Motion(MODELS["ur5e"]).tcp_pose([0.0] * 6)
    assert pose[:3] == pytest.approx((A2 + A3, -(D4 + D6), D1 - D5), abs=1e-12)
    assert pose[3:] == pytest.approx((math.pi / 2, 0.0, 0.0), abs=1e-12)


def test_ur5e_upright():
    # Shoulder and wrist 1 at -pi/2: the arm stands straight up, the flange on top.
    q = [0.0, -math.pi / 2, 0.0, -math.pi / 2, 0.0, 0.0]
    pose = Motion(MODELS["ur5e"]).tcp_pose(q)
    assert pose[:3] == pytest.approx((0.0, -(D4 + D6), D1 - A2 - A3 + D5), abs=1e-12)
    # Rx(pi/2) Rz(-pi): a half turn, so the sign of the rotation vector is free; compare matrices.
    assert_matrix(rodrigues(pose[3:]), [[-1, 0, 0], [0, 0, -1], [0, -1, 0]])


def test_base_joint_turns_the_pose_about_z():
    motion = Motion(MODELS["ur10e"])
    q = [0.3, -1.2, 1.1, -0.4, 0.7, 0.2]
    x, y, z = motion.tcp_pose(q)[:3]
    turned = motion.tcp_pose([q[0] + 0.5] + q[1:])
    c, s = math.cos(0.5), math.sin(0.5)
    assert turned[:3] == pytest.approx((c * x - s * y, s * x + c * y, z), abs=1e-12)


def test_rotation_vector_is_rodrigues_inverse():
    rng = random.Random(7)
    for _ in range(200):
        axis = [rng.gauss(0, 1) for _ in range(3)]
        norm = math.sqrt(sum(a * a for a in axis))
        angle = rng.choice([rng.uniform(0, math.pi), math.pi - 1e-9, 1e-9, math.pi])
        v = [a / norm * angle for a in axis]
        assert_matrix(rodrigues(rotation_vector(rodrigues(v))), rodrigues(v))


def test_the_reported_pose_is_the_forward_kinematics_of_the_dh_chain():
    rotation, position = forward_kinematics(MODELS["ur3"], [0.1, -1.0, 0.5, -0.2, 0.3, 0.4])
    pose = Motion(MODELS["ur3"]).tcp_pose([0.1, -1.0, 0.5, -0.2, 0.3, 0.4])
    assert pose[:3] == pytest.approx(position)
    assert_matrix(rodrigues(pose[3:]), rotation)


def test_every_rate_samples_the_same_motion():
    # RTDE at 500 Hz and the primary stream at 10 Hz meet every 0.1 s on the same joints.
    fast, slow = Motion(MODELS["ur5e"]), Motion(MODELS["ur5e"])
    at_500 = {round(i / 500, 6): fast.joints(i / 500) for i in range(0, 1001)}
    for i in range(0, 21):
        assert slow.joints(i / 10) == at_500[round(i / 10, 6)]


def test_the_motion_is_smooth_and_within_the_joint_limits():
    motion = Motion(MODELS["ur5e"])
    step = 0.002
    for i in range(0, 5000, 7):
        t = i * step
        now, later = motion.joints(t), motion.joints(t + step)
        for j in range(6):
            assert abs(now.q[j]) < 2 * math.pi and abs(now.qd[j]) < math.pi  # the default speed limit
            # qd is the derivative of q, qdd of qd.
            assert (later.q[j] - now.q[j]) / step == pytest.approx(now.qd[j], abs=0.01)
            assert (later.qd[j] - now.qd[j]) / step == pytest.approx(now.qdd[j], abs=0.01)
        assert all(abs(i) < 6.0 for i in now.current)


def test_tcp_speed_is_the_derivative_of_the_pose():
    motion = Motion(MODELS["ur5e"])
    t, h = 4.2, 1e-5
    before = motion.tcp_pose(motion.joints(t - h).q)
    after = motion.tcp_pose(motion.joints(t + h).q)
    linear = [(a - b) / (2 * h) for a, b in zip(after[:3], before[:3])]
    assert motion.tcp_speed(t)[:3] == pytest.approx(linear, abs=1e-6)
    # The turn between the two orientations, R(t+h) R(t-h)^T, is I + 2h [w]x to first order.
    r1, r0 = rodrigues(after[3:]), rodrigues(before[3:])
    turn = [[sum(r1[i][k] * r0[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    angular = [(turn[2][1] - turn[1][2]) / (4 * h), (turn[0][2] - turn[2][0]) / (4 * h),
               (turn[1][0] - turn[0][1]) / (4 * h)]
    assert motion.tcp_speed(t)[3:] == pytest.approx(angular, abs=1e-5)
    assert math.dist(angular, (0, 0, 0)) > 0.01
