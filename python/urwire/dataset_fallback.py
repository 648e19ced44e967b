"""The dataset calls that `urwire spark` makes (capture_parts, write_parts, dataset_schema,
capture_id), in their simplest form, for an installation whose package has no `urwire.dataset`:
the tables of `urwire export` (export.Tables), one Part per table.

A Part's robot is the one given for a raw stream, "unknown" in a capture, its date the UTC day of the capture's first
frame, else the one given, and its schema the table's own: a kind's columns are those its
capture shows, so dataset_schema knows none in advance (None).
"""
from __future__ import annotations

import datetime
import hashlib
import io
import tempfile
from pathlib import Path
from typing import Iterable, Iterator, NamedTuple, Optional

from .capture import is_capture
from .cell import ports_of
from .export import Tables, _ARROW_TYPES
from .interfaces import INTERFACES
from .reading import records_of_raw, timed_records_of_capture


class Part(NamedTuple):
    interface: str
    kind: str
    robot: str
    date: str
    table: object    # a pyarrow.Table


def capture_id(data: bytes) -> str:
    """A capture's name in its part files: from its content, so that exporting it again
    replaces its parts."""
    return hashlib.sha256(data).hexdigest()[:16]


def dataset_schema(interface: str, kind: str):
    """Not known before the rows are: each table has the columns its capture shows."""
    return None


def _interface_of(table: str) -> str:
    for name in sorted(INTERFACES, key=len, reverse=True):
        if name != "ur" and (table == name or table.startswith(name + "_")):
            return name
    return "ur"


def _timed_records(data: bytes, version_hint) -> Iterator[tuple]:
    fh = io.BufferedReader(io.BytesIO(data))
    if is_capture(bytes(data[:4])):
        yield from timed_records_of_capture(fh, version_hint, (), by_port=ports_of(INTERFACES.values()))
    else:
        for record in records_of_raw(fh, version_hint, lambda n: None):
            yield None, record


def capture_parts(data: bytes, source: str, version_hint=None, robot: Optional[str] = None,
                  date: Optional[str] = None) -> Iterator[Part]:
    import pyarrow as pa

    robot = "unknown" if robot is None or is_capture(bytes(data[:4])) else robot
    first_time: Optional[float] = None
    with tempfile.TemporaryDirectory(prefix="urwire-rows-") as spill:
        tables = Tables(Path(spill))
        try:
            for position, (time, record) in enumerate(_timed_records(data, version_hint)):
                if first_time is None and time is not None:
                    first_time = time
                tables.add_record(position, record, time)
            tables.cell.finish()
            if first_time is not None:
                date = datetime.datetime.fromtimestamp(first_time, datetime.timezone.utc).date().isoformat()
            date = date or "unknown"
            for name, kinds in tables.kinds.items():
                schema = pa.schema([(col, getattr(pa, _ARROW_TYPES.get(kind, "string"))()) for col, kind in kinds.items()])
                batches = [pa.Table.from_arrays([pa.array(v, type=f.type) for v, f in zip(columns, schema)],
                                                schema=schema) for _, columns in tables.batches(name)]
                yield Part(_interface_of(name), name, robot, date, pa.concat_tables(batches))
        finally:
            tables.close()


def _filesystem(root: str):
    """pyarrow's filesystem of a root and the path in it: a local folder, or a URI pyarrow
    writes (s3://bucket/prefix, gs://..., hdfs://...)."""
    from pyarrow import fs

    if "://" in str(root):
        return fs.FileSystem.from_uri(str(root))
    return fs.LocalFileSystem(), str(Path(root).resolve())


def write_parts(root, parts: Iterable[Part], capture_id: str) -> None:
    """ROOT/interface=/kind=/robot=/date=/part-<capture id>-<n>.parquet; a capture written
    again replaces its own parts in the folders it writes."""
    import pyarrow.parquet as pq
    from pyarrow import fs

    filesystem, base = _filesystem(root)
    written: dict[str, int] = {}
    for part in parts:
        folder = f"{base}/interface={part.interface}/kind={part.kind}/robot={part.robot}/date={part.date}"
        if folder not in written:
            filesystem.create_dir(folder, recursive=True)
            for old in filesystem.get_file_info(fs.FileSelector(folder)):
                if old.base_name.startswith(f"part-{capture_id}-"):
                    filesystem.delete_file(old.path)
            written[folder] = 0
        pq.write_table(part.table, f"{folder}/part-{capture_id}-{written[folder]}.parquet", filesystem=filesystem)
        written[folder] += 1
