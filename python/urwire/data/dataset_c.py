"""The dataset's rows of the primary interface made in C (dataset.py, under the C backend).

The extension's PrimaryColumns (ext/ccore/columns.c) frames and decodes the stream with the
generated C parser and appends each record's values straight into per-kind column buffers; a
kind's full batch comes back as buffers that become Arrow arrays without a Python object per
value. The columns are the dataset's schema (dataset_columns): Python gives C, once, each kind's
column paths and types in schema order. A kind that holds JSON text of its own (name lists,
global-variable values, program threads: rare messages) has no columns in C: its messages come
back as bytes and go through the Python decoder and PartBuilder (dataset_rows.py), so every
kind's rows are made in one place, in stream order. The result is the same Parts as the pure-Python path
(tests/python/test_dataset_c.py compares them). Captures: dataset_c_capture.py.
"""
from __future__ import annotations

import datetime
import functools
from array import array
from typing import Iterator, Optional

from ..arguments import parse_version
from ..backends import ccore
from ..canonical import to_json_line
from ..decoding import decode_message
from ..envelope import FROM_ROBOT, Enveloped
from .dataset_columns import ERROR_KINDS, LEAD, PRIMARY, ROBOT_STATE, Part, columns_of, dataset_schema, kinds
from .dataset_rows import PartBuilder
# pyarrow, an optional extra (urwire[parquet]), is imported by the functions that make columns.

BATCH_ROWS = 1 << 15        # rows of a kind the C side holds before it hands them over
CHUNK = 1 << 20             # bytes of the stream read at a time
_PYTHON_KINDS = ("texts", "values", "json")   # columns whose JSON text Python writes


def _type_code(arrow_type) -> int:
    """A column's Arrow type as columns.c numbers it."""
    import pyarrow as pa
    codes = {pa.int64(): 0, pa.uint64(): 1, pa.bool_(): 2, pa.float32(): 3, pa.float64(): 4, pa.string(): 5,
             pa.binary(): 6}
    return codes[arrow_type]


@functools.lru_cache(maxsize=None)
def layout() -> tuple:
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
    return tuple(out)


def available() -> bool:
    """Whether C makes the primary interface's rows: the C backend, with PrimaryColumns."""
    return hasattr(ccore(), "PrimaryColumns")


class Conversations:
    """The conversation of each record of a capture whose rows C made, by its position: C's rows
    carry their position, and a robot's rows of all its conversations share its columns."""

    def __init__(self) -> None:
        self._names: list = [None]              # index 0: no conversation (a fault of the capture file)
        self._index: dict = {None: 0}
        self._at = array("i")                   # position -> index in _names

    def note(self, start: int, count: int, conversation: Optional[str]) -> None:
        """The records at positions start ... start + count - 1 came from `conversation`."""
        index = self._index.get(conversation)
        if index is None:
            index = self._index[conversation] = len(self._names)
            self._names.append(conversation)
        end = start + count
        if len(self._at) < end:
            self._at.frombytes(bytes(self._at.itemsize * (end - len(self._at))))
        self._at[start:end] = array("i", [index]) * count

    def at(self, position: int) -> Optional[str]:
        return self._names[self._at[position]] if position < len(self._at) else None

    def of(self, positions):
        """The conversations of an Arrow array of positions, as a string array (null where none)."""
        import pyarrow as pa
        import pyarrow.compute as pc
        if len(positions) == 0:
            return pa.array([], pa.string())
        span = pc.min_max(positions).as_py()
        low, high = span["min"], min(span["max"] + 1, len(self._at))
        # A copy of the span: a buffer over _at itself would stop it growing while Arrow holds it.
        window = self._at[low:high] if low < high else array("i")
        window.extend(array("i", [0]) * (span["max"] + 1 - low - len(window)))
        indexes = pa.Array.from_buffers(pa.int32(), len(window), [None, pa.py_buffer(window)])
        return pc.take(pa.array(self._names, pa.string()), pc.take(indexes, pc.subtract(positions, low)))


class Tables:
    """C's batches as Parts: each batch of one robot, split by the day of its rows. In a capture,
    `conversations` names each row's conversation, and an `errors` row holds its record as decode
    prints it, envelope and all; a raw stream's rows have none (null)."""

    def __init__(self, capture: str, source: str, date: Optional[str],
                 conversations: Optional[Conversations] = None) -> None:
        self.capture, self.source, self.date = capture, source, date
        self.conversations = conversations
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
        kind, positions = self.kinds[index], _array(fields[2].type, rows, buffers[0])
        conversations = pa.nulls(rows, pa.string()) if self.conversations is None else \
            self.conversations.of(positions)
        arrays = [pa.repeat(pa.scalar(self.capture, pa.string()), rows),
                  pa.repeat(pa.scalar(self.source, pa.string()), rows),
                  positions, _array(fields[3].type, rows, buffers[1]), conversations]
        arrays += [_array(f.type, rows, b) for f, b in zip(fields[len(LEAD):], buffers[2:])]
        if kind == ERROR_KINDS[0] and conversations.null_count < rows:
            arrays[len(LEAD)] = _enveloped(arrays[len(LEAD)], conversations)
        table = pa.Table.from_arrays(arrays, schema=schema)
        times = arrays[3]
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


class _Written:
    """A record's canonical JSON as C wrote it, for canonical's writer to put in an envelope."""

    __slots__ = ("text",)

    def __init__(self, text: str) -> None:
        self.text = text

    def canonical_json(self) -> str:
        return self.text


def _enveloped(records, conversations):
    """The JSON texts of primary error rows, each of a conversation in its envelope, as decode
    prints the record (errors are few: this is done a row at a time)."""
    import pyarrow as pa
    return pa.array([text if conversation is None else
                     to_json_line(Enveloped(PRIMARY, FROM_ROBOT, conversation, _Written(text)))
                     for text, conversation in zip(records.to_pylist(), conversations.to_pylist())], pa.string())


def _day(days: int) -> str:
    return (datetime.date(1970, 1, 1) + datetime.timedelta(days=days)).isoformat()


def micros(time: Optional[float]) -> Optional[int]:
    """A capture time as the dataset's column holds it (dataset_rows.PartBuilder: rounded to the µs)."""
    return None if time is None else round(time * 1e6)


def _array(arrow_type, rows: int, buffers: tuple):
    import pyarrow as pa
    valid, data, offsets = buffers
    parts = [None if valid is None else pa.py_buffer(valid)]
    if offsets is not None:
        parts.append(pa.py_buffer(offsets))
    parts.append(pa.py_buffer(data))
    return pa.Array.from_buffers(arrow_type, rows, parts)


def hint_text(version_hint) -> Optional[str]:
    hint = parse_version(version_hint)
    return None if hint is None else "%d.%d.%d" % hint


def columns(version_hint):
    """A PrimaryColumns of the dataset's layout."""
    return ccore().PrimaryColumns(hint_text(version_hint), layout(), BATCH_ROWS)


def raw_parts(fh, capture: str, source: str, version_hint=None, robot: Optional[str] = None,
              date: Optional[str] = None) -> Iterator[Part]:
    """The Parts of a raw primary/secondary stream read from a binary file object, as
    dataset.parts_of gives them (its robot `robot`, its day `date`)."""
    stream = columns(version_hint)
    tables = Tables(capture, source, date)
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
