"""The dataset's rows of a .pcap or .pcapng under the C backend (dataset.py, dataset_c.py).

The capture reader (C's, else capture.py's) reads the file and reassembles the TCP streams, and
Python makes the rows of the other interfaces; each robot's primary and secondary streams go to C
(a PrimaryStream per connection, one PrimaryColumns per robot, so that the rows of its connections
stay in capture order), and the capture reader counts a placeholder per block of records C made,
so that every record keeps its position. Each position C fills is noted with its conversation
(dataset_c.Conversations), which names the conversation of C's rows. The C reader joins the
segments of a primary stream that come in a row (capture.Segments), which C reads a segment at a
time: Python takes a step per run of segments and per batch of rows, not per segment or record.
"""
from __future__ import annotations

import dataclasses
from typing import Iterator, Optional

from .._runtime import StreamError
from ..backends import ccore
from ..canonical import to_json_line
from ..capture import Segments
from ..cell import cell_records, ports_of, primary_ports
from ..decoding import decode_message
from ..envelope import FROM_ROBOT, Endpoints, Enveloped
from ..interfaces import INTERFACES
from .dataset_c import Conversations, Tables, columns, hint_text, micros
from .dataset_columns import PRIMARY, Part
from .dataset_rows import PartBuilder, serial_numbers
from .records import conversation_text, robot_address


class MadeInC:
    """What the capture reader yields for `count` records in a row whose rows C made."""

    __slots__ = ("count",)

    def __init__(self, count: int) -> None:
        self.count = count


class _CaptureRows:
    """A capture's primary rows from C: one PrimaryColumns per robot, whose output waits here for
    the loop that reads the capture (capture_parts) to turn it into Parts."""

    def __init__(self, version_hint, serials: dict) -> None:
        self.version_hint, self.serials = version_hint, serials
        self.next_position = 0          # the position of the next record the reader yields
        self.robots: dict = {}          # robot -> its PrimaryColumns
        self.waiting: list = []         # (robot, capture time, (batches, messages))
        self.conversations = Conversations()

    def robot_of(self, address: str) -> str:
        return self.serials.get(address, address)

    def columns(self, robot: str):
        if robot not in self.robots:
            self.robots[robot] = columns(self.version_hint)
        return self.robots[robot]

    def conversation(self, version_hint=None) -> "_PrimaryConversation":
        return _PrimaryConversation(self, version_hint)

    def interfaces(self) -> dict:
        """The capture reader's ports, the primary interface's conversations made here."""
        by_port = ports_of(INTERFACES.values())
        primary = dataclasses.replace(INTERFACES[PRIMARY], conversation=self.conversation)
        return {port: primary if i.name == PRIMARY else i for port, i in by_port.items()}


class _PrimaryConversation:
    """interfaces.PrimaryConversation with C's framer: it gives a placeholder for the records whose
    rows C has made, numbered from the reader's next position and dated by the capture time of the
    segment that completes each."""

    def __init__(self, rows: _CaptureRows, version_hint) -> None:
        self.rows = rows
        self.stream = ccore().PrimaryStream(hint_text(version_hint))
        self.time: Optional[float] = None
        self.robot: Optional[str] = None
        self.conversation: Optional[str] = None
        self.next_position = 0

    def at(self, time: Optional[float], key: tuple) -> None:
        """The capture time of the bytes about to be fed, and their conversation (server address,
        port, client address, port: the robot is the server)."""
        if self.conversation is None:
            self.conversation = str(Endpoints(*key))
            self.robot = self.rows.robot_of(key[0])
        self.time = time

    def feed(self, data, from_robot: bool) -> list:
        if not from_robot:
            return []
        columns = self.rows.columns(self.robot)
        if type(data) is Segments:
            return self._made(columns, columns.feed_segments(self.stream, data.data, data.stamps, self._position()))
        return self._made(columns, columns.feed_stream(self.stream, data, self._position(), micros(self.time)))

    def close(self, from_robot: Optional[bool] = None) -> list:
        if self.robot is None or from_robot is False:    # nothing was fed, or the client's side
            return []
        columns = self.rows.columns(self.robot)
        return self._made(columns, columns.close_stream(self.stream, self._position(), micros(self.time)))

    def lost(self, from_robot: bool, offset: int) -> list:
        if self.robot is None or not from_robot:
            return []
        columns = self.rows.columns(self.robot)
        return self._made(columns, columns.restart_stream(self.stream, offset, self._position(), micros(self.time)))

    def _position(self) -> int:
        # Records fed and closed in one step of the reader are not counted yet when it closes.
        return max(self.rows.next_position, self.next_position)

    def _made(self, columns, count: int) -> list:
        self.rows.conversations.note(self._position(), count, self.conversation)
        self.next_position = self._position() + count
        self.rows.waiting.append((self.robot, columns.take()))
        return [MadeInC(count)] if count else []

    @property
    def software_version(self):
        return self.stream.software_version


def capture_parts(fh, capture: str, source: str, version_hint=None, robot: Optional[str] = None,
                  date: Optional[str] = None) -> Iterator[Part]:
    """The Parts of a .pcap or .pcapng read from a binary file object, as dataset.parts_of gives
    them, each robot's primary rows made in C."""
    start = fh.tell()
    rows = _CaptureRows(version_hint, serial_numbers(fh))
    fh.seek(start)
    tables = Tables(capture, source, date, rows.conversations)
    builder = PartBuilder(capture, source, date, robot)     # the other interfaces, the kinds Python makes

    def waiting() -> Iterator[Part]:
        for owner, (batches, messages) in rows.waiting:
            for index, count, buffers in batches:
                yield from tables.parts(owner, index, count, buffers)
            for _, position, us, frame, version, known in messages:
                time = None if us is None else us / 1e6     # the time of the segment that completed it
                record = Enveloped(PRIMARY, FROM_ROBOT, rows.conversations.at(position),
                                   decode_message(frame, version, known), time)
                yield from builder.add(position, time, owner, record)
        rows.waiting.clear()

    position = 0
    by_port = rows.interfaces()
    for item in cell_records(fh, version_hint, by_port, joined=primary_ports(by_port)):
        record, time, address = item.record, item.capture_time, robot_address(item)
        in_c = type(record) is MadeInC
        count = record.count if in_c else 1
        rows.next_position = position + count
        if in_c:
            builder.place(time, rows.robot_of(address))     # the last of C's records places what follows
        elif item.interface is None:
            # A fault of the capture file: a primary error row, among C's rows of the robot before it.
            owner, day = builder.place(None, None)
            tables.fault_dates[(owner, position)] = day
            rows.columns(owner).add_record("errors", position, None, to_json_line(record))
        elif item.interface == PRIMARY and isinstance(record, StreamError):
            # The reader's record of a primary stream's gap or differing retransmission: an error row
            # among C's rows of its robot, in its envelope as C's errors are (dataset_c.Tables).
            owner, _ = builder.place(time, rows.robot_of(address))
            rows.conversations.note(position, 1, conversation_text(item))
            rows.columns(owner).add_record("errors", position, micros(time), to_json_line(record))
        else:
            yield from builder.add(position, time, None if address is None else rows.robot_of(address), item)
        position += count
        if rows.waiting:
            yield from waiting()
    for owner, columns in rows.robots.items():
        rows.waiting.append((owner, columns.flush()))
    yield from waiting()
    yield from builder.finish()
