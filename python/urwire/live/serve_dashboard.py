"""The dashboard server (29999) as `urwire serve` serves it: the banner, then one reply line per
command line, with the replies' texts as the dashboard spec gives them (UR's dashboard server
articles), for the commands the served software version has; any other line gets the server's
"could not understand" reply. Commands that change the robot (load, play, stop, pause, power
on/off, brake release) change the one robot every interface reports.

Lines are split as the decoder splits them (text_lines.LineSplitter): a line longer than the
spec's limit gets one "could not understand" reply that names the fault, and none of its bytes,
up to its newline, are ever read as a command.
"""
from __future__ import annotations

from typing import Callable

from .._runtime import StreamError
from ..generated import ur_dashboard as _g
from ..text_lines import LineSplitter, ReplySpec, find_command
from .robot_cell import BUILD_DATE, BUILD_NUMBER, IDLE, PAUSED, PLAYING, POWER_OFF, RUNNING, RobotCell


def say(reply: ReplySpec, value: str = "") -> str:
    """A reply's text: its pattern with `value` in its placeholder (patterns have at most one)."""
    return value.join(reply.pieces) if len(reply.pieces) > 1 else reply.pieces[0]


def reply_named(command, name: str) -> ReplySpec:
    return next(r for r in command.replies if r.name == name)


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
        name, value = _HANDLERS[command.name](self, argument or "")
        return say(reply_named(command, name), value)

    # ---- one command each; each returns (reply name, the text in its placeholder) ---------------
    def load(self, path: str):
        if not path.endswith(".urp"):
            return "file_not_found", path
        self.cell.load(self.clock(), path)
        return "loading_program", path

    def play(self, _):
        return ("starting_program", "") if self.cell.play(self.clock()) else ("failed", "")

    def stop(self, _):
        return ("stopped", "") if self.cell.stop(self.clock()) else ("failed", "")

    def pause(self, _):
        return ("pausing_program", "") if self.cell.pause(self.clock()) else ("failed", "")

    def quit(self, _):
        self.closing = True
        return "disconnected", ""

    def running(self, _):
        return "program_running", str(self.cell.program_state == PLAYING).lower()

    def robotmode(self, _):
        return "robotmode", self.cell.robot_mode

    def loaded_program(self, _):
        if self.cell.loaded_program is None:
            return "no_program_loaded", ""
        return "loaded_program", self.cell.loaded_program

    def program_state(self, _):
        name = {PLAYING: "playing", PAUSED: "paused"}.get(self.cell.program_state, "stopped")
        return name, self.cell.program_name

    def polyscope_version(self, _):
        return "version", f"{self.version_text()} ({BUILD_DATE})"

    def version(self, _):
        return "version", self.version_text()

    def version_text(self) -> str:
        return ".".join(map(str, self.cell.version)) + f".{BUILD_NUMBER}"

    def power(self, mode: str) -> Callable:
        def handler(_):
            self.cell.power(self.clock(), mode)
            return {POWER_OFF: "powering_off", IDLE: "powering_on", RUNNING: "brake_releasing"}[mode], ""
        return handler

    def add_to_log(self, text: str):
        return ("added_log_message", "") if text else ("no_log_message", "")

    def operational_mode(self, mode: str):
        if mode not in ("manual", "automatic"):
            return "failed", mode
        return "mode_set", f"'{mode}'"

    def robot_model(self, _):
        return "robot_model", self.cell.model.name.upper().rstrip("E")


def _fixed(name: str, value: str = "") -> Callable:
    return lambda session, argument: (name, value)


def _echo(name: str) -> Callable:
    return lambda session, argument: (name, argument)


_HANDLERS: dict[str, Callable] = {
    "load": DashboardSession.load, "play": DashboardSession.play, "stop": DashboardSession.stop,
    "pause": DashboardSession.pause, "quit": DashboardSession.quit,
    "shutdown": _fixed("shutting_down"),             # the simulated controller keeps running
    "running": DashboardSession.running, "robotmode": DashboardSession.robotmode,
    "get_loaded_program": DashboardSession.loaded_program,
    "popup": _fixed("showing_popup"), "close_popup": _fixed("closing_popup"),
    "add_to_log": DashboardSession.add_to_log,
    "is_program_saved": lambda s, a: ("saved", s.cell.program_name),
    "program_state": DashboardSession.program_state,
    "polyscope_version": DashboardSession.polyscope_version, "version": DashboardSession.version,
    "set_user_role": _echo("setting_user_role"), "get_user_role": _fixed("role", "PROGRAMMER"),
    "set_operational_mode": DashboardSession.operational_mode,
    "get_operational_mode": _fixed("mode", "NONE"),
    "clear_operational_mode": _fixed("cleared", "Current operational mode: 'NONE'."),
    "power_on": lambda s, a: s.power(IDLE)(a), "power_off": lambda s, a: s.power(POWER_OFF)(a),
    "brake_release": lambda s, a: s.power(RUNNING)(a),
    "safetymode": _fixed("safetymode", "NORMAL"), "safetystatus": _fixed("safetystatus", "NORMAL"),
    "unlock_protective_stop": _fixed("releasing"), "close_safety_popup": _fixed("closing_safety_popup"),
    "load_installation": _echo("loading_installation"), "restart_safety": _fixed("restarting_safety"),
    "is_in_remote_control": _fixed("remote"),
    "get_serial_number": lambda s, a: ("serial_number", s.cell.serial),
    "get_robot_model": DashboardSession.robot_model,
    "generate_flight_report": _fixed("generating", "1764115200"),
    "generate_support_file": lambda s, a: ("completed", f"{a.rstrip('/')}/ur_{s.cell.serial}_support_file.zip"),
    "save_log": _fixed("log_saved"),
}

