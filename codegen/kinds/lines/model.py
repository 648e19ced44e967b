"""The IR of a text-line interface (the dashboard server): its commands, their replies and the
versions that have them, as plain objects every target renders; and what a simulated robot
(`urwire serve`) does on each command and answers, which only the Python target carries."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir, series

# What a command may do to the simulated robot (`effect:`); `urwire serve` does each, and those
# that can fail (a load of no .urp, a play with nothing to play) answer with the command's first
# error reply.
EFFECTS = ("load_program", "play", "stop", "pause", "power_on", "power_off", "brake_release",
           "close_connection", "add_to_log", "set_operational_mode", "clear_operational_mode",
           # interpreter mode: a statement interpreted (acknowledged with its id), the buffer skipped,
           # the running motion aborted; the Robotiq gripper: variables set
           "interpret", "skip_buffer", "abort_motion", "set_variables")
# The values of the simulated robot a reply's `fill:` text names as {name}, and its `when:` tests;
# `argument` is the command's argument.
ROBOT_STATES = ("argument", "program_state", "program_running", "program_name", "loaded_program", "robot_mode",
                "software_version", "build_date", "serial_number", "robot_model", "operational_mode",
                # interpreter mode: the ids its state queries tell, and the statements not yet executed
                "last_executed", "last_interpreted", "last_cleared", "unexecuted")


@dataclass(frozen=True)
class Reply:
    name: str
    pattern: str                 # literal text, each <name> standing for any text
    pieces: tuple[str, ...]      # the literal text between the placeholders (one piece: no placeholder)
    error: bool
    doc: str
    where: ir.Where
    fill: Optional[str] = None   # what the simulated robot puts in the placeholder; {name}: a robot state
    fill_parts: tuple[str, ...] = ()          # the fill split: literal text and state names, alternately
    when: tuple[tuple[str, str], ...] = ()   # (robot state, value) pairs that must hold for it to answer


@dataclass(frozen=True)
class Command:
    name: str
    text: str                    # the words that open the line; "": any line no other command is
    argument: Optional[str]      # what the text after the words is, when the command takes one
    since_cb: Optional[ir.Version]        # first CB2/CB3 version with the command; None: none has it
    since_e_series: Optional[ir.Version]  # first e-Series (5.x) version; None: none has it
    since_polyscope_x: Optional[ir.Version]  # first PolyScope X (10.x) version (codegen/series.py); None: none
    every_version: bool                   # no `since:`: every version has it
    doc: str
    replies: tuple[Reply, ...]
    where: ir.Where
    effect: Optional[str] = None          # what it does to the simulated robot (EFFECTS)

    @property
    def catch_all(self) -> bool:
        """A command with no text (interpreter mode's statement): any line no other command is, the
        whole line its argument. The longest text is tried first, so it is tried last."""
        return not self.text

    @property
    def heading(self) -> str:
        """What opens the command's line, for comments: its text, or that it is any other line."""
        return self.text or "any other line"

    def since_text(self) -> str:
        """"CB 1.4, e-Series 5.0": where and from when the command exists, for comments."""
        if self.every_version:
            return "every version"
        parts = [f"CB {ir.version_text(self.since_cb)}"] if self.since_cb else []
        parts += [f"e-Series {ir.version_text(self.since_e_series)}"] if self.since_e_series else []
        # PolyScope X is named only where it does not simply follow the e-Series.
        if self.since_polyscope_x != (series.POLYSCOPE_X_FROM if self.since_e_series else None):
            parts.append(f"PolyScope X {ir.version_text(self.since_polyscope_x)}" if self.since_polyscope_x
                         else "not PolyScope X")
        return ", ".join(parts)


@dataclass(frozen=True)
class RecordField:
    name: str
    label: str
    doc: str


@dataclass(frozen=True)
class LinesProtocol:
    name: str
    title: str
    doc: str
    ports: tuple[int, ...]
    max_line: int
    banner: Optional[Reply]              # the line the server greets a client with, if any
    robot_is_client: bool                # the robot connects to the port (the driver's sockets)
    requests_from_robot: bool            # the robot asks and the other side answers (script sender)
    one_reply_per_request: bool          # else every answering line belongs to the latest request
    version_command: Optional[str]       # the command whose reply tells the software version
    version_prefix: str                  # the reply's text before the version
    fields: dict[str, RecordField]
    common_replies: tuple[Reply, ...]
    commands: tuple[Command, ...]

    E_SERIES_MAJOR = 5                   # software 5.x is the e-Series' line of versions, 10.x PolyScope X's
