"""The Robotiq gripper URCap's socket (63352) as `urwire serve` serves it: a 2F-85 gripper behind
the GET and SET lines of spec/robotiq_gripper.yaml, one reply line per line.

- `SET <VAR> <value> ...` (the command's `effect: set_variables`) writes ACT, GTO, ATR, ARD, POS,
  SPE and FOR (0 to 255) and is acknowledged with its first reply that says no error (`ack`);
  a pair with another name or a value out of range is not written;
- `GET <VAR>` answers its reply that says no error, `<VAR> <value>`, for every variable the
  clients read: STA (0 reset, 1 activating for ACTIVATION_SECONDS after ACT goes to 1, then 3
  active), PRE (the position requested by the last GTO 1), POS (the fingers, moving toward PRE
  at SPE's speed), OBJ (0 moving, 2 stopped at the part between the fingers while closing,
  3 at the position requested), FLT (7 while a GTO 1 waits for activation, else 0), and the
  written ones;
- a line that is neither, or a GET of no variable, gets "?": no source gives the URCap's answer.

A part OBJECT_AT wide sits between the fingers: closing past it stops there with OBJ 2, as a
grasp does. One gripper serves the robot, whatever connection sends to it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

from .._runtime import StreamError
from ..generated import robotiq_gripper as _g
from ..text_lines import LineSplitter, find_command
from .serve_interpreter import say_each

ACTIVATION_SECONDS = 0.5           # STA reads 1 (activating) this long after ACT goes to 1
OBJECT_AT = 227                    # where closing fingers meet the part (0 open, 255 closed)
# A 2F-85's fingers travel 85 mm at 20 to 150 mm/s as SPE goes from 0 to 255: in position units
# (255 for the whole stroke) per second.
SLOWEST, FASTEST = 20 * 255 / 85, 150 * 255 / 85
WRITTEN = ("ACT", "GTO", "ATR", "ARD", "POS", "SPE", "FOR")
UNKNOWN = "?"
MOVING, STOPPED_OPENING, STOPPED_CLOSING, AT_POSITION = 0, 1, 2, 3
NO_FAULT, ACTIVATE_FIRST = 0, 7


def has_gripper(version: tuple) -> bool:
    """Whether the software version runs the gripper's URCap (CB3 from 3.3, every e-Series)."""
    return _g.GET.available(version)


@dataclass
class Gripper:
    """The gripper: what clients wrote, and its fingers' motion on the server's clock."""

    written: dict = field(default_factory=lambda: dict.fromkeys(WRITTEN, 0))
    activated_at: Optional[float] = None     # when ACT last went to 1
    position: float = 0.0                    # the fingers, 0 open to 255 closed
    requested: int = 0                       # PRE: the position of the last GTO 1
    moved_at: float = 0.0                    # when `position` was last brought up to date
    fault: int = NO_FAULT

    def status(self, now: float) -> int:
        if self.activated_at is None:
            return 0
        return 1 if now - self.activated_at < ACTIVATION_SECONDS else 3

    def target(self) -> float:
        """Where the fingers stop: the position requested, or the part when closing onto it."""
        closing = self.requested > self.position
        return min(self.requested, OBJECT_AT) if closing and self.position <= OBJECT_AT else self.requested

    def move(self, now: float) -> None:
        """Bring the fingers up to `now`: toward their target at SPE's speed, while GTO is 1 and the
        gripper active."""
        if self.written["GTO"] and self.status(now) == 3:
            start = max(self.moved_at, self.activated_at + ACTIVATION_SECONDS)
            step = (SLOWEST + (FASTEST - SLOWEST) * self.written["SPE"] / 255) * max(0.0, now - start)
            target = self.target()
            self.position = min(target, self.position + step) if target > self.position else \
                max(target, self.position - step)
        self.moved_at = now

    def set(self, now: float, assignments: str) -> bool:
        self.move(now)
        words = assignments.split()
        for name, value in zip(words[::2], words[1::2]):
            if name in WRITTEN and value.isdigit() and int(value) <= 255:
                self.write(now, name, int(value))
        return True

    def write(self, now: float, name: str, value: int) -> None:
        if name == "ACT" and value != self.written["ACT"]:
            self.activated_at = now if value else None
            self.fault = NO_FAULT
        self.written[name] = value
        if name == "GTO" and value:
            self.requested = self.written["POS"]
            self.fault = NO_FAULT if self.status(now) == 3 else ACTIVATE_FIRST

    def read(self, now: float, name: str) -> Optional[int]:
        self.move(now)
        values = {"STA": self.status(now), "PRE": self.requested, "FLT": self.fault,
                  "OBJ": self.object_status(now), "POS": round(self.position)}
        return values.get(name, self.written.get(name))

    def object_status(self, now: float) -> int:
        """OBJ: moving toward the target, stopped at the part, or at the position requested (also
        when no GTO 1 moves the fingers)."""
        if not self.written["GTO"] or self.status(now) != 3:
            return AT_POSITION
        if round(self.position) != round(self.target()):
            return MOVING
        return STOPPED_CLOSING if self.target() != self.requested else AT_POSITION


class GripperSession:
    """One client's connection to the gripper's socket: lines in, a reply line out for each."""

    def __init__(self, gripper: Gripper, clock: Callable[[], float]):
        self.gripper = gripper
        self.clock = clock
        self.lines = LineSplitter(_g.MAX_LINE)

    def received(self, data: bytes) -> bytes:
        out = []
        for line in self.lines.feed(data):
            out.append(UNKNOWN if isinstance(line, StreamError) else self.answer(line[1].decode("utf-8", "replace")))
        return "".join(text + "\n" for text in out).encode()

    def answer(self, line: str) -> str:
        command, argument = find_command(_g.LOOKUP, line)
        if command is None or not argument:
            return UNKNOWN
        reply = next(r for r in command.replies if not r.error)
        if command.effect:
            _EFFECTS[command.effect](self.gripper, self.clock(), argument)
            return say_each(reply)
        value = self.gripper.read(self.clock(), argument)
        return UNKNOWN if value is None else say_each(reply, argument, str(value))


# What each `effect` of the spec does to the gripper.
_EFFECTS: dict[str, Callable[[Gripper, float, str], bool]] = {
    "set_variables": Gripper.set,
}
