"""The real-time interface (30003) as `urwire serve` serves it: one fixed packet per period, in
the layout the served software version sends (the spec's FORMS_BY_SIZE), at the generation's rate:
125 Hz on CB2 and CB3, 500 Hz on e-Series and PolyScope X (UR's "Remote Control Via TCP/IP"
article). Packets are on one grid of the server's clock, so every client gets the same packet for
the same period, and each packet is built once however many clients read it.
"""
from __future__ import annotations

import asyncio
import dataclasses
from typing import Optional

from ..generated import ur_realtime as _g
from ..realtime import version_number
from .robot_cell import RobotCell, Snapshot
from .robot_models import CB2, CB3, generation

RATE = {CB2: 125.0, CB3: 125.0}
E_SERIES_RATE = 500.0


def rate_of(version: tuple) -> float:
    return RATE.get(generation(version), E_SERIES_RATE)


def form_for(version: tuple) -> tuple:
    """(low, high, class, enum name tables) of the layout a controller of `version` sends."""
    number = version_number(version)
    held = [form for forms in _g.FORMS_BY_SIZE.values() for form in forms if form[0] <= number <= form[1]]
    if not held:
        raise ValueError(f"no real-time layout for software {'.'.join(map(str, version))}")
    return held[-1]


def _code(names: dict, name: str, fallback: int) -> float:
    """A mode's code in the layout's own table (CB2's robot modes are numbered apart from 3.0's)."""
    return float(next((code for code, n in names.items() if n == name), fallback))


class RealtimePackets:
    """The packets of one robot, by period number on the server's clock."""

    def __init__(self, cell: RobotCell):
        self.cell = cell
        self.rate = rate_of(cell.version)
        _, _, self.cls, self.names = form_for(cell.version)
        zero = _g.SIZE_FIELD.pack(self.cls.SIZE) + bytes(self.cls.SIZE - _g.SIZE_FIELD_BYTES)
        self.blank = self.cls.decode(zero, 0)
        self.fields = {f.name for f in dataclasses.fields(self.cls)}
        self._last: tuple[int, bytes] = (-1, b"")

    def packet(self, period: int) -> bytes:
        if self._last[0] != period:
            self._last = (period, self.build(self.cell.state_at(period / self.rate)).encode())
        return self._last[1]

    def build(self, s: Snapshot):
        six = lambda value: (float(value),) * 6   # noqa: E731 (one value for each joint)
        values = {
            "time": s.t, "controller_timer": s.t,
            "q_target": s.q, "q_actual": s.q, "qd_target": s.qd, "qd_actual": s.qd, "qdd_target": s.qdd,
            "i_target": s.current, "i_actual": s.current, "i_control": s.current,
            "tool_vector_actual": s.tcp_pose, "tool_vector_target": s.tcp_pose,
            "tcp_speed_actual": s.tcp_speed, "tcp_speed_target": s.tcp_speed,
            "motor_temperatures": s.joint_temperatures,
            "robot_mode": _code(self.names.get("robot_mode", {}), self.cell.robot_mode, s.robot_mode),
            "joint_modes": six(_code(self.names.get("joint_mode", {}), "RUNNING" if s.joint_mode == 253 else "IDLE",
                                     s.joint_mode)),
            "safety_mode": float(s.safety_mode), "speed_scaling": s.speed_scaling,
            "target_speed_fraction": s.target_speed_fraction,
            "v_main": s.main_voltage, "v_robot": s.robot_voltage, "i_robot": s.robot_current,
            "v_actual": six(s.robot_voltage), "digital_outputs": float(s.digital_outputs),
            "program_state": float(s.program_state),
        }
        return dataclasses.replace(self.blank, **{k: _fit(v) for k, v in values.items() if k in self.fields})


def _fit(value):
    return tuple(float(v) for v in value) if isinstance(value, (tuple, list)) else float(value)


class RealtimeSession:
    """One client: a packet each period from the next one on; what the client sends (URScript) is
    read and ignored, as `urwire serve` does not run programs."""

    def __init__(self, packets: RealtimePackets, clock, send):
        self.packets = packets
        self.clock = clock
        self.send = send

    async def run(self, closing) -> None:
        rate = self.packets.rate
        period: Optional[int] = None
        while not closing():
            now = self.clock()
            due = int(now * rate)
            period = due if period is None or due - period > rate else period   # a slow client skips ahead
            while period <= due:
                if not self.send(self.packets.packet(period)):
                    return
                period += 1
            await asyncio.sleep(max(0.0, period / rate - self.clock()))
