"""A capture's records as the dataset's rows (dataset.py): each record placed on its robot and
day, held with the rows of its kind until a batch is full, then made a Part of Arrow columns.

The pure-Python path makes every row here; under the C backend (dataset_c.py,
dataset_c_capture.py) C makes the primary interface's columns and the rest come here, so that
every kind's rows are made in one place.
"""
from __future__ import annotations

import datetime
from typing import Iterator, Optional

from ..canonical import has_error
from ..cell import cell_records, ports_of
from ..envelope import Enveloped
from ..generated import ur_dashboard
from ..interfaces import INTERFACES
from .dataset_columns import ERROR_KINDS, LEAD, PRIMARY, REALTIME, REALTIME_STATE, ROBOT_STATE, Part, columns_of
from .dataset_columns import dataset_schema, interfaces
from .records import conversation_text, robot_address
# pyarrow, an optional extra (urwire[parquet]), is imported by the function that makes columns.

BATCH_ROWS = 1 << 12           # records turned into Arrow columns at a time


def _utc_date(time: float) -> str:
    return datetime.datetime.fromtimestamp(time, datetime.timezone.utc).date().isoformat()


class _Rows:
    """Records of one kind, robot and date, held until a batch is full."""

    __slots__ = ("key", "positions", "times", "conversations", "objs")

    def __init__(self, key: tuple) -> None:
        self.key, self.positions, self.times, self.conversations, self.objs = key, [], [], [], []


class PartBuilder:
    """Turns (capture time, robot, record) into Parts, BATCH_ROWS rows of a key at a time."""

    def __init__(self, capture: str, source: str, date: Optional[str], robot: Optional[str]) -> None:
        self.capture, self.source, self.date, self.robot = capture, source, date, robot
        self._open: dict[tuple, _Rows] = {}
        self._last: tuple = (None, None)     # the robot and date of the last row

    def add(self, position: int, time: Optional[float], robot: Optional[str], record) -> Iterator[Part]:
        """The Parts that this record fills: `robot` is its serial number or address (None in a raw
        stream, whose robot the builder was given). A capture's record is Enveloped, and its rows
        name its conversation; a raw stream's is as it is, its rows naming none (null)."""
        if isinstance(record, Enveloped):
            # A fault of the capture file (no interface) is a primary error row.
            interface, conversation, inner = record.interface or PRIMARY, conversation_text(record), record.record
        else:
            interface, conversation, inner = PRIMARY, None, record
        if interface not in interfaces():   # another interface of the cell: in `--out`'s tables only
            return
        robot, date = self.place(time, robot)
        at = (robot, date, position, time, conversation)
        if has_error(inner):
            yield from self._row(interface, ERROR_KINDS[0], at, record)     # as decode prints it, envelope and all
        elif getattr(inner, "TYPE", "unknown") == "unknown":
            yield from self._row(interface, ERROR_KINDS[1], at, inner)
        elif interface == REALTIME:
            yield from self._row(REALTIME, REALTIME_STATE, at, inner)
        elif hasattr(inner, "packages"):
            yield from self._row(PRIMARY, ROBOT_STATE, at, inner.packages)
            for pkg in inner.packages:
                if hasattr(pkg, "JSON") and not has_error(pkg):
                    yield from self._row(PRIMARY, pkg.TYPE, at, pkg)
                else:
                    yield from self._row(PRIMARY, "errors" if has_error(pkg) else "unknown", at, pkg)
        else:
            yield from self._row(PRIMARY, inner.TYPE, at, inner)

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

    def _row(self, interface: str, kind: str, at: tuple, obj) -> Iterator[Part]:
        """A row of `obj` at (robot, date, position, capture time, conversation)."""
        robot, date, position, time, conversation = at
        key = (interface, kind, robot, date)
        rows = self._open.get(key)
        if rows is None:
            rows = self._open[key] = _Rows(key)
        rows.positions.append(position)
        rows.times.append(time)
        rows.conversations.append(conversation)
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
                  pa.array(rows.positions, pa.int64()), micros.cast(pa.timestamp("us", "UTC")),
                  pa.array(rows.conversations, pa.string())]
        arrays += [pa.array(column.read(objs), field.type)
                   for column, field in zip(columns_of(interface, kind), list(schema)[len(LEAD):])]
        rows.positions, rows.times, rows.conversations, rows.objs = [], [], [], []
        return Part(interface, kind, robot, date, pa.Table.from_arrays(arrays, schema=schema))

    def finish(self) -> Iterator[Part]:
        for rows in self._open.values():
            if rows.objs:
                yield self._part(rows)
        self._open.clear()


def serial_numbers(fh) -> dict[str, str]:
    """Robot address -> serial number, from the dashboard server's answers to `get serial number`
    in a capture: the one place a UR cell's traffic carries it. Only the dashboard's conversations
    are read (a first pass over the file)."""
    dashboard = INTERFACES[ur_dashboard.NAME]
    serials = {}
    for item in cell_records(fh, None, ports_of([dashboard])):
        reply = item.record
        if getattr(reply, "reply_name", None) == "serial_number" and not reply.error:
            serials[robot_address(item)] = reply.reply.strip()
    return serials

