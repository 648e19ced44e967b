"""The runtime of a text-line interface (the dashboard server, generated/.../ur_dashboard.py):
lines split per direction, commands looked up, replies paired with their commands and read
against their patterns, the software version learnt from its reply.

The generated module gives the tables (COMMANDS, LOOKUP, COMMON_REPLIES, BANNER, MAX_LINE, the
version reply) and the record classes; this module is the same for any such interface.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from types import ModuleType
from typing import Optional

from ._runtime import StreamError
from .arguments import parse_version

Version = tuple[int, int, int]
PENDING_KEPT = 256   # commands awaiting a reply; a client that never reads cannot grow it further
# Reading a client's whole raw file before the server's, every command of the session awaits its
# reply at once: raw files keep this many (references, a few MiB) before one is not kept.
PENDING_KEPT_RAW = 1 << 20


def not_kept(kept: int) -> str:
    return f"command not kept: more than {kept} commands awaited replies"


def reply_not_kept(kept: int) -> str:
    return f"reply to a command that was not kept: more than {kept} commands awaited replies"


# The first line after a gap: the gap may have ended inside a line ("popup power off" may show as
# "power off"), so the line is decoded but not taken for a whole one.
LINE_AFTER_GAP = "line after bytes lost from the capture: its start may be lost"


def reply_unknown(request: str) -> str:
    return f"reply after bytes lost from the capture: its {request} is unknown"


@dataclass(frozen=True)
class ReplySpec:
    name: str
    pieces: tuple[str, ...]   # literal text around each placeholder of the pattern
    error: bool
    # What a simulated robot (`urwire serve`) answers with the reply: the text of its placeholder,
    # literal text and robot state names alternately ("{a} ({b})": "", "a", " (", "b", ")"), and the
    # (state, value) pairs that must hold.
    fill: tuple[str, ...] = ()
    when: tuple[tuple[str, str], ...] = ()


@dataclass(frozen=True)
class CommandSpec:
    name: str
    text: str
    takes_argument: bool
    since_cb: Optional[Version]
    since_e_series: Optional[Version]
    since_polyscope_x: Optional[Version]
    series_from: tuple[Version, Version]   # the first versions read from since_e_series and since_polyscope_x
    replies: tuple[ReplySpec, ...]
    effect: Optional[str] = None      # what the command does to a simulated robot (`urwire serve`)

    def available(self, version: Version) -> bool:
        e_series_from, polyscope_x_from = self.series_from
        since = self.since_polyscope_x if version >= polyscope_x_from else \
            self.since_e_series if version >= e_series_from else self.since_cb
        return since is not None and version >= since


def matches(pieces: tuple[str, ...], text: str) -> bool:
    """Whether the whole text is the pattern: its first piece opens it, its last ends it, the
    others follow in order between them, and each placeholder takes any text."""
    if len(pieces) == 1:
        return text == pieces[0]
    first, last = pieces[0], pieces[-1]
    if len(text) < len(first) + len(last) or not text.startswith(first) or not text.endswith(last):
        return False
    at, end = len(first), len(text) - len(last)
    for piece in pieces[1:-1]:
        found = text.find(piece, at, end)
        if found < 0:
            return False
        at = found + len(piece)
    return True


def find_command(lookup: tuple[CommandSpec, ...], text: str) -> tuple[Optional[CommandSpec], Optional[str]]:
    """The command a line is and its argument (None when it has none), or (None, None). A command
    with no text (interpreter mode's statement), tried last, is any line, its argument the whole."""
    for command in lookup:
        if not command.text:
            return command, text
        if text == command.text:
            return command, None
        if command.takes_argument and text.startswith(command.text + " "):
            return command, text[len(command.text) + 1:]
    return None, None


def classify(common: tuple[ReplySpec, ...], command: Optional[CommandSpec], text: str) -> Optional[ReplySpec]:
    """The reply a line is: a common reply first, then one of the command's own."""
    for reply in common + (command.replies if command else ()):
        if matches(reply.pieces, text):
            return reply
    return None


def version_in(text: str, prefix: str) -> Optional[Version]:
    """The software version a version reply tells: "URSoftware 5.11.1.108318 (...)" -> (5, 11, 1);
    the word after the prefix, split at its dots, whose first two or three parts are 1 to 3 digits."""
    if not text.startswith(prefix):
        return None
    parts = text[len(prefix):].split(" ", 1)[0].split(".")[:3]
    if len(parts) < 2 or not all(_is_number(p) for p in parts):
        return None
    numbers = [int(p) for p in parts] + [0]
    return numbers[0], numbers[1], numbers[2]


def _is_number(part: str) -> bool:
    return 1 <= len(part) <= 3 and part.isascii() and part.isdigit()


class LineSplitter:
    """One direction's bytes -> (offset, text) lines; a line over max_line bytes is an error."""

    def __init__(self, max_line: int):
        self.max_line = max_line
        self.buffer = bytearray()
        self.offset = 0            # stream offset of buffer[0]
        self.skipping = False      # inside a line too long, dropped up to its newline

    def feed(self, data: bytes) -> list:
        self.buffer += data
        out: list = []
        start = 0
        while True:
            end = self.buffer.find(b"\n", start)
            if end < 0:
                break
            if self.skipping:
                self.skipping = False
            elif end - start > self.max_line + (1 if self.buffer[end - 1:end] == b"\r" else 0):
                out.append(self._too_long(self.offset + start))
            else:
                line = bytes(self.buffer[start:end])
                out.append((self.offset + start, line[:-1] if line.endswith(b"\r") else line))
            start = end + 1
        if not self.skipping and len(self.buffer) - start > self.max_line + 1:
            out.append(self._too_long(self.offset + start))
            self.skipping = True
        if self.skipping:
            start = len(self.buffer)
        del self.buffer[:start]
        self.offset += start
        return out

    def _too_long(self, offset: int) -> StreamError:
        return StreamError(offset, f"line longer than {self.max_line} bytes")

    def close(self) -> list:
        left, at = len(self.buffer), self.offset
        self.buffer.clear()
        self.offset += left
        if left and not self.skipping:
            return [StreamError(at, f"{left} bytes without a newline at the end of the stream")]
        return []

    def restart(self, offset: int) -> list:
        """The stream lost bytes: the line they cut is given up (close()'s record), and lines are
        split afresh from stream offset `offset`."""
        out = self.close()
        self.offset = offset
        self.skipping = False
        return out


NOT_KEPT, UNKNOWN = "not kept", "unknown"      # why a request or reply pairs with none


class Pending:
    """Requests awaiting their replies, oldest first, at most `limit` of them. A request that
    comes when the queue is full is not kept but counted as lost, and so is every request after
    it while lost ones are ahead of it (replies come in order); a reply that comes when none is
    kept but some are lost answers a lost one. So no reply is ever paired with another request.

    Bytes lost from a capture make the count of lost requests unknown (`unknown`), for good: no
    byte after a gap tells how many requests or replies it swallowed, and a client may send its
    next request before the last reply, so no later moment is known to have none awaiting."""

    def __init__(self, limit: int = PENDING_KEPT):
        self.limit = limit
        self.kept: deque = deque()
        self.lost = 0
        self.unknown = False

    def __len__(self) -> int:
        return len(self.kept)

    def push(self, request) -> Optional[str]:
        """None when the request is kept, else why not: `NOT_KEPT` (the queue is full, or one not
        kept is ahead), which its record says, or `UNKNOWN` (after a gap), which the gap's says."""
        if self.unknown or self.lost or len(self.kept) >= self.limit:
            self.lost += 1
            return UNKNOWN if self.unknown else NOT_KEPT
        self.kept.append(request)
        return None

    def pop(self) -> tuple:
        """(the request the next reply answers or None, why it pairs with none: None when it
        pairs, or none was asked, else `NOT_KEPT` or `UNKNOWN`)."""
        if self.kept:
            return self.kept.popleft(), None
        if self.unknown:
            return None, UNKNOWN
        if self.lost:
            self.lost -= 1
            return None, NOT_KEPT
        return None, None

    def requests_lost(self) -> None:
        """The capture lost bytes of the requests: those kept came before them and keep their
        replies, which come first; every later request is behind an unknown number of lost ones."""
        self.unknown = True

    def replies_lost(self) -> None:
        """The capture lost bytes of the replies: how many of the awaiting requests they answered
        is unknown, unless none awaited (bytes sent then answer nothing)."""
        if self.kept or self.lost:
            self.kept.clear()
            self.unknown = True


class Latest:
    """Where every answering line belongs to the latest request: only that one is kept. Bytes
    lost from the requests may have held a later one: until a request comes after them, an
    answering line's request is unknown. Bytes lost from the answers change nothing."""

    limit = 1

    def __init__(self):
        self.command = None
        self.any = False
        self.unknown = False

    def __len__(self) -> int:
        return int(self.any)

    def push(self, command) -> Optional[str]:
        self.command, self.any, self.unknown = command, True, False
        return None

    def pop(self) -> tuple:
        return (None, UNKNOWN) if self.unknown else (self.command, None)

    def requests_lost(self) -> None:
        self.command, self.unknown = None, True

    def replies_lost(self) -> None:
        pass


class LinesConversation:
    """One TCP connection of a text-line interface: `feed(data, from_robot)` -> records in order."""

    def __init__(self, tables: ModuleType, version_hint=None):
        self.tables = tables
        self.version: Optional[Version] = parse_version(version_hint) if version_hint is not None else None
        self.commands = LineSplitter(tables.MAX_LINE)
        self.replies = LineSplitter(tables.MAX_LINE)
        self.pending = Pending() if tables.ONE_REPLY_PER_REQUEST else Latest()
        self.greeted = False
        self.cut = {True: False, False: False}      # by direction: the next line follows a gap

    def feed(self, data: bytes, from_robot: bool) -> list:
        requests = from_robot == self.tables.REQUESTS_FROM_ROBOT
        lines = (self.commands if requests else self.replies).feed(data)
        read = self._command if requests else self._reply
        out = []
        for line in lines:
            if isinstance(line, StreamError):
                out.append(self._too_long(line, requests))
            else:
                out.append(read(line[1], self.cut[from_robot]))
            self.cut[from_robot] = False
        return out

    def close(self, from_robot: Optional[bool] = None) -> list:
        """A line cut short at the end of one direction's stream (both, to_robot's first, as the C
        decoder reports them, when from_robot is None)."""
        if from_robot is None:
            return self.close(False) + self.close(True)
        return self._lines(from_robot).close()

    def lost(self, from_robot: bool, offset: int) -> list:
        """Bytes of one direction are missing before `offset`: the line they cut is given up, and
        that direction's lines are split afresh from there; the requests they may have held, or
        answered, leave the pairing unknown (Pending)."""
        self.cut[from_robot] = True
        if from_robot == self.tables.REQUESTS_FROM_ROBOT:
            self.pending.requests_lost()
        else:
            self.pending.replies_lost()
        return self._lines(from_robot).restart(offset)

    def _lines(self, from_robot: bool) -> "_Lines":
        return self.commands if from_robot == self.tables.REQUESTS_FROM_ROBOT else self.replies

    def keep_pending(self, limit: int) -> None:
        """Keep up to `limit` commands awaiting replies (raw files: PENDING_KEPT_RAW), before any."""
        if isinstance(self.pending, Pending):
            self.pending.limit = limit

    def _too_long(self, error: StreamError, requests: bool) -> StreamError:
        """A line too long is still a line: a command that the server answers, or the reply to
        the oldest one, so the pairing of the lines after it holds."""
        if requests:
            self.pending.push(None)
        else:
            self.greeted = True
            self.pending.pop()
        return error

    def _command(self, raw: bytes, cut: bool = False):
        t = self.tables
        text = raw.decode("utf-8", "surrogateescape")
        command, argument = find_command(t.LOOKUP, text)
        error = not_kept(self.pending.limit) if self.pending.push(command) == NOT_KEPT else None
        error = LINE_AFTER_GAP if cut else error
        if command is None:
            return t.Command(text, error=error)
        available = None if self.version is None else command.available(self.version)
        return t.Command(text, command.name, argument, available, error)

    def _reply(self, raw: bytes, cut: bool = False):
        t = self.tables
        text = raw.decode("utf-8", "surrogateescape")
        if not self.greeted:
            self.greeted = True
            if t.BANNER is not None and matches(t.BANNER.pieces, text):
                return t.Reply(text, None, t.BANNER.name, False)
        # The end of a line begun in the lost bytes answers none of the commands seen since; a
        # whole line then answers none seen either (Pending.replies_lost): it pairs with none.
        command, unpaired = self.pending.pop() if not cut else (None, None)
        reply = classify(t.COMMON_REPLIES, command, text)
        if command is not None and command.name == t.VERSION_COMMAND:
            self.version = version_in(text, t.VERSION_PREFIX) or self.version
        # A reply that pairs with none says why in place of whether it says an error.
        if unpaired == NOT_KEPT:
            error = reply_not_kept(self.pending.limit)
        elif unpaired == UNKNOWN:
            error = reply_unknown("command")
        elif cut:
            error = LINE_AFTER_GAP
        else:
            error = reply.error if reply else False
        return t.Reply(text, command.name if command else None, reply.name if reply else None, error)
