"""The robot arms a simulated controller can be: each model's nominal kinematics and the codes
its controller reports about itself, by controller generation.

DH parameters (theta is 0 for every joint): UR's support article "DH Parameters for calculations
of kinematics and dynamics",
https://www.universal-robots.com/articles/ur/application-installation/dh-parameters-for-calculations-of-kinematics-and-dynamics/
(CB3 UR3, UR5 and UR10, e-Series UR3e to UR16e, UR20 and UR30); the same values are in
UniversalRobots/Universal_Robots_ROS2_Description@2221ec0f:config/<model>/default_kinematics.yaml.
A CB2 controller is given its arm's CB3 values: UR's older manuals list earlier series of the UR5
and UR10 whose lengths differ by millimetres.

Robot type codes (configuration data's robot_type): UniversalRobots/Universal_Robots_Client_Library
@c5d1e26c:include/ur_client_library/ur/datatypes.h, enum RobotType (UR5 1, UR10 2, UR3 3, UR16 4,
UR20 7, UR30 8). An e-Series arm reports the code of its CB3 namesake: a UR5e is 1, as URSim 5.8's
UR5e sends (tests/conformance/Universal_Robots_Client_Library/robot_state_ursim5.8_ur5e_first.yaml).
"""
from __future__ import annotations

import math
import struct
import zlib
from dataclasses import dataclass

HALF_PI = math.pi / 2
# Every UR arm twists its links the same way; only the lengths differ.
DH_ALPHA = (HALF_PI, 0.0, 0.0, HALF_PI, -HALF_PI, 0.0)
DH_THETA = (0.0,) * 6

CB2, CB3, E_SERIES, POLYSCOPE_X = "CB2", "CB3", "e-Series", "PolyScope X"
GENERATION_OF_MAJOR = {1: CB2, 3: CB3, 5: E_SERIES, 10: POLYSCOPE_X}


@dataclass(frozen=True)
class RobotModel:
    name: str                # as `--model` takes it: "ur5e"
    robot_type: int          # configuration data's robot_type
    generations: tuple       # the controller generations this arm was sold with
    d1: float                # DH d of the base joint (m)
    a2: float                # DH a of the upper arm (m)
    a3: float                # DH a of the forearm (m)
    d4: float                # DH d of wrist 1, 2 and 3 (m)
    d5: float
    d6: float

    @property
    def dh_a(self) -> tuple:
        return (0.0, self.a2, self.a3, 0.0, 0.0, 0.0)

    @property
    def dh_d(self) -> tuple:
        return (self.d1, 0.0, 0.0, self.d4, self.d5, self.d6)

    @property
    def dh_alpha(self) -> tuple:
        return DH_ALPHA

    @property
    def dh_theta(self) -> tuple:
        return DH_THETA

    @property
    def reach(self) -> float:
        """Shoulder to wrist, stretched out (m): what the arm's motion scales with."""
        return -(self.a2 + self.a3)


_CB = (CB2, CB3)
# The generations of the e-Series control box: PolyScope X runs on it and sends its layouts.
E_SERIES_BOX = (E_SERIES, POLYSCOPE_X)
MODELS = {m.name: m for m in (
    RobotModel("ur3", 3, (CB3,), 0.1519, -0.24365, -0.21325, 0.11235, 0.08535, 0.0819),
    RobotModel("ur5", 1, _CB, 0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823),
    RobotModel("ur10", 2, _CB, 0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922),
    RobotModel("ur3e", 3, E_SERIES_BOX, 0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
    RobotModel("ur5e", 1, E_SERIES_BOX, 0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
    RobotModel("ur10e", 2, E_SERIES_BOX, 0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
    RobotModel("ur16e", 4, E_SERIES_BOX, 0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655),
    RobotModel("ur20", 7, E_SERIES_BOX, 0.2363, -0.862, -0.7287, 0.201, 0.1593, 0.1543),
    RobotModel("ur30", 8, E_SERIES_BOX, 0.2363, -0.637, -0.5037, 0.201, 0.1593, 0.1543),
)}
DEFAULT_MODEL = {CB2: "ur5", CB3: "ur5", E_SERIES: "ur5e", POLYSCOPE_X: "ur5e"}


@dataclass(frozen=True)
class ControllerBoard:
    """What configuration data says of the controller beside the arm."""
    masterboard_version: int
    controller_box_type: int
    robot_sub_type: int


# CB2: a UR5 on 1.8 (the CustusX capture, docs/firmware-history.md#configuration-data) sends
# masterboard 5, control box 2, sub-type 1. e-Series: URSim 5.8's UR5e sends 6, 4 and 3 (the
# URCL sample above); PolyScope X runs on the same control box. No public CB3 capture gives them:
# its values are the ones between.
BOARDS = {CB2: ControllerBoard(5, 2, 1), CB3: ControllerBoard(5, 3, 2),
          E_SERIES: ControllerBoard(6, 4, 3), POLYSCOPE_X: ControllerBoard(6, 4, 3)}


def generation(version: tuple) -> str:
    """The controller generation of a software version: CB2 1.x, CB3 3.x, e-Series 5.x,
    PolyScope X 10.x; a version between series is taken as the series below it."""
    major = max((m for m in GENERATION_OF_MAJOR if m <= version[0]), default=1)
    return GENERATION_OF_MAJOR[major]


def model_for(version: tuple, name: str | None = None) -> RobotModel:
    """The arm a controller of `version` drives: `name`, or the generation's usual one. A ValueError
    says which models the generation takes when `name` is not one of them."""
    gen = generation(version)
    model = MODELS.get((name or DEFAULT_MODEL[gen]).lower())
    if model is None or gen not in model.generations:
        fits = ", ".join(m.name for m in MODELS.values() if gen in m.generations)
        raise ValueError(f"{name} is not a {gen} arm (software {'.'.join(map(str, version))}): "
                         f"choose one of {fits}")
    return model


def serial_number(model: RobotModel, version: tuple) -> str:
    """A made-up serial number, eleven digits from a year of the generation's sale: no
    primary-interface message carries one (the dashboard server's `get serial number` does)."""
    year = {CB2: 2014, CB3: 2018, E_SERIES: 2021, POLYSCOPE_X: 2024}[generation(version)]
    return f"{year}{model.robot_type:02d}{version[0] % 10}0042"


def kinematics_checksums(model: RobotModel) -> list:
    """Kinematics info's six joint checksums. A real robot's hash its own calibration, which UR
    does not describe (URSim sends 0xFFFFFFFF for each); these are the CRC-32 of each joint's
    nominal DH row (theta, a, d, alpha), nonzero and the same for every robot of a model."""
    rows = zip(model.dh_theta, model.dh_a, model.dh_d, model.dh_alpha)
    return [zlib.crc32(struct.pack(">4d", *row)) for row in rows]
