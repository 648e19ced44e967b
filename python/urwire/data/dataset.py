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
  (the record's place in the capture, as `urwire export` counts), `capture_time` (UTC) and
  `conversation` (the TCP conversation, as `urwire decode` names it); the last two are null in a
  raw stream. In a capture, an `errors` row holds the record as decode prints it, envelope and all.
- A robot is its serial number where a capture holds the dashboard server's answer to `get serial
  number` (the primary and real-time streams carry none), else its address in the .pcap or
  .pcapng, or the name given for a raw stream. A row's date is its capture time's (UTC), or, in a
  raw stream, the date given (the command line gives the file's mtime by default).
- Exporting a capture again replaces its own files (they are named by its id); another capture's
  files are added beside them.
- Rows are built into Arrow columns a batch at a time, and written in row groups of up to 1M rows
  or 128 MiB of column data, whichever comes first, with statistics (dataset_files.ROW_GROUP_ROWS
  says why).

The dataset holds the primary interface's kinds (`ur`) and the real-time interface's (`ur_realtime`:
`state`, one table for every layout, `type` naming it); a capture's other interfaces stay in
`--out`'s per-capture tables. This module reads a capture; dataset_rows.py turns its records into
rows, dataset_columns.py gives each kind's columns and dataset_files.py writes the files.
"""
from __future__ import annotations

import hashlib
import io
import os
from typing import Iterator, Optional, Union

from ..capture import head_of, is_capture
from ..envelope import Enveloped
from . import dataset_c, dataset_c_capture
from .dataset_columns import Part
from .dataset_rows import PartBuilder, serial_numbers
from .records import records_of_file, robot_address
# what the module's callers use, from the modules that make it
from .dataset_columns import columns_of, dataset_schema, kinds  # noqa: F401
from .dataset_files import write_parts  # noqa: F401


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


def _timed(fh, version_hint) -> Iterator[tuple]:
    """(capture time, robot, record) of a capture, each record Enveloped and each robot by its
    serial number where the capture holds it, else its address; or of a raw primary stream (no
    time, no robot, the records as they are)."""
    serials = {}
    if is_capture(head_of(fh)):
        start = fh.tell()
        serials = serial_numbers(fh)
        fh.seek(start)
    for record in records_of_file(fh, version_hint):
        if isinstance(record, Enveloped):
            address = robot_address(record)
            yield record.capture_time, serials.get(address, address), record
        else:
            yield None, None, record


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
