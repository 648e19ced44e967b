"""`urwire export --dataset ROOT`: captures as one Hive-partitioned Parquet dataset (docs/tables.md).

    ROOT/interface=ur/kind=joint_data/robot=<id>/date=<YYYY-MM-DD>/part-<capture id>-<n>.parquet
    ROOT/interface=ur_realtime/kind=state/robot=<id>/date=<YYYY-MM-DD>/part-<capture id>-<n>.parquet

- One schema per kind, the same for every software version: a column for each field of any layout
  of the kind (the generated class holds the union of its layouts, a version's missing fields
  being None), null where a version has none, so that the files of a fleet union. It is read from
  the generated classes (`dataset_schema`): fixed-count lists and groups take a column per item
  (the count is in the field's metadata), lists of a count only a record knows, name lists and
  global-variable values take their canonical JSON text.
- Each row starts with `capture` (the capture id: a hash of the capture's bytes), `capture_file`
  (the name of the file it came from; a robot message has a `source` of its own), `position`
  (the record's place in the capture, as `urwire export` counts) and `capture_time` (UTC; null
  in a raw stream).
- A robot is its serial number where a capture holds the dashboard server's answer to `get serial
  number` (the primary and real-time streams carry none), else its address in the .pcap or
  .pcapng, or the name given for a raw stream. A row's date is its capture time's (UTC), or, in a
  raw stream, the date given (the command line gives the file's mtime by default).
- Exporting a capture again replaces its own files (they are named by its id); another capture's
  files are added beside them.
- Rows are built into Arrow columns a batch at a time, and written in row groups of up to 1M rows
  or 128 MiB of column data, whichever comes first, with statistics (ROW_GROUP_ROWS says why).

The dataset holds the primary interface's kinds (`ur`) and the real-time interface's (`ur_realtime`:
`state`, one table for every layout, `type` naming it); a capture's other interfaces stay in
`--out`'s per-capture tables. This module turns a capture into rows; dataset_columns.py gives each
kind's columns and dataset_files.py writes the files.
"""
from __future__ import annotations

import datetime
import hashlib
import io
import os
from typing import Iterator, Optional, Union

from . import dataset_c, dataset_c_capture
from .canonical import has_error
from .capture import head_of, is_capture
from .cell import ports_of, timed_robot_records
# what the module's callers use, from the modules that make it
from .dataset_columns import ERROR_KINDS, PRIMARY, REALTIME, REALTIME_STATE, ROBOT_STATE, Part, interfaces
from .dataset_columns import LEAD, columns_of, dataset_schema, kinds  # noqa: F401
from .dataset_files import ROW_GROUP_BYTES, ROW_GROUP_ROWS, part_folder, write_parts  # noqa: F401
from .envelope import Enveloped
from .generated import ur_dashboard
from .interfaces import INTERFACES
from .reading import records_of_raw

BATCH_ROWS = 1 << 12           # records turned into Arrow columns at a time


def capture_id(data: Union[bytes, bytearray, memoryview]) -> str:
    """A capture's id: the first 16 hex digits of the SHA-256 of its bytes, so that the same
    capture exported again is known as the same, whatever its file is called."""
    return hashlib.sha256(data).hexdigest()[:16]


def file_capture_id(path: Union[str, os.PathLike]) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()[:16]


def _utc_date(time: float) -> str:
    return datetime.datetime.fromtimestamp(time, datetime.timezone.utc).date().isoformat()


class _Rows:
    """Records of one kind, robot and date, held until a batch is full."""

    __slots__ = ("key", "positions", "times", "objs")

    def __init__(self, key: tuple) -> None:
        self.key, self.positions, self.times, self.objs = key, [], [], []


class PartBuilder:
    """Turns (capture time, robot, record) into Parts, BATCH_ROWS rows of a key at a time."""

    def __init__(self, capture: str, source: str, date: Optional[str], robot: Optional[str]) -> None:
        self.capture, self.source, self.date, self.robot = capture, source, date, robot
        self._open: dict[tuple, _Rows] = {}
        self._last: tuple = (None, None)     # the robot and date of the last row

    def add(self, position: int, time: Optional[float], robot: Optional[str], record) -> Iterator[Part]:
        """The Parts that this record fills: `robot` is its serial number or address (None in a raw
        stream, whose robot the builder was given)."""
        interface = record.interface if isinstance(record, Enveloped) else PRIMARY
        if interface not in interfaces():   # another interface of the cell: in `--out`'s tables only
            return
        robot, date = self.place(time, robot)
        inner = record.record if isinstance(record, Enveloped) else record
        if has_error(record) or getattr(inner, "TYPE", "unknown") == "unknown":
            yield from self._row(interface, ERROR_KINDS[0] if has_error(record) else ERROR_KINDS[1],
                                 robot, date, position, time, record)
            return
        if interface == REALTIME:
            yield from self._row(REALTIME, REALTIME_STATE, robot, date, position, time, inner)
            return
        if hasattr(record, "packages"):
            yield from self._row(PRIMARY, ROBOT_STATE, robot, date, position, time, record.packages)
            for pkg in record.packages:
                if hasattr(pkg, "JSON") and not has_error(pkg):
                    yield from self._row(PRIMARY, pkg.TYPE, robot, date, position, time, pkg)
                else:
                    yield from self._row(PRIMARY, "errors" if has_error(pkg) else "unknown", robot, date, position,
                                         time, pkg)
            return
        yield from self._row(PRIMARY, record.TYPE, robot, date, position, time, record)

    def place(self, time: Optional[float], robot: Optional[str]) -> tuple[str, str]:
        """The robot and day of a row at `time` from `robot`, which are then the last row's. A fault
        of a capture file has neither robot nor time: it goes with the rows before it."""
        robot = robot or self.robot or self._last[0]
        if robot is None:
            raise ValueError("a raw stream needs the robot's name (--robot)")
        date = _utc_date(time) if time is not None else self.date or self._last[1]
        if date is None:
            raise ValueError("a raw stream needs a date (--date)")
        self._last = (robot, date)
        return robot, date

    def _row(self, interface: str, kind: str, robot: str, date: str, position: int, time, obj) -> Iterator[Part]:
        key = (interface, kind, robot, date)
        rows = self._open.get(key)
        if rows is None:
            rows = self._open[key] = _Rows(key)
        rows.positions.append(position)
        rows.times.append(time)
        rows.objs.append(obj)
        if len(rows.objs) >= BATCH_ROWS:
            yield self._part(rows)

    def _part(self, rows: _Rows) -> Part:
        """The held records as Arrow columns, a column at a time."""
        import pyarrow as pa
        import pyarrow.compute as pc
        interface, kind, robot, date = rows.key
        schema = dataset_schema(interface, kind)
        count, objs = len(rows.objs), rows.objs
        micros = pc.cast(pc.round(pc.multiply(pa.array(rows.times, pa.float64()), 1e6)), pa.int64())
        arrays = [pa.array([self.capture] * count, pa.string()), pa.array([self.source] * count, pa.string()),
                  pa.array(rows.positions, pa.int64()), micros.cast(pa.timestamp("us", "UTC"))]
        arrays += [pa.array(column.read(objs), field.type)
                   for column, field in zip(columns_of(interface, kind), list(schema)[len(LEAD):])]
        rows.positions, rows.times, rows.objs = [], [], []
        return Part(interface, kind, robot, date, pa.Table.from_arrays(arrays, schema=schema))

    def finish(self) -> Iterator[Part]:
        for rows in self._open.values():
            if rows.objs:
                yield self._part(rows)
        self._open.clear()


def _timed(fh, version_hint) -> Iterator[tuple]:
    """(capture time, robot, record) of a capture, each robot by its serial number where the
    capture holds it, else its address; or of a raw primary stream (no time, no robot)."""
    head = head_of(fh)
    if is_capture(head):
        start = fh.tell()
        serials = serial_numbers(fh)
        fh.seek(start)
        for time, address, record in timed_robot_records(fh, version_hint, ports_of(INTERFACES.values())):
            yield time, serials.get(address, address), record
        return
    for record in records_of_raw(fh, version_hint, lambda n: None):
        yield None, None, record


def serial_numbers(fh) -> dict[str, str]:
    """Robot address -> serial number, from the dashboard server's answers to `get serial number`
    in a capture: the one place a UR cell's traffic carries it. Only the dashboard's conversations
    are read (a first pass over the file)."""
    dashboard = INTERFACES[ur_dashboard.NAME]
    serials = {}
    for _, address, record in timed_robot_records(fh, None, ports_of([dashboard])):
        reply = getattr(record, "record", None)
        if getattr(reply, "reply_name", None) == "serial_number" and not reply.error:
            serials[address] = reply.reply.strip()
    return serials


def parts_of(fh, capture: str, source: str, version_hint=None, robot: Optional[str] = None,
             date: Optional[str] = None) -> Iterator[Part]:
    """The Parts of a capture read from a binary file object (see capture_parts). Under the C
    backend, C makes the columns of the primary interface (dataset_c.py)."""
    head = head_of(fh)
    if dataset_c.available():
        made = dataset_c_capture.capture_parts if is_capture(head) else dataset_c.raw_parts
        yield from made(fh, capture, source, version_hint, robot, date)
        return
    builder = PartBuilder(capture, source, date, robot)
    for position, (time, address, record) in enumerate(_timed(fh, version_hint)):
        yield from builder.add(position, time, address, record)
    yield from builder.finish()


def capture_parts(data: bytes, source: str, version_hint=None, robot: Optional[str] = None,
                  date: Optional[str] = None) -> Iterator[Part]:
    """The dataset's Parts of one capture held in memory (a raw stream, .pcap or .pcapng): each
    Part a batch of rows of one kind, robot and day. A capture's robots are their serial numbers
    where its dashboard traffic tells them, else their addresses; a raw stream's robot is `robot`
    and its day `date` (YYYY-MM-DD), without which it is a ValueError."""
    return parts_of(io.BufferedReader(io.BytesIO(data)), capture_id(data), source, version_hint, robot, date)
