"""`urwire decode`'s JSON Lines of a capture under the C backend: the primary interface's
conversations (the bulk of a cell's bytes) framed, decoded and written by C
(urwire._ccore.PrimaryJsonLines), as a raw stream's are, each line then given its envelope;
every other interface's records written by canonical.py. cell.py orders and envelopes both, so
the lines are the same bytes as to_json_line of each record of capture_records. The C capture
reader joins the primary streams' segments that come in a row (capture.Segments): a line has no
capture time, so C is fed each run's bytes, FEED_BYTES at a time.
"""
from __future__ import annotations

import dataclasses
from typing import BinaryIO, Callable, Iterator, Optional

from .arguments import VersionLike, parse_version
from .canonical import envelope_head, fails, to_json_line
from .capture import Segments
from .cell import PRIMARY, cell_records, primary_ports
from .envelope import Endpoints
from .extension import CCORE
from .interfaces import Interface
from .reading import CaptureRecords

# C hands a feed's lines over as one bytes object, about 3.5 times the bytes fed. Fed a run of 1 MB
# at once, each would be a fresh block of megabytes whose pages the kernel fills on first touch:
# at 200 MB, 251k page faults and 0.51 s of system time, against 43k and 0.14 s in slices of 64 KiB.
FEED_BYTES = 64 << 10


@dataclasses.dataclass(frozen=True)
class Written:
    """JSON Lines that C wrote (bytes, each line ending in a newline), and whether a line the
    conversation wrote so far held an error; `enveloped` once the conversation's lines start
    with their envelope (set_head), else each starts with its record's "{"."""

    text: bytes
    errors: bool
    enveloped: bool
    conversation: "PrimaryJsonConversation"


class PrimaryJsonConversation:
    """interfaces.PrimaryConversation, its records Written blocks: one per call that completes any."""

    def __init__(self, version_hint: VersionLike = None):
        hint = parse_version(version_hint)
        self._c = CCORE.PrimaryJsonLines(None if hint is None else "%d.%d.%d" % hint)
        self._enveloped = False

    def feed(self, data, from_robot: bool) -> list:
        if not from_robot:
            return []
        if type(data) is not Segments:
            return self._written(self._c.feed(data))
        run = memoryview(data.data)
        return [block for at in range(0, len(run), FEED_BYTES)
                for block in self._written(self._c.feed(run[at:at + FEED_BYTES]))]

    def close(self, from_robot: Optional[bool] = None) -> list:
        return [] if from_robot is False else self._written(self._c.close())

    def lost(self, from_robot: bool, offset: int) -> list:
        return self._written(self._c.restart(offset)) if from_robot else []

    @property
    def software_version(self):
        """The version the robot's Version message announced, else None (as PrimaryConversation's)."""
        return self._c.announced

    def set_head(self, head: bytes) -> None:
        """Each line from now on starts with `head` (its envelope's) in place of its "{"."""
        self._c.set_head(head)
        self._enveloped = True

    def _written(self, text: bytes) -> list:
        return [Written(text, self._c.errors, self._enveloped, self)] if text else []


def written_in_c(by_port: dict[int, Interface]) -> dict[int, Interface]:
    """by_port with the primary interface's conversations written by C."""
    return {port: dataclasses.replace(i, conversation=PrimaryJsonConversation) if i.name == PRIMARY else i
            for port, i in by_port.items()}


class CaptureJsonLines:
    """The JSON Lines of a capture (bytes, a piece per record or block of records) as they are
    iterated; `errors` says whether a line so far held an error, `unclaimed` is CaptureRecords'."""

    def __init__(self, fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                 advance: Callable[[int], None] = lambda n: None):
        self._records = CaptureRecords(lambda others: cell_records(fh, hint, written_in_c(by_port), advance, others,
                                                                   primary_ports(by_port)))
        self.errors = False

    def __iter__(self) -> Iterator[bytes]:
        for item in self._records:
            written = item.record
            if type(written) is not Written:
                self.errors = self.errors or fails(item)
                yield (to_json_line(item) + "\n").encode()
                continue
            self.errors = self.errors or written.errors
            if written.enveloped:
                yield written.text
                continue
            # The conversation's first lines: enveloped here, its next ones by C.
            head = envelope_head(item).encode()
            written.conversation.set_head(head)
            # Each line's "{" becomes the envelope's head; a newline inside a JSON text is escaped.
            yield head + written.text[1:].replace(b"\n{", b"\n" + head)

    @property
    def unclaimed(self) -> dict[Endpoints, int]:
        return self._records.unclaimed
