"""A simulated controller: the messages a robot of one software version sends a client, built
with the generated message classes and encoders, so every layout is that version's own.

A client gets the Version message, then a robot state per tick (kinematics and configuration
only in the first), while a program runs in a loop: key messages when it starts and stops, text
messages, global variables (set up once, then updated) and now and then a protective stop with
its safety mode message.
"""
from __future__ import annotations

import dataclasses
import math
import re
from typing import Iterator

from .generated import enums as _e
from .generated import messages as _m
from ._runtime import GlobalValue
from .decoding import encode_message, package_classes
from .generated.spec import value_codec

JOINTS = 6
CYCLE_TICKS = 100          # one program run, start to start
STOP_EVERY = 3             # every third run ends in a protective stop
SOURCE = -2                # the controller, as real Version messages say
FIRST_ONLY = (_m.KinematicsInfo, _m.ConfigurationData)
# Layouts UR documents as internal (calibration, safety checksums, singularities) or as e-Series
# only are left out where a real controller of that generation does not send them.
INTERNAL = (_m.CalibrationData, _m.SafetyData, _m.SingularityInfo)
E_SERIES_ONLY = (_m.ToolCommInfo, _m.ToolModeInfo)

_ZERO = {"int": 0, "enum": 0, "bool": False, "f32": 0.0, "f64": 0.0, "int|f32": 0, "int|f64": 0, "text": "", "hex": b"",
         "texts": [], "values": []}
_LIST_OF = re.compile(r"list\[(\w+)\]")


def filled(cls, **given):
    """An instance of a generated class with `given` fields and every other one zero: each
    version's encoder writes only the fields of its own layout."""
    kinds = {name: kind for name, kind, _ in cls.JSON}
    values = {}
    for f in dataclasses.fields(cls):
        if f.name in given or f.name not in kinds:
            continue
        kind = kinds[f.name]
        if kind == "items":
            item = getattr(_m, _LIST_OF.search(str(f.type)).group(1))
            values[f.name] = [filled(item) for _ in range(JOINTS)]
        elif kind.startswith("list:"):
            values[f.name] = [0.0 if kind != "list:int" else 0] * JOINTS
        else:
            values[f.name] = _ZERO[kind]
    return cls(**values, **given)


def _enum_value(table: str, version: tuple, name: str, default: int) -> int:
    try:
        members = getattr(_e, table)[version].values()
    except (KeyError, AttributeError):
        return default
    return next((int(m) for m in members if m.name == name), default)


def state_classes(version: tuple) -> list:
    """The sub-package classes a controller of `version` sends, in type-code order."""
    return [cls for cls in package_classes(version).values()
            if cls not in INTERNAL and (version[0] >= 5 or cls not in E_SERIES_ONLY)]


class Controller:
    """The messages of one client's session, tick by tick."""

    def __init__(self, version: tuple, rate: float):
        self.version = version
        self.rate = rate
        self.tick = 0
        self.classes = state_classes(version)
        self.running_mode = _enum_value("ROBOT_MODE_BY_VALUE", version, "RUNNING", 7)
        self.joint_running = _enum_value("JOINT_MODE_BY_VALUE", version, "RUNNING", 253)
        codes = value_codec(version).codes
        self.value_codes = {"INT": codes["INT"], "NUM": codes["NUM"], "BOOL": codes["BOOL"], "POSE": codes["POSE"],
                            "STRING": codes.get("VAR_STRING", codes.get("STRING"))}
        self.string_type = "VAR_STRING" if "VAR_STRING" in codes else "STRING"

    # --- timing -----------------------------------------------------------------------------
    def seconds(self) -> float:
        return self.tick / self.rate

    def millis(self) -> int:
        return int(self.seconds() * 1000)

    # --- messages ---------------------------------------------------------------------------
    def encode(self, msg) -> bytes:
        return encode_message(msg, self.version)

    def version_message(self) -> bytes:
        major, minor, bugfix = self.version
        msg = filled(_m.VersionMessage, timestamp=0, source=SOURCE, project_name="URControl",
                     major_version=major, minor_version=minor, svn_revision=20000 + minor,
                     bugfix_version=bugfix, build_number=1, build_date="23-11-2026, 00:00:00")
        return self.encode(msg)

    def step(self) -> Iterator[bytes]:
        """The messages of the next tick: the robot state first, then what the program says."""
        phase = self.tick % CYCLE_TICKS
        run = self.tick // CYCLE_TICKS
        stops = run % STOP_EVERY == STOP_EVERY - 1
        yield _m.RobotStateMessage(self.packages(phase, stops)).encode(self.version)
        yield from self.program(phase, run, stops)
        self.tick += 1

    def packages(self, phase: int, stops: bool) -> list:
        protective = stops and 50 <= phase < 60
        running = 0 < phase < (50 if stops else 80)
        out = []
        for cls in self.classes:
            if cls in FIRST_ONLY and self.tick:
                continue
            build = _BUILDERS.get(cls)
            out.append(build(self, running, protective) if build else filled(cls))
        return out

    def robot_mode(self, running: bool, protective: bool):
        return filled(_m.RobotModeData, timestamp=self.millis(), is_real_robot_connected=True,
                      is_real_robot_enabled=True, is_robot_power_on=True, is_protective_stopped=protective,
                      is_program_running=running, robot_mode=self.running_mode, target_speed_fraction=1.0,
                      speed_scaling=1.0, target_speed_fraction_limit=1.0)

    def joints(self, running: bool, protective: bool):
        t = self.seconds()
        joints = []
        for j in range(JOINTS):
            # Each joint swings about its own centre, well inside the +-2 pi limits.
            w = 2 * math.pi / (8 + 2 * j)
            q = 0.3 * j - 0.6 + 0.8 * math.sin(w * t + j)
            qd = 0.8 * w * math.cos(w * t + j)
            joints.append(_m.Joint(q_actual=q, q_target=q + 0.001 * qd, qd_actual=qd,
                                   i_actual=0.4 + 0.3 * abs(qd) + 0.05 * math.sin(3 * t + j),
                                   v_actual=48.0 - 0.1 * abs(qd), t_motor=30.0 + 8.0 * (1 - math.exp(-t / 600)) + j,
                                   t_micro=35.0 + j, joint_mode=self.joint_running))
        return _m.JointData(joints)

    def configuration(self, running: bool, protective: bool):
        limits = [filled(_m.JointPositionLimit, joint_min_limit=-2 * math.pi, joint_max_limit=2 * math.pi)
                  for _ in range(JOINTS)]
        motion = [filled(_m.JointMotionLimit, joint_max_speed=math.pi, joint_max_acceleration=40.0)
                  for _ in range(JOINTS)]
        return filled(_m.ConfigurationData, joint_position_limits=limits, joint_motion_limits=motion,
                      v_joint_default=1.05, a_joint_default=1.4, v_tool_default=0.25, a_tool_default=1.2,
                      eq_radius=0.02)

    def program(self, phase: int, run: int, stops: bool) -> Iterator[bytes]:
        ts = self.millis()
        if phase == 0:
            yield self.encode(filled(_m.KeyMessage, timestamp=ts, source=SOURCE, title="PROGRAM_XXX_STARTED",
                                     text="demo"))
            if run == 0:
                names = ["counter", "speed", "gripper_closed", "waypoint", "status"]
                yield self.encode(filled(_m.GlobalVariablesSetupMessage, timestamp=ts, start_index=0,
                                         variable_names=names))
        elif phase == 20:
            yield self.encode(filled(_m.TextMessage, timestamp=ts, source=SOURCE, text=f"cycle {run} picking"))
        if 0 < phase < 80 and phase % 5 == 0 and not (stops and phase >= 50):
            yield self.encode(filled(_m.GlobalVariablesUpdateMessage, timestamp=ts, start_index=0,
                                     variables=self.variables(run, phase)))
        if stops and phase == 50:
            yield self.safety_mode(ts, "PROTECTIVE_STOP", 3)
            yield self.encode(filled(_m.KeyMessage, timestamp=ts, source=SOURCE, title="PROGRAM_XXX_STOPPED",
                                     text="demo"))
        elif stops and phase == 60:
            yield self.safety_mode(ts, "NORMAL", 1)
        elif not stops and phase == 80:
            yield self.encode(filled(_m.KeyMessage, timestamp=ts, source=SOURCE, title="PROGRAM_XXX_STOPPED",
                                     text="demo"))

    def safety_mode(self, ts: int, mode: str, default: int) -> bytes:
        code = _enum_value("SAFETY_MODE_BY_VALUE", self.version, mode, default)
        return self.encode(filled(_m.SafetyModeMessage, timestamp=ts, source=SOURCE, robot_message_code=209,
                                  robot_message_argument=0, safety_mode_type=code, report_data_type=0,
                                  report_data=0, text=mode.replace("_", " ").lower()))

    def variables(self, run: int, phase: int) -> list:
        c = self.value_codes
        t = self.seconds()
        pose = [0.4 + 0.1 * math.sin(t), -0.2, 0.3, 0.0, 3.14, 0.0]
        return [GlobalValue("INT", run * 100 + phase, c["INT"]),
                GlobalValue("NUM", 0.5 + 0.25 * math.sin(t), c["NUM"]),
                GlobalValue("BOOL", phase % 10 == 0, c["BOOL"]),
                GlobalValue("POSE", pose, c["POSE"]),
                GlobalValue(self.string_type, f"run {run}", c["STRING"])]


_BUILDERS = {
    _m.RobotModeData: Controller.robot_mode,
    _m.JointData: Controller.joints,
    _m.ConfigurationData: Controller.configuration,
}
