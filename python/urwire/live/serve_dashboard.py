"""The dashboard server (29999) as `urwire serve` serves it: the banner, then one reply line per
command line, for the commands the served software version has; any other line gets the server's
"could not understand" reply. Every answer comes from the dashboard spec, through one routine
(`DashboardSession.answer`) and no code per command:

- a command's `effect` (spec/ur_dashboard.yaml) is what it does to the one robot every interface
  reports (load, play, stop, pause, power on/off, brake release, the operational mode, quit);
  one that fails (a load of no .urp, a play with nothing loaded or the arm not running) answers
  with the command's first error reply;
- otherwise the answer is the first reply that says no error, whose `when` holds and whose
  `fill` has every robot state it names; none: the first error reply (`get loaded program` with
  none loaded). The reply's placeholder takes its `fill`, each {name} in it a value of _STATES.

Lines are split as the decoder splits them (text_lines.LineSplitter): a line longer than the
spec's limit gets one "could not understand" reply that names the fault, and none of its bytes,
up to its newline, are ever read as a command.
"""
from __future__ import annotations

from typing import Callable, Optional

from .._runtime import StreamError
from ..generated import ur_dashboard as _g
from ..text_lines import LineSplitter, ReplySpec, find_command
from .robot_cell import BUILD_DATE, BUILD_NUMBER, IDLE, PLAYING, POWER_OFF, RUNNING, RobotCell


def say(reply: ReplySpec, value: str = "") -> str:
    """A reply's text: its pattern with `value` in each placeholder."""
    return value.join(reply.pieces)


def software_version(version: tuple) -> str:
    """"5.11.0.108318": the version and build the dashboard's version replies tell."""
    return ".".join(map(str, version)) + f".{BUILD_NUMBER}"


class DashboardSession:
    """One client's dashboard connection: lines in, a reply line out for each."""

    def __init__(self, cell: RobotCell, clock: Callable[[], float]):
        self.cell = cell
        self.clock = clock
        self.lines = LineSplitter(_g.MAX_LINE)
        self.closing = False                     # after `quit`: the reply is sent, then the connection closed

    def banner(self) -> bytes:
        return (say(_g.BANNER) + "\n").encode()

    def received(self, data: bytes) -> bytes:
        """The replies to every whole line in `data`, and to a line too long as soon as it is
        (its rest, up to its newline, is dropped)."""
        out = []
        for line in self.lines.feed(data):
            if self.closing:
                break
            if isinstance(line, StreamError):
                out.append(say(_g.COMMON_REPLIES[0], line.error) + "\n")
            else:
                out.append(self.answer(line[1].decode("utf-8", "replace")) + "\n")
        return "".join(out).encode()

    def answer(self, line: str) -> str:
        command, argument = find_command(_g.LOOKUP, line)
        if command is None or not command.available(self.cell.version):
            return say(_g.COMMON_REPLIES[0], line)
        argument = argument or ""
        done = _EFFECTS[command.effect](self, argument) if command.effect else True
        if done:
            for reply in command.replies:
                text = None if reply.error else self.filled(reply, argument)
                if text is not None:
                    return text
        reply = next((r for r in command.replies if r.error), command.replies[0])
        return self.filled(reply, argument) or say(reply)

    def filled(self, reply: ReplySpec, argument: str) -> Optional[str]:
        """The reply's text, or None when a robot state its `when` names has another value or one
        its `fill` names has none."""
        if any(_STATES[state](self, argument) != value for state, value in reply.when):
            return None
        parts = list(reply.fill)
        parts[1::2] = [_STATES[name](self, argument) for name in parts[1::2]]
        return None if None in parts else say(reply, "".join(parts))

    def close_connection(self, _) -> bool:
        self.closing = True
        return True

    def power(self, mode: str) -> bool:
        self.cell.power(self.clock(), mode)
        return True


# What each `effect` of the spec does; False: it failed, and the command's first error reply answers.
_EFFECTS: dict[str, Callable[[DashboardSession, str], bool]] = {
    "load_program": lambda s, path: s.cell.load(s.clock(), path),
    "play": lambda s, _: s.cell.play(s.clock()),
    "stop": lambda s, _: s.cell.stop(s.clock()),
    "pause": lambda s, _: s.cell.pause(s.clock()),
    "power_on": lambda s, _: s.power(IDLE),
    "power_off": lambda s, _: s.power(POWER_OFF),
    "brake_release": lambda s, _: s.power(RUNNING),
    "close_connection": DashboardSession.close_connection,
    "add_to_log": lambda s, text: bool(text),
    "set_operational_mode": lambda s, mode: s.cell.set_operational_mode(mode),
    "clear_operational_mode": lambda s, _: s.cell.set_operational_mode(None),
}

# The robot states a reply's `fill` and `when` name: their texts, None for a state with no value.
_STATES: dict[str, Callable[[DashboardSession, str], Optional[str]]] = {
    "argument": lambda s, argument: argument,
    "program_state": lambda s, _: s.cell.program_state,
    "program_running": lambda s, _: str(s.cell.program_state == PLAYING).lower(),
    "program_name": lambda s, _: s.cell.program_name,
    "loaded_program": lambda s, _: s.cell.loaded_program,
    "robot_mode": lambda s, _: s.cell.robot_mode,
    "software_version": lambda s, _: software_version(s.cell.version),
    "build_date": lambda s, _: BUILD_DATE,
    "serial_number": lambda s, _: s.cell.serial,
    "robot_model": lambda s, _: s.cell.model.name.upper().rstrip("E"),
    "operational_mode": lambda s, _: s.cell.operational_mode,
}

