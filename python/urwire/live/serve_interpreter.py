"""Interpreter mode (30020) as `urwire serve` serves it: one reply line per line, as a program that
called interpreter_mode() answers (spec/ur_interpreter.yaml).

- a statement (any line no interpreter command is) is acknowledged with the next id,
  "ack: <id>: <statement>", and queued; or, when its brackets or quotes do not close (what a
  compile error looks like from here), discarded: "discard: Compile error: <statement>" (the
  reason's wording is the simulator's own: the manual gives none);
- the queue runs on the server's clock: a statement starts when the one before it has ended, a
  sleep(t) lasts t seconds, a move (movej, movel, movep, movec) MOVE_SECONDS, any other none;
- `skipbuffer` drops what has not started, `abort` ends the running move now; both are answered
  in the statement's form with the last id interpreted (the manual says to ignore the reply);
- clear_interpreter() clears what was interpreted before it: statelastcleared tells its id - 1;
- the state queries answer with their reply's `fill` (last_executed, last_interpreted,
  last_cleared, unexecuted), as the dashboard's do.

Which reply answers, and with which robot state, is the spec's: the command's `effect`, else its
first reply that says no error. One interpreter serves the robot, whatever connection sends to it.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Callable, Optional

from .._runtime import StreamError
from ..generated import ur_interpreter as _g
from ..text_lines import CommandSpec, LineSplitter, ReplySpec, find_command

MOVE_SECONDS = 2.0                  # how long a simulated movej, movel, movep or movec lasts
_MOVE = re.compile(r"\s*move[jlpc]\s*\(")
_SLEEP = re.compile(r"\s*sleep\s*\(\s*([0-9.]+)\s*\)\s*$")
_PAIRS = {"(": ")", "[": "]", "{": "}"}


def has_interpreter(version: tuple) -> bool:
    """Whether the software version has interpreter mode (e-Series from 5.10, as its spec says)."""
    return _g.STATEMENT.available(version)


def say_each(reply: ReplySpec, *values: str) -> str:
    """A reply's text: its pattern with each value in its placeholder, in order."""
    out = [reply.pieces[0]]
    for value, piece in zip(values, reply.pieces[1:]):
        out += [value, piece]
    return "".join(out)


def compiles(statement: str) -> bool:
    """Whether the statement's brackets and double quotes close, in order: the one compile error a
    simulator can tell without a URScript compiler."""
    expected: list[str] = []
    quoted = False
    for char in statement:
        if char == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif char in _PAIRS:
            expected.append(_PAIRS[char])
        elif char in _PAIRS.values() and (not expected or expected.pop() != char):
            return False
    return not quoted and not expected


def duration(statement: str) -> float:
    """Seconds the statement runs: a sleep its argument, a move MOVE_SECONDS, anything else none."""
    sleep = _SLEEP.match(statement)
    if sleep:
        try:
            return float(sleep.group(1))
        except ValueError:
            return 0.0
    return MOVE_SECONDS if _MOVE.match(statement) else 0.0


@dataclass
class Interpreter:
    """The robot's interpreter: ids, and the queue of statements interpreted but not yet started."""

    last_interpreted: int = 0
    last_executed: int = 0            # the largest id that has started
    last_cleared: int = 0
    busy_until: float = 0.0           # when the statement running ends
    queue: list = field(default_factory=list)     # (id, seconds, when interpreted) not yet started, oldest first

    def run(self, now: float) -> None:
        """Start every queued statement whose turn has come by `now`: each when the one before it
        has ended, and not before it was interpreted."""
        while self.queue and max(self.busy_until, self.queue[0][2]) <= now:
            number, seconds, at = self.queue.pop(0)
            self.busy_until = max(self.busy_until, at) + seconds
            self.last_executed = number

    def interpret(self, now: float, statement: str) -> Optional[str]:
        """The id the statement gets, or None: it is discarded."""
        if not compiles(statement):
            return None
        self.run(now)
        self.last_interpreted += 1
        if statement.strip().startswith("clear_interpreter("):
            self.last_cleared = self.last_interpreted - 1
        self.queue.append((self.last_interpreted, duration(statement), now))
        self.run(now)
        return str(self.last_interpreted)

    def skip_buffer(self, now: float) -> str:
        self.run(now)
        self.queue.clear()
        return str(self.last_interpreted)

    def abort_motion(self, now: float) -> str:
        self.busy_until = min(self.busy_until, now)
        self.run(now)
        return str(self.last_interpreted)


class InterpreterSession:
    """One client's connection to interpreter mode: lines in, a reply line out for each."""

    def __init__(self, interpreter: Interpreter, clock: Callable[[], float]):
        self.interpreter = interpreter
        self.clock = clock
        self.lines = LineSplitter(_g.MAX_LINE)

    def received(self, data: bytes) -> bytes:
        """The replies to every whole line in `data`; a line too long is discarded once."""
        out = []
        for line in self.lines.feed(data):
            if isinstance(line, StreamError):
                out.append(say_each(_g.COMMON_REPLIES[0], "Line too long", line.error))
            else:
                out.append(self.answer(line[1].decode("utf-8", "replace")))
        return "".join(text + "\n" for text in out).encode()

    def answer(self, line: str) -> str:
        command, argument = find_command(_g.LOOKUP, line)
        assert command is not None          # a statement is any other line
        now = self.clock()
        if command.effect:
            number = _EFFECTS[command.effect](self.interpreter, now, argument or "")
            if number is None:
                return say_each(_g.COMMON_REPLIES[0], "Compile error", line)
            return say_each(_ok(command), number, line)
        self.interpreter.run(now)
        reply = _ok(command)
        parts = list(reply.fill)
        parts[1::2] = [str(_STATES[name](self.interpreter)) for name in parts[1::2]]
        return say_each(reply, "".join(parts))


def _ok(command: CommandSpec) -> ReplySpec:
    """The command's first reply that says no error."""
    return next(r for r in command.replies if not r.error)


# What each `effect` of the spec does: the id its acknowledgement tells, None: it is discarded.
_EFFECTS: dict[str, Callable[[Interpreter, float, str], Optional[str]]] = {
    "interpret": Interpreter.interpret,
    "skip_buffer": lambda i, now, _: i.skip_buffer(now),
    "abort_motion": lambda i, now, _: i.abort_motion(now),
}

# The states a state query's `fill` names.
_STATES: dict[str, Callable[[Interpreter], int]] = {
    "last_executed": lambda i: i.last_executed,
    "last_interpreted": lambda i: i.last_interpreted,
    "last_cleared": lambda i: i.last_cleared,
    "unexecuted": lambda i: len(i.queue),
}
