"""A simulated controller: the messages a robot of one software version sends a client, built
with the generated message classes and encoders, so every layout is that version's own.

A client gets the Version message, then a robot state per tick (kinematics and configuration
only in the first), while a program runs in a loop: key messages when it starts and stops, text
messages, global variables (set up once, then updated) and now and then a protective stop with
its safety mode message.

The robot is a believable one: a chosen arm (robot_models) with its nominal DH parameters, robot
type and controller board, every mode a valid one of the version's tables (robot and joints
RUNNING, safety NORMAL but in a protective stop), and joints that follow the arm's Motion, with
the tool pose their forward kinematics.
"""
from __future__ import annotations

import dataclasses
import math
import re
from typing import Iterator

from .._runtime import GlobalValue
from ..decoding import encode_message, package_classes
from ..generated import enums as _e
from ..generated import messages as _m
from ..generated.spec import value_codec
from .motion import Motion
from .robot_cell import PAUSED, POWER_OFF, RobotCell
from .robot_models import BOARDS, E_SERIES_BOX, RobotModel, generation, kinematics_checksums, model_for

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


def mode_code(table: str, version: tuple, name: str) -> int:
    """The code of `name` in a table whose codes changed between versions (ROBOT_MODE_BY_VALUE,
    JOINT_MODE_BY_VALUE): RUNNING is 0 on CB2 and 7 from 3.0."""
    return next(int(m) for m in getattr(_e, table)[version].values() if m.name == name)


# Real robots are seen sending payload info from 5.11 (URCL pull request 137) and not on URSim 5.8
# or 5.10; robot message 12 right after the Version message from 3.3 to 5.13 (docs/firmware-history.md).
PAYLOAD_INFO_FROM = (5, 11, 0)
MESSAGE_12_VERSIONS = ((3, 3, 0), (5, 13, 99))


def state_classes(version: tuple) -> list:
    """The sub-package classes a controller of `version` sends, in type-code order."""
    return [cls for cls in package_classes(version).values()
            if cls not in INTERNAL and (generation(version) in E_SERIES_BOX or cls not in E_SERIES_ONLY)
            and (cls is not _m.PayloadInfo or version >= PAYLOAD_INFO_FROM)]


class Controller:
    """The messages of one client's session, tick by tick."""

    def __init__(self, version: tuple, rate: float, model: RobotModel | None = None, start: float = 0.0,
                 cell: RobotCell | None = None):
        """`model`: the arm (default: the generation's usual one); `start`: the time on the
        motion's clock of the first state, so that sessions started at different times, and the
        other interfaces, report the same motion at the same time. `cell`: the robot `urwire serve`
        shares between its interfaces, whose program and power state this stream then reports
        (its joints hold still while the program is stopped or paused); without one the demo
        program plays on."""
        self.cell = cell
        self._was_playing = True       # the demo program plays when a session starts
        self.version = version
        self.rate = rate
        self.tick = 0
        self.start = start
        self.model = model or model_for(version)
        self.motion = Motion(self.model)
        self._sample, self._sampled_tick = None, -1
        self.board = BOARDS[generation(version)]
        self.classes = state_classes(version)
        self.running_mode = mode_code("ROBOT_MODE_BY_VALUE", version, "RUNNING")
        self.joint_running = mode_code("JOINT_MODE_BY_VALUE", version, "RUNNING")
        codes = value_codec(version).codes
        self.value_codes = {"INT": codes["INT"], "NUM": codes["NUM"], "BOOL": codes["BOOL"], "POSE": codes["POSE"],
                            "STRING": codes.get("VAR_STRING", codes.get("STRING"))}
        self.string_type = "VAR_STRING" if "VAR_STRING" in codes else "STRING"

    # --- timing -----------------------------------------------------------------------------
    def seconds(self) -> float:
        return self.tick / self.rate

    def millis(self) -> int:
        return int(self.seconds() * 1000)

    def motion_time(self) -> float:
        return self.start + self.seconds()

    def sample(self):
        """The joints of this tick, worked out once for the packages that report them."""
        if self._sampled_tick != self.tick:
            t = self.motion_time()
            self._sample = self.cell.joints(t) if self.cell else self.motion.joints(t)
            self._sampled_tick = self.tick
        return self._sample

    # --- messages ---------------------------------------------------------------------------
    def encode(self, msg) -> bytes:
        return encode_message(msg, self.version)

    def version_message(self) -> bytes:
        major, minor, bugfix = self.version
        msg = filled(_m.VersionMessage, timestamp=0, source=SOURCE, project_name="URControl",
                     major_version=major, minor_version=minor, svn_revision=20000 + minor,
                     bugfix_version=bugfix, build_number=1, build_date="23-11-2026, 00:00:00")
        return self.encode(msg)

    def opening(self) -> bytes:
        """What a client gets on connecting: the Version message, then robot message 12 where real
        controllers send it, and from 5.26 and 10.13 the hardware info message (the spec's
        hardware_info: sent from those releases)."""
        out = self.version_message()
        low, high = MESSAGE_12_VERSIONS
        if low <= self.version <= high:
            # The payload a URSim 5.4 sends (docs/firmware-history.md#robot-message-subtype-12).
            out += self.encode(_m.RobotMessage12Message(timestamp=0, source=SOURCE, raw=bytes.fromhex("000000000000000001")))
        if (5, 26, 0) <= self.version < (10, 0, 0) or self.version >= (10, 13, 0):
            # Control box CB5 and tool flange V1 (numbered as later patch releases do): an e-Series
            # box and the flange of the arms UR sold with it.
            out += self.encode(filled(_m.HardwareInfoMessage, timestamp=0, source=SOURCE,
                                      robot_type=self.model.robot_type, control_box_type=_e.ControlBoxType.CB5,
                                      tool_flange_type=_e.ToolFlangeType.V1))
        return out

    def playing(self) -> bool:
        """Whether the demo program plays: always, unless the shared robot's program is stopped or
        paused (a dashboard `stop` or `pause`) or its arm is not running (powered off)."""
        return self.cell is None or self.cell.moving

    def step(self) -> Iterator[bytes]:
        """The messages of the next tick: the robot state first, then what the program says."""
        phase = self.tick % CYCLE_TICKS
        run = self.tick // CYCLE_TICKS
        stops = run % STOP_EVERY == STOP_EVERY - 1
        yield _m.RobotStateMessage(self.packages(phase, stops)).encode(self.version)
        playing = self.playing()
        if playing != self._was_playing:
            yield self.program_key(playing)
            self._was_playing = playing
        if playing:
            yield from self.program(phase, run, stops)
        self.tick += 1

    def program_key(self, started: bool) -> bytes:
        """The key message of a program the shared robot started or stopped (a dashboard `play`,
        `stop` or `pause`, a power change), named as the demo program's are: by the file's stem."""
        title = "PROGRAM_XXX_STARTED" if started else "PROGRAM_XXX_STOPPED"
        name = self.cell.program_name.rsplit(".", 1)[0] if self.cell else "demo"
        return self.encode(filled(_m.KeyMessage, timestamp=self.millis(), source=SOURCE, title=title, text=name))

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
        mode, powered, paused, speed = self.running_mode, True, False, 1.0
        if self.cell is not None:
            running = running and self.playing()
            paused = self.cell.program_state == PAUSED
            powered = self.cell.robot_mode != POWER_OFF
            mode = mode_code("ROBOT_MODE_BY_VALUE", self.version, self.cell.robot_mode)
            speed = self.cell.speed_fraction
        return filled(_m.RobotModeData, timestamp=self.millis(), is_real_robot_connected=True,
                      is_real_robot_enabled=True, is_robot_power_on=powered, is_protective_stopped=protective,
                      is_program_running=running, is_program_paused=paused, robot_mode=mode,
                      target_speed_fraction=speed, speed_scaling=speed if self.playing() else 0.0,
                      target_speed_fraction_limit=1.0)

    def joints(self, running: bool, protective: bool):
        t = self.seconds()
        sample = self.sample()
        joints = []
        for j in range(JOINTS):
            q, qd = sample.q[j], sample.qd[j]
            joints.append(_m.Joint(q_actual=q, q_target=q + 0.001 * qd, qd_actual=qd, i_actual=sample.current[j],
                                   v_actual=48.0 - 0.1 * abs(qd), t_motor=30.0 + 8.0 * (1 - math.exp(-t / 600)) + j,
                                   t_micro=35.0 + j, joint_mode=self.joint_running))
        return _m.JointData(joints)

    def cartesian(self, running: bool, protective: bool):
        x, y, z, rx, ry, rz = self.motion.tcp_pose(self.sample().q)
        return filled(_m.CartesianInfo, x=x, y=y, z=z, rx=rx, ry=ry, rz=rz)

    def kinematics(self, running: bool, protective: bool):
        m = self.model
        # calibration_status 2, as a real 5.11 robot sends (tests/conformance, URCL PR 137).
        return filled(_m.KinematicsInfo, checksum=kinematics_checksums(m), dh_theta=list(m.dh_theta),
                      dh_a=list(m.dh_a), dh_d=list(m.dh_d), dh_alpha=list(m.dh_alpha), calibration_status=2)

    def masterboard(self, running: bool, protective: bool):
        # CB2 says its safety in master_safety_state and master_on_off_state, later versions in
        # safety_mode: each version's encoder writes the fields of its own layout.
        safety = _e.SafetyMode.PROTECTIVE_STOP if protective else _e.SafetyMode.NORMAL
        return filled(_m.MasterboardData, master_board_temperature=38.5, robot_voltage_48v=48.1,
                      robot_current=0.9, master_io_current=0.05, master_safety_state=_e.MasterSafetyState.OK,
                      master_on_off_state=_e.MasterOnOffState.ON, safety_mode=safety,
                      euromap_voltage_24v=0.0, operational_mode_selector_input=1,
                      three_position_enabling_device_input=1)

    def payload(self, running: bool, protective: bool):
        # What a real 5.11 robot sends: 1 kg at the flange, the inertia of a sphere of water.
        return _m.PayloadInfo(mass=1.0, center_of_gravity=[0.0, 0.0, 0.0],
                              inertia=[0.001539, 0.001539, 0.001539, 0.0, 0.0, 0.0])

    def tool(self, running: bool, protective: bool):
        return filled(_m.ToolData, tool_voltage_48v=24.1, tool_output_voltage=24, tool_current=0.06,
                      tool_temperature=33.0, tool_mode=_e.ToolMode.RUNNING)

    def tool_comm(self, running: bool, protective: bool):
        # The settings URSim 5.8 sends (tests/conformance, URCL's first UR5e state).
        return filled(_m.ToolCommInfo, baud_rate=115200, parity=0, stop_bits=1, rx_idle_chars=1.5,
                      tx_idle_chars=3.5)

    def tool_mode(self, running: bool, protective: bool):
        return filled(_m.ToolModeInfo, output_mode=0, digital_output_mode_output_0=1,
                      digital_output_mode_output_1=1)

    def configuration(self, running: bool, protective: bool):
        limits = [filled(_m.JointPositionLimit, joint_min_limit=-2 * math.pi, joint_max_limit=2 * math.pi)
                  for _ in range(JOINTS)]
        motion = [filled(_m.JointMotionLimit, joint_max_speed=math.pi, joint_max_acceleration=40.0)
                  for _ in range(JOINTS)]
        m, board = self.model, self.board
        return filled(_m.ConfigurationData, joint_position_limits=limits, joint_motion_limits=motion,
                      v_joint_default=1.05, a_joint_default=1.4, v_tool_default=0.25, a_tool_default=1.2,
                      eq_radius=0.02, dh_a=list(m.dh_a), dh_d=list(m.dh_d), dh_alpha=list(m.dh_alpha),
                      dh_theta=list(m.dh_theta), masterboard_version=board.masterboard_version,
                      controller_box_type=board.controller_box_type, robot_type=m.robot_type,
                      robot_sub_type=board.robot_sub_type,
                      motor_type=[2] * JOINTS)  # CB2 1.8 only: 2 for each joint, as the CustusX capture

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
            yield self.safety_mode(ts, _e.SafetyMode.PROTECTIVE_STOP)
            yield self.encode(filled(_m.KeyMessage, timestamp=ts, source=SOURCE, title="PROGRAM_XXX_STOPPED",
                                     text="demo"))
        elif stops and phase == 60:
            yield self.safety_mode(ts, _e.SafetyMode.NORMAL)
        elif not stops and phase == 80:
            yield self.encode(filled(_m.KeyMessage, timestamp=ts, source=SOURCE, title="PROGRAM_XXX_STOPPED",
                                     text="demo"))

    def safety_mode(self, ts: int, mode: _e.SafetyMode) -> bytes:
        return self.encode(filled(_m.SafetyModeMessage, timestamp=ts, source=SOURCE, robot_message_code=209,
                                  robot_message_argument=0, safety_mode_type=mode, report_data_type=0,
                                  report_data=0, text=mode.name.replace("_", " ").lower()))

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
    _m.CartesianInfo: Controller.cartesian,
    _m.KinematicsInfo: Controller.kinematics,
    _m.MasterboardData: Controller.masterboard,
    _m.ToolData: Controller.tool,
    _m.ToolCommInfo: Controller.tool_comm,
    _m.ToolModeInfo: Controller.tool_mode,
    _m.ConfigurationData: Controller.configuration,
    _m.PayloadInfo: Controller.payload,
}
