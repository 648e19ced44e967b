"""The dataset's rows of a raw primary/secondary stream made in C (dataset.py, under the C backend).

The extension's PrimaryColumns (ext/ccore/columns.c) frames and decodes the stream with the
generated C parser and appends each record's values straight into per-kind column buffers; a
kind's full batch comes back as buffers that become Arrow arrays without a Python object per
value. The columns are the dataset's schema (dataset_columns): Python gives C, once, each kind's
column paths and types in schema order. A kind that holds JSON text of its own (name lists,
global-variable values, program threads: rare messages) has no columns in C: its messages come
back as bytes and go through the Python decoder and PartBuilder, so every kind's rows are made in
one place, in stream order. The result is the same Parts as the pure-Python path
(tests/python/test_dataset_c.py compares them).
"""
from __future__ import annotations

import dataclasses
import datetime
from typing import Iterator, Optional

from .arguments import parse_version
from .canonical import has_error, to_json_line
from .cell import ports_of, timed_robot_records
from .envelope import Enveloped
from .interfaces import INTERFACES
from .backends import ccore
from .dataset_columns import ERROR_KINDS, PRIMARY, ROBOT_STATE, LEAD, Part, columns_of, dataset_schema, kinds
from .decoding import decode_message

BATCH_ROWS = 1 << 15        # rows of a kind the C side holds before it hands them over
CHUNK = 1 << 20             # bytes of the stream read at a time
_PYTHON_KINDS = ("texts", "values", "json")   # columns whose JSON text Python writes


def _type_code(arrow_type) -> int:
    """A column's Arrow type as columns.c numbers it."""
    import pyarrow as pa
    codes = {pa.int64(): 0, pa.uint64(): 1, pa.bool_(): 2, pa.float32(): 3, pa.float64(): 4, pa.string(): 5,
             pa.binary(): 6}
    return codes[arrow_type]


def layout() -> list[tuple]:
    """Each primary kind as C is given it: (kind, [(path, type code), ...]) in schema order after
    the lead columns, or (kind, None) for a kind Python makes."""
    out = []
    for kind in kinds(PRIMARY):
        columns = columns_of(PRIMARY, kind)
        if kind not in ERROR_KINDS + (ROBOT_STATE,) and any(c.kind in _PYTHON_KINDS for c in columns):
            out.append((kind, None))
            continue
        fields = list(dataset_schema(PRIMARY, kind))[len(LEAD):]
        out.append((kind, [(c.path, _type_code(f.type)) for c, f in zip(columns, fields)]))
    return out


def available() -> bool:
    """Whether C makes the rows of a raw stream: the C backend, with PrimaryColumns."""
    return hasattr(ccore(), "PrimaryColumns")


class _Tables:
    """C's batches as Parts: each batch of one robot, split by the day of its rows."""

    def __init__(self, capture: str, source: str, date: Optional[str]) -> None:
        self.capture, self.source, self.date = capture, source, date
        self.kinds = [kind for kind, _ in layout()]
        self.schemas = [dataset_schema(PRIMARY, kind) for kind in self.kinds]
        self.fault_dates: dict = {}     # (robot, position) -> the day of a row without a time

    def parts(self, robot: Optional[str], index: int, rows: int, buffers: list) -> Iterator[Part]:
        import pyarrow as pa
        import pyarrow.compute as pc
        if robot is None:
            raise ValueError("a raw stream needs the robot's name (--robot)")
        schema = self.schemas[index]
        fields = list(schema)
        arrays = [pa.repeat(pa.scalar(self.capture, pa.string()), rows),
                  pa.repeat(pa.scalar(self.source, pa.string()), rows),
                  _array(fields[2].type, rows, buffers[0]), _array(fields[3].type, rows, buffers[1])]
        arrays += [_array(f.type, rows, b) for f, b in zip(fields[len(LEAD):], buffers[2:])]
        table = pa.Table.from_arrays(arrays, schema=schema)
        kind, times = self.kinds[index], arrays[3]
        if times.null_count == 0:
            span = pc.min_max(times.cast(pa.int64())).as_py()
            if span["min"] // _DAY_US == span["max"] // _DAY_US:
                yield Part(PRIMARY, kind, robot, _day(span["min"] // _DAY_US), table)
                return
        elif times.null_count == rows and self.date is not None and not self.fault_dates:
            yield Part(PRIMARY, kind, robot, self.date, table)
            return
        dates = [self._date(robot, position, time) for position, time in
                 zip(arrays[2].to_pylist(), times.cast(pa.int64()).to_pylist())]
        for date in dict.fromkeys(dates):           # each day's rows, in their order
            yield Part(PRIMARY, kind, robot, date, table.filter(pa.array([d == date for d in dates])))

    def _date(self, robot: str, position: int, time: Optional[int]) -> str:
        if time is not None:
            return _day(time // _DAY_US)
        date = self.fault_dates.get((robot, position), self.date)
        if date is None:
            raise ValueError("a raw stream needs a date (--date)")
        return date


_DAY_US = 86_400_000_000


def _day(days: int) -> str:
    return (datetime.date(1970, 1, 1) + datetime.timedelta(days=days)).isoformat()


def _micros(time: Optional[float]) -> Optional[int]:
    """A capture time as the dataset's column holds it (dataset.PartBuilder: rounded to the µs)."""
    return None if time is None else round(time * 1e6)


def _array(arrow_type, rows: int, buffers: tuple):
    import pyarrow as pa
    valid, data, offsets = buffers
    parts = [None if valid is None else pa.py_buffer(valid)]
    if offsets is not None:
        parts.append(pa.py_buffer(offsets))
    parts.append(pa.py_buffer(data))
    return pa.Array.from_buffers(arrow_type, rows, parts)


def _hint_text(version_hint) -> Optional[str]:
    hint = parse_version(version_hint)
    return None if hint is None else "%d.%d.%d" % hint


def _columns(version_hint):
    return ccore().PrimaryColumns(_hint_text(version_hint), layout(), BATCH_ROWS)


def raw_parts(fh, capture: str, source: str, version_hint=None, robot: Optional[str] = None,
              date: Optional[str] = None) -> Iterator[Part]:
    """The Parts of a raw primary/secondary stream read from a binary file object, as
    dataset.parts_of gives them (its robot `robot`, its day `date`)."""
    from .dataset import PartBuilder
    stream = _columns(version_hint)
    tables = _Tables(capture, source, date)
    builder = PartBuilder(capture, source, date, robot)     # the kinds Python makes

    def parts(output) -> Iterator[Part]:
        batches, messages = output
        for index, rows, buffers in batches:
            yield from tables.parts(robot, index, rows, buffers)
        for _, position, _, frame, version, known in messages:
            yield from builder.add(position, None, None, decode_message(frame, version, known))

    while chunk := fh.read(CHUNK):
        yield from parts(stream.feed(chunk))
    yield from parts(stream.close())
    yield from builder.finish()


class _MadeInC:
    """What the capture reader yields for a record whose rows C made: it counts as one record."""


MADE_IN_C = _MadeInC()


class _CaptureRows:
    """A capture's primary rows from C: one PrimaryColumns per robot, whose output waits here for
    the loop that reads the capture (capture_parts) to turn it into Parts."""

    def __init__(self, version_hint, serials: dict) -> None:
        self.version_hint, self.serials = version_hint, serials
        self.next_position = 0          # the position of the next record the reader yields
        self.robots: dict = {}          # robot -> its PrimaryColumns
        self.waiting: list = []         # (robot, capture time, (batches, messages))

    def robot_of(self, address: str) -> str:
        return self.serials.get(address, address)

    def columns(self, robot: str):
        if robot not in self.robots:
            self.robots[robot] = _columns(self.version_hint)
        return self.robots[robot]

    def conversation(self, version_hint=None) -> "_PrimaryConversation":
        return _PrimaryConversation(self, version_hint)

    def interfaces(self) -> dict:
        """The capture reader's ports, the primary interface's conversations made here."""
        by_port = ports_of(INTERFACES.values())
        primary = dataclasses.replace(INTERFACES[PRIMARY], conversation=self.conversation)
        return {port: primary if i.name == PRIMARY else i for port, i in by_port.items()}


class _PrimaryConversation:
    """interfaces.PrimaryConversation with C's framer: it gives a placeholder per record, whose rows
    C has made, numbered from the reader's next position and dated by the bytes' capture time."""

    def __init__(self, rows: _CaptureRows, version_hint) -> None:
        self.rows = rows
        self.stream = ccore().PrimaryStream(_hint_text(version_hint))
        self.time: Optional[float] = None
        self.robot: Optional[str] = None
        self.next_position = 0

    def at(self, time: Optional[float], address: str) -> None:
        self.time, self.robot = time, self.rows.robot_of(address)

    def feed(self, data: bytes, from_robot: bool) -> list:
        if not from_robot:
            return []
        columns = self.rows.columns(self.robot)
        return self._made(columns, columns.feed_stream(self.stream, data, self._position(), _micros(self.time)))

    def close(self) -> list:
        if self.robot is None:          # nothing was fed
            return []
        columns = self.rows.columns(self.robot)
        return self._made(columns, columns.close_stream(self.stream, self._position(), _micros(self.time)))

    def _position(self) -> int:
        # Records fed and closed in one step of the reader are not counted yet when it closes.
        return max(self.rows.next_position, self.next_position)

    def _made(self, columns, count: int) -> list:
        self.next_position = self._position() + count
        self.rows.waiting.append((self.robot, self.time, columns.take()))
        return [MADE_IN_C] * count

    @property
    def software_version(self):
        return self.stream.software_version


def capture_parts(fh, capture: str, source: str, version_hint=None, robot: Optional[str] = None,
                  date: Optional[str] = None) -> Iterator[Part]:
    """The Parts of a .pcap or .pcapng read from a binary file object, as dataset.parts_of gives
    them, each robot's primary rows made in C."""
    from .dataset import PartBuilder, serial_numbers
    start = fh.tell()
    rows = _CaptureRows(version_hint, serial_numbers(fh))
    fh.seek(start)
    tables = _Tables(capture, source, date)
    builder = PartBuilder(capture, source, date, robot)     # the other interfaces, the kinds Python makes

    def waiting() -> Iterator[Part]:
        for owner, time, (batches, messages) in rows.waiting:
            for index, count, buffers in batches:
                yield from tables.parts(owner, index, count, buffers)
            for _, position, _, frame, version, known in messages:
                yield from builder.add(position, time, owner, decode_message(frame, version, known))
        rows.waiting.clear()

    for position, (time, address, record) in enumerate(timed_robot_records(fh, version_hint, rows.interfaces())):
        rows.next_position = position + 1
        if record is MADE_IN_C:
            builder.place(time, rows.robot_of(address))
        elif address is None and not isinstance(record, Enveloped) and has_error(record):
            # A fault of the capture file: a primary error row, among C's rows of the robot before it.
            owner, day = builder.place(None, None)
            tables.fault_dates[(owner, position)] = day
            rows.columns(owner).add_record("errors", position, None, to_json_line(record))
        else:
            yield from builder.add(position, time, None if address is None else rows.robot_of(address), record)
        yield from waiting()
    for owner, columns in rows.robots.items():
        rows.waiting.append((owner, None, columns.flush()))
    yield from waiting()
    yield from builder.finish()
