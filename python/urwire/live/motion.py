"""One motion of a simulated arm, to be sampled at any time by every interface that reports it.

The joints swing smoothly about a working pose, each at its own period, so the primary stream
(10 Hz), the real-time interface (125/500 Hz) and RTDE (any frequency) that sample the same
Motion at the same time t report the same joints. The tool pose is the forward kinematics of
the model's DH parameters, so the pose a stream reports is the one its joints give.

Conventions are UR's: angles in rad, lengths in m, the TCP pose as (x, y, z, rx, ry, rz) in the
base frame with the orientation as a rotation vector, and the tool flange as the TCP (no offset).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .robot_models import RobotModel

# A pose where a UR arm works over a table: the shoulder lifts the upper arm, the elbow bends
# back down and the wrist points the flange at the table.
WORKING_POSE = (0.0, -1.6, 1.4, -1.37, -1.57, 0.0)
AMPLITUDE = (0.8, 0.35, 0.5, 0.5, 0.6, 0.9)      # rad
PERIOD = (8.0, 10.0, 12.0, 14.0, 16.0, 18.0)     # s
# Current per unit of gravity load and of acceleration, and at rest (A); larger arms draw more.
GRAVITY_AMPS = 3.0
INERTIA_AMPS = 0.4
REST_AMPS = 0.1
# Time step of the finite differences that give the tool's speed (s).
SPEED_STEP = 1e-4


@dataclass(frozen=True)
class JointSample:
    """The six joints at one time: positions (rad), speeds (rad/s), accelerations (rad/s²) and
    motor currents (A)."""
    t: float
    q: tuple
    qd: tuple
    qdd: tuple
    current: tuple


class Motion:
    """The motion of one arm. `joints(t)` and `tcp_pose(q)` are pure: any number of streams may
    sample one Motion, each at its own rate."""

    def __init__(self, model: RobotModel):
        self.model = model
        self.load = model.reach / 0.8172  # a UR5e is 1

    def joints(self, t: float) -> JointSample:
        q, qd, qdd = [], [], []
        for j in range(6):
            w = 2 * math.pi / PERIOD[j]
            phase = w * t + j
            q.append(WORKING_POSE[j] + AMPLITUDE[j] * math.sin(phase))
            qd.append(AMPLITUDE[j] * w * math.cos(phase))
            qdd.append(-AMPLITUDE[j] * w * w * math.sin(phase))
        return JointSample(t, tuple(q), tuple(qd), tuple(qdd), self.currents(q, qdd))

    def currents(self, q, qdd) -> tuple:
        """Motor currents: the shoulder and elbow hold the arm against gravity (the more, the more
        level the links), every joint draws more to accelerate."""
        upper, fore = math.cos(q[1]), math.cos(q[1] + q[2])
        gravity = (0.0, 0.6 * upper + 0.4 * fore, 0.5 * fore, 0.1 * math.cos(q[1] + q[2] + q[3]), 0.0, 0.0)
        return tuple(REST_AMPS + self.load * (GRAVITY_AMPS * g + INERTIA_AMPS * a) for g, a in zip(gravity, qdd))

    def tcp_pose(self, q) -> tuple:
        """The flange pose of joint positions q: (x, y, z, rx, ry, rz)."""
        rotation, position = forward_kinematics(self.model, q)
        return (*position, *rotation_vector(rotation))

    def tcp_speed(self, t: float) -> tuple:
        """The flange's linear (m/s) and angular (rad/s) velocity in the base frame at time t."""
        before_r, before_p = forward_kinematics(self.model, self.joints(t - SPEED_STEP).q)
        after_r, after_p = forward_kinematics(self.model, self.joints(t + SPEED_STEP).q)
        linear = [(a - b) / (2 * SPEED_STEP) for a, b in zip(after_p, before_p)]
        turn = _multiply(after_r, _transpose(before_r))
        angular = [x / (2 * SPEED_STEP) for x in rotation_vector(turn)]
        return (*linear, *angular)


def forward_kinematics(model: RobotModel, q) -> tuple:
    """The flange's rotation matrix (rows) and position in the base frame: the product of each
    joint's standard DH transform Rot_z(theta + q) Trans_z(d) Trans_x(a) Rot_x(alpha)."""
    rotation = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    x = y = z = 0.0
    for qj, theta, a, d, alpha in zip(q, model.dh_theta, model.dh_a, model.dh_d, model.dh_alpha):
        ct, st = math.cos(theta + qj), math.sin(theta + qj)
        ca, sa = math.cos(alpha), math.sin(alpha)
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation
        # The link's origin, (a cos, a sin, d) in the frame so far.
        ox, oy = a * ct, a * st
        x, y, z = (x + r00 * ox + r01 * oy + r02 * d, y + r10 * ox + r11 * oy + r12 * d,
                   z + r20 * ox + r21 * oy + r22 * d)
        rotation = _multiply(rotation, ((ct, -st * ca, st * sa), (st, ct * ca, -ct * sa), (0.0, sa, ca)))
    return rotation, (x, y, z)


def rotation_vector(r) -> tuple:
    """The rotation vector (axis times angle, the angle in [0, pi]) of a rotation matrix."""
    skew = (r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1])  # 2 sin(angle) axis
    sin_angle = math.sqrt(sum(x * x for x in skew)) / 2
    cos_angle = (r[0][0] + r[1][1] + r[2][2] - 1) / 2
    angle = math.atan2(sin_angle, cos_angle)
    if angle < 1e-12:
        return (0.0, 0.0, 0.0)
    if angle < math.pi - 1e-3:
        return tuple(angle * x / (2 * sin_angle) for x in skew)
    # Near a half turn the skew part vanishes: the axis is read from the symmetric part,
    # (R + R^T) / 2 - cos(angle) I = (1 - cos(angle)) axis axis^T, and its sign from the skew part.
    sym = [[(r[i][j] + r[j][i]) / 2 - (cos_angle if i == j else 0.0) for j in range(3)] for i in range(3)]
    i = max(range(3), key=lambda k: sym[k][k])
    axis = [x / math.sqrt(sym[i][i] * (1 - cos_angle)) for x in sym[i]]
    if sum(a * b for a, b in zip(axis, skew)) < 0:
        axis = [-x for x in axis]
    return tuple(angle * x for x in axis)


def _multiply(a, b) -> tuple:
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = b
    return ((a00 * b00 + a01 * b10 + a02 * b20, a00 * b01 + a01 * b11 + a02 * b21, a00 * b02 + a01 * b12 + a02 * b22),
            (a10 * b00 + a11 * b10 + a12 * b20, a10 * b01 + a11 * b11 + a12 * b21, a10 * b02 + a11 * b12 + a12 * b22),
            (a20 * b00 + a21 * b10 + a22 * b20, a20 * b01 + a21 * b11 + a22 * b21, a20 * b02 + a21 * b12 + a22 * b22))


def _transpose(a) -> tuple:
    return tuple(zip(*a))
