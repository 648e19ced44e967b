"""The state one simulated robot shares between the interfaces `urwire serve` serves.

Every interface samples the same Motion on one clock, the server's: `t` is the seconds since the
server started, as a controller's RTDE `timestamp` and real-time `time` count from its start. What
clients change is kept here, so every interface reports it:

- the program (dashboard `play`, `stop`, `pause`, `load`): the arm moves only while it plays, so
  the motion's own time is the time spent playing (`motion_time`), and a stopped or paused arm
  holds its joints, with zero speeds, on every interface;
- the power (dashboard `power on`, `power off`, `brake release`), which sets the robot mode, and
  the operational mode the dashboard sets;
- RTDE inputs (speed slider, standard digital outputs, input registers), and which RTDE connection
  holds each input, so that a second client asking for one gets `IN_USE`.
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, replace
from typing import Optional

from .motion import JointSample, Motion
from .robot_models import RobotModel, serial_number

PLAYING, PAUSED, STOPPED = "PLAYING", "PAUSED", "STOPPED"
# Robot modes by name (the RTDE guide's and the real-time interface's codes, 3.0 and later).
POWER_OFF, IDLE, RUNNING = "POWER_OFF", "IDLE", "RUNNING"
ROBOT_MODE_CODES = {POWER_OFF: 3, IDLE: 5, RUNNING: 7}
# RTDE runtime_state and the real-time program_state share these codes.
PROGRAM_STATE_CODES = {STOPPED: 1, PLAYING: 2, PAUSED: 4}
DEMO_PROGRAM = "/programs/demo.urp"
# The build of the served software, as RTDE's controller version and the dashboard's version
# replies give it (a 5.11.1 release's: "URSoftware 5.11.1.108318 (Nov 26 2021)").
BUILD_NUMBER, BUILD_DATE = 108318, "Nov 26 2021"
SAFETY_NORMAL = 1
NO_OPERATIONAL_MODE = "NONE"
KEPT_CHANGES = 64
# Joint modes (3.0 and later): RUNNING 253, IDLE 255.
JOINT_RUNNING, JOINT_IDLE = 253, 255


@dataclass(frozen=True)
class Snapshot:
    """The robot at one server time t, in SI units and the RTDE guide's codes."""
    t: float
    q: tuple
    qd: tuple
    qdd: tuple
    current: tuple
    tcp_pose: tuple
    tcp_speed: tuple
    robot_mode: int
    safety_mode: int
    program_state: int
    speed_scaling: float
    target_speed_fraction: float
    digital_outputs: int
    main_voltage: float
    robot_voltage: float
    robot_current: float
    joint_temperatures: tuple
    joint_mode: int


@dataclass
class RtdeInputs:
    """The values RTDE clients last wrote, by variable name, and which connection holds each."""
    values: dict
    owners: dict


class RobotCell:
    """One robot: its model, software version, motion and the state clients change."""

    def __init__(self, version: tuple, model: RobotModel):
        self.version = version
        self.model = model
        self.motion = Motion(model)
        self.serial = serial_number(model, version)
        self.program_state = PLAYING
        self.loaded_program: Optional[str] = DEMO_PROGRAM
        self.robot_mode = RUNNING
        self.operational_mode = NO_OPERATIONAL_MODE   # the dashboard's: none set, the pendant decides
        self.inputs = RtdeInputs({"speed_slider_fraction": 1.0, "standard_digital_output": 0}, {})
        # Each time (server seconds) the arm started or stopped moving, with the seconds it had
        # moved by then and whether it moves after: the latest few, since interfaces sample times
        # at most a period or two before now, and a client toggling the program costs no more.
        self._changes: list[tuple[float, float, bool]] = [(0.0, 0.0, True)]

    # ---- the motion --------------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        return self.program_state == PLAYING and self.robot_mode == RUNNING

    def _change_at(self, t: float) -> tuple[float, float, bool]:
        """The latest change at or before t (the earliest kept, for a t before it)."""
        index = bisect.bisect_right(self._changes, (t, math.inf, True)) - 1
        return self._changes[max(index, 0)]

    def motion_time(self, t: float) -> float:
        """The motion's time at server time t: the seconds the arm has moved until t."""
        since, moved, moving = self._change_at(t)
        return moved + (max(t - since, 0.0) if moving else 0.0)

    def joints(self, t: float) -> JointSample:
        """The joints at server time t: held still, speeds and accelerations zero, when not moving."""
        sample = self.motion.joints(self.motion_time(t))
        if self._moving_at(t):
            return sample
        still = (0.0,) * len(sample.q)
        return replace(sample, qd=still, qdd=still, current=self.motion.currents(sample.q, still))

    def _moving_at(self, t: float) -> bool:
        return self._change_at(t)[2]

    def _set(self, now: float, program_state: Optional[str] = None, robot_mode: Optional[str] = None) -> None:
        was = self.moving
        self.program_state = program_state or self.program_state
        self.robot_mode = robot_mode or self.robot_mode
        if was != self.moving:
            at = max(now, self._changes[-1][0])
            self._changes = self._changes[-KEPT_CHANGES + 1:] + [(at, self.motion_time(at), self.moving)]

    def state_at(self, t: float) -> "Snapshot":
        """What every interface reports at server time t."""
        sample = self.joints(t)
        moving = self._moving_at(t)
        speed = self.motion.tcp_speed(self.motion_time(t)) if moving else (0.0,) * 6
        powered = self.robot_mode != POWER_OFF
        return Snapshot(t=t, q=sample.q, qd=sample.qd, qdd=sample.qdd, current=sample.current,
                        tcp_pose=self.motion.tcp_pose(sample.q), tcp_speed=speed,
                        robot_mode=ROBOT_MODE_CODES[self.robot_mode], safety_mode=SAFETY_NORMAL,
                        program_state=PROGRAM_STATE_CODES[self.program_state],
                        speed_scaling=self.speed_fraction if moving else 0.0,
                        target_speed_fraction=self.speed_fraction, digital_outputs=self.digital_outputs,
                        main_voltage=48.1 if powered else 0.0, robot_voltage=48.0 if powered else 0.0,
                        robot_current=0.9 if powered else 0.0,
                        joint_temperatures=tuple(30.0 + j for j in range(6)),
                        joint_mode=JOINT_RUNNING if self.robot_mode == RUNNING else JOINT_IDLE)

    # ---- what the dashboard changes ------------------------------------------------------------
    def play(self, now: float) -> bool:
        if self.loaded_program is None or self.robot_mode != RUNNING:
            return False
        self._set(now, program_state=PLAYING)
        return True

    def stop(self, now: float) -> bool:
        self._set(now, program_state=STOPPED)
        return True

    def pause(self, now: float) -> bool:
        if self.program_state != PLAYING:
            return False
        self._set(now, program_state=PAUSED)
        return True

    def load(self, now: float, path: str) -> bool:
        """Loads a program file (a .urp; any other path is not found) and stops the one playing."""
        if not path.endswith(".urp"):
            return False
        self._set(now, program_state=STOPPED)
        self.loaded_program = path
        return True

    def set_operational_mode(self, mode: Optional[str]) -> bool:
        """"manual" or "automatic" as the dashboard sets it; None gives it back to the pendant."""
        if mode not in (None, "manual", "automatic"):
            return False
        self.operational_mode = mode.upper() if mode else NO_OPERATIONAL_MODE
        return True

    def power(self, now: float, mode: str) -> None:
        """POWER_OFF (stops the program), IDLE (powered, brakes on) or RUNNING (brakes released)."""
        self._set(now, program_state=STOPPED if mode == POWER_OFF else None, robot_mode=mode)

    @property
    def program_name(self) -> str:
        return (self.loaded_program or "<unnamed>").rsplit("/", 1)[-1]

    # ---- what RTDE inputs change ---------------------------------------------------------------
    def claim_inputs(self, owner: object, names: list) -> list:
        """The names another connection holds; the rest are now `owner`'s."""
        taken = [n for n in names if self.inputs.owners.get(n, owner) is not owner]
        if not taken:
            for name in names:
                self.inputs.owners[name] = owner
        return taken

    def release_inputs(self, owner: object) -> None:
        for name in [n for n, o in self.inputs.owners.items() if o is owner]:
            del self.inputs.owners[name]

    def write_inputs(self, values: dict) -> None:
        """An input data package: masked outputs change only the bits their mask selects."""
        kept = self.inputs.values
        for name, value in values.items():
            if name.endswith("_mask"):
                continue
            if name == "speed_slider_fraction":
                # Bit 0 of the mask: use the fraction. A slider runs from 0 to 1: any other value
                # (NaN too) moves it nowhere, and the speed every interface reports stays.
                if values.get("speed_slider_mask", 1) & 1 and 0.0 <= value <= 1.0:
                    kept[name] = value
                continue
            mask = values.get(f"{name}_mask")
            kept[name] = value if mask is None else (kept.get(name, 0) & ~mask) | (value & mask)

    @property
    def speed_fraction(self) -> float:
        return float(self.inputs.values.get("speed_slider_fraction", 1.0))

    @property
    def digital_outputs(self) -> int:
        return int(self.inputs.values.get("standard_digital_output", 0))
