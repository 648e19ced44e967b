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
`--out`'s per-capture tables.
"""
from __future__ import annotations

import dataclasses
import datetime
import hashlib
import inspect
import io
import json
import operator
import os
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, NamedTuple, Optional, Union

from .canonical import has_error, member_text, shown_text, to_dict, to_json_line
from .capture import is_capture
from .cell import ports_of, timed_robot_records
from .envelope import Enveloped
from .generated import messages, ur_dashboard, ur_realtime
from .interfaces import INTERFACES
from .reading import records_of_raw

PRIMARY = "ur"
REALTIME = "ur_realtime"
REALTIME_STATE = "state"
# The size of a row group: DuckDB and Spark give each row group to one thread, and
# skip a row group whose statistics rule it out, so a group wants to be large enough to be worth a
# thread (DuckDB's guidance is 100k to 1M rows) and small enough to be skipped often and held in
# memory while it is written: 1M rows, or fewer where a row is wide (joint_data's 52 columns reach
# 128 MiB at about 365k rows).
ROW_GROUP_ROWS = 1 << 20
ROW_GROUP_BYTES = 128 << 20
BATCH_ROWS = 1 << 12           # records turned into Arrow columns at a time
_LEAD = ("capture", "capture_file", "position", "capture_time")
_ERROR_KINDS = ("errors", "unknown")
_ROBOT_STATE = "robot_state"


class Part(NamedTuple):
    """Rows of one kind, of one robot on one day, in the kind's schema (`dataset_schema`)."""

    interface: str
    kind: str
    robot: str
    date: str           # YYYY-MM-DD
    table: Any          # pyarrow.Table


# ---- the schema of each kind ---------------------------------------------------------------

_ARROW = {"int": "int64", "enum": "int64", "uint64": "uint64", "bool": "bool_", "f32": "float32",
          "f64": "float64", "text": "string", "hex": "binary", "texts": "string", "values": "string",
          "json": "string", "int|f32": "float64", "int|f64": "float64"}


class Column(NamedTuple):
    name: str
    kind: str                            # a key of _ARROW
    read: Callable[[list], list]         # a batch of records -> the column's values for them


def _attr(name: str) -> Callable[[list], list]:
    get = operator.attrgetter(name)

    def read(objs: list) -> list:
        try:
            return list(map(get, objs))
        except (AttributeError, TypeError):  # a missing group, or a layout without the field
            return [None if o is None else getattr(o, name, None) for o in objs]
    return read


def _nth(j: int) -> Callable[[list], list]:
    get = operator.itemgetter(j)

    def read(lists: list) -> list:
        try:
            return list(map(get, lists))
        except (IndexError, TypeError):      # a list that is missing or shorter
            return [None if i is None or j >= len(i) else i[j] for i in lists]
    return read


def _then(first: Callable[[list], list], second: Callable[[list], list]) -> Callable[[list], list]:
    return lambda objs: second(first(objs))


def _plain(kind: str) -> Callable[[list], list]:
    """Values as `urwire decode` shows them, in the type their column takes (as export.py writes
    them): any nonzero bool byte as true, text with each invalid UTF-8 byte as U+FFFD, name lists
    and values as their JSON; numbers and enums go to Arrow as they are."""
    if kind == "bool":
        return lambda vs: [None if v is None else bool(v) for v in vs]
    if kind == "text":
        return lambda vs: [None if v is None else shown_text(v) for v in vs]
    if kind in ("texts", "values"):
        return lambda vs: [None if v is None else member_text(kind, v) for v in vs]
    if kind == "hex":
        return lambda vs: [None if v is None else bytes(v) for v in vs]
    return lambda vs: vs


def _as_json(name: str) -> Callable[[list], list]:
    return lambda objs: [None if getattr(o, name) is None else json.dumps(to_dict(o)[name], ensure_ascii=False)
                         for o in objs]


def class_columns(cls: type) -> list[Column]:
    """The columns of a generated class, in the order of its fields: a fixed-count group's fields
    per item (`q_actual_0` ..., prefixed with the group's name where a kind has two groups), a
    fixed-count list's items (`dh_a_0` ...), anything of a count only a record knows as JSON text."""
    meta = {f.name: f.metadata for f in dataclasses.fields(cls)}
    groups = [name for name, kind, _ in cls.JSON if kind == "items"]
    out: list[Column] = []
    for name, kind, _ in cls.JSON:
        count = meta[name].get("count")
        if meta[name].get("wire") == "uint64":
            kind = "list:uint64" if kind.startswith("list:") else "uint64"
        if kind == "items" and count is not None:
            prefix = f"{name}_" if len(groups) > 1 else ""
            for j in range(count):
                item = _then(_attr(name), _nth(j))
                out += [Column(f"{prefix}{c.name}_{j}", c.kind, _then(item, c.read))
                        for c in class_columns(cls.ITEMS[name])]
        elif kind.startswith("list:") and count is not None:
            item_kind = kind[len("list:"):]
            out += [Column(f"{name}_{j}", item_kind, _then(_then(_attr(name), _nth(j)), _plain(item_kind)))
                    for j in range(count)]
        elif kind == "items" or kind.startswith("list:"):
            out.append(Column(name, "json", _as_json(name)))
        else:
            out.append(Column(name, kind, _then(_attr(name), _plain(kind))))
    return out


def _primary_classes() -> dict[str, type]:
    """Every kind of the primary interface that has a table: sub-packages and messages by TYPE."""
    return {cls.TYPE: cls for cls in vars(messages).values()
            if inspect.isclass(cls) and hasattr(cls, "JSON") and isinstance(getattr(cls, "TYPE", None), str)}


def _realtime_columns() -> list[Column]:
    """One real-time table for every layout: `type` names the layout, then the fields of every
    layout, oldest first, each once (a field that a layout lacks is null)."""
    seen: dict[str, Column] = {"type": Column("type", "text", lambda objs: [o.TYPE for o in objs])}
    for forms in ur_realtime.FORMS_BY_SIZE.values():
        for *_, cls, _ in forms:
            for column in class_columns(cls):
                seen.setdefault(column.name, column)
    return list(seen.values())


_CLASSES = _primary_classes()
_APART = {kind: [Column("record", "text", lambda objs: [to_json_line(o) for o in objs])] for kind in _ERROR_KINDS}
# Each interface's kinds, each with the function that gives its columns.
_KINDS: dict[str, dict[str, Callable[[], list[Column]]]] = {
    PRIMARY: {**{kind: (lambda cls=cls: class_columns(cls)) for kind, cls in _CLASSES.items()},
              _ROBOT_STATE: lambda: [Column("packages", "int", lambda objs: [len(o) for o in objs])],
              **{kind: (lambda kind=kind: _APART[kind]) for kind in _ERROR_KINDS}},
    REALTIME: {REALTIME_STATE: _realtime_columns, **{kind: (lambda kind=kind: _APART[kind]) for kind in _ERROR_KINDS}},
}
_COLUMNS: dict[tuple, list[Column]] = {}


def interfaces() -> list[str]:
    """The interfaces the dataset holds, each a folder `interface=<name>`."""
    return list(_KINDS)


def kinds(interface: str = PRIMARY) -> list[str]:
    """The kinds an interface's part of the dataset has, each a folder `kind=<name>`."""
    if interface not in _KINDS:
        raise ValueError(f"the dataset holds the interfaces {', '.join(_KINDS)}, not {interface!r}")
    return list(_KINDS[interface])


def columns_of(interface: str, kind: str) -> list[Column]:
    if (interface, kind) not in _COLUMNS:
        if kind not in kinds(interface):
            raise ValueError(f"no kind {kind!r} in interface {interface!r}")
        _COLUMNS[(interface, kind)] = _KINDS[interface][kind]()
    return _COLUMNS[(interface, kind)]


def dataset_schema(interface: str, kind: str):
    """The kind's pyarrow schema, the same for every capture and software version."""
    import pyarrow as pa
    lead = [pa.field("capture", pa.string(), nullable=False), pa.field("capture_file", pa.string()),
            pa.field("position", pa.int64(), nullable=False), pa.field("capture_time", pa.timestamp("us", "UTC"))]
    return pa.schema(lead + [pa.field(c.name, getattr(pa, _ARROW[c.kind])()) for c in columns_of(interface, kind)])


# ---- rows of a capture ---------------------------------------------------------------------

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
        if interface not in _KINDS:         # another interface of the cell: in `--out`'s tables only
            return
        # A fault of a capture file has neither robot nor time: it goes with the rows before it.
        robot = robot or self.robot or self._last[0]
        if robot is None:
            raise ValueError("a raw stream needs the robot's name (--robot)")
        date = _utc_date(time) if time is not None else self.date or self._last[1]
        if date is None:
            raise ValueError("a raw stream needs a date (--date)")
        self._last = (robot, date)
        inner = record.record if isinstance(record, Enveloped) else record
        if has_error(record) or getattr(inner, "TYPE", "unknown") == "unknown":
            yield from self._row(interface, _ERROR_KINDS[0] if has_error(record) else _ERROR_KINDS[1],
                                 robot, date, position, time, record)
            return
        if interface == REALTIME:
            yield from self._row(REALTIME, REALTIME_STATE, robot, date, position, time, inner)
            return
        if hasattr(record, "packages"):
            yield from self._row(PRIMARY, _ROBOT_STATE, robot, date, position, time, record.packages)
            for pkg in record.packages:
                if hasattr(pkg, "JSON") and not has_error(pkg):
                    yield from self._row(PRIMARY, pkg.TYPE, robot, date, position, time, pkg)
                else:
                    yield from self._row(PRIMARY, "errors" if has_error(pkg) else "unknown", robot, date, position,
                                         time, pkg)
            return
        yield from self._row(PRIMARY, record.TYPE, robot, date, position, time, record)

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
                   for column, field in zip(columns_of(interface, kind), list(schema)[len(_LEAD):])]
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
    head = fh.peek(4)[:4] if hasattr(fh, "peek") else b""
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
    """The Parts of a capture read from a binary file object (see capture_parts)."""
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


# ---- the files -----------------------------------------------------------------------------

def part_folder(root: Union[str, os.PathLike], interface: str, kind: str, robot: str, date: str) -> Path:
    return Path(root) / f"interface={interface}" / f"kind={kind}" / f"robot={_safe(robot)}" / f"date={date}"


def _safe(value: str) -> str:
    """A partition value as a folder name: '/' and ':' (an IPv6 address) cannot stand in one."""
    return value.replace("/", "_").replace(":", "_")


def _row_group_rows(schema) -> int:
    return max(1, min(ROW_GROUP_ROWS, ROW_GROUP_BYTES // sum(map(_width, schema))))


def _width(field) -> int:
    """Bytes a value of the column takes in memory, a text counted as 32."""
    try:
        return max(1, field.type.bit_width // 8)
    except ValueError:      # variable width
        return 32


class _File:
    """One Parquet file being written. Its rows go first to an Arrow stream beside it (on the disk
    the dataset is on), and become Parquet row groups when the capture ends: a row group is
    written whole, so only one, of one file, is ever held in memory, however many kinds,
    robots and days a capture fills at once."""

    def __init__(self, path: Path, schema) -> None:
        import pyarrow as pa
        self.path, self.schema = path, schema
        self.tmp = path.with_name("." + path.name + ".tmp")
        self.spill = path.with_name("." + path.name + ".arrows")
        self._sink = pa.OSFile(str(self.spill), "wb")
        self._stream = pa.ipc.new_stream(self._sink, schema)

    def add(self, table) -> None:
        self._stream.write_table(table)

    def close(self) -> None:
        """Write the Parquet file (as .tmp) from the Arrow stream, group_rows rows a row group."""
        import pyarrow as pa
        import pyarrow.parquet as pq
        self._stream.close()
        self._sink.close()
        group_rows = _row_group_rows(self.schema)
        with pa.OSFile(str(self.spill), "rb") as source, \
                pq.ParquetWriter(self.tmp, self.schema, compression="zstd", write_statistics=True) as writer:
            waiting, rows = [], 0
            for batch in pa.ipc.open_stream(source):
                waiting.append(batch)
                rows += batch.num_rows
                while rows >= group_rows:
                    table = pa.Table.from_batches(waiting, self.schema)
                    writer.write_table(table.slice(0, group_rows), row_group_size=group_rows)
                    rest = table.slice(group_rows)
                    waiting, rows = rest.to_batches(), rest.num_rows
            if rows:
                writer.write_table(pa.Table.from_batches(waiting, self.schema), row_group_size=group_rows)
        self.spill.unlink()

    def discard(self) -> None:
        if not self._sink.closed:
            self._stream.close()
            self._sink.close()
        self.spill.unlink(missing_ok=True)
        self.tmp.unlink(missing_ok=True)


def write_parts(root: Union[str, os.PathLike], parts: Iterable[Part], capture_id: str) -> dict[str, int]:
    """Write a capture's Parts under `root` as `part-<capture_id>-<n>.parquet`, one file per kind,
    robot and day (n counts a capture's files in one folder, 0 unless another writer adds more);
    files a former export of the same capture left are removed once the new ones are complete.
    `root` is a folder, or a URI pyarrow writes (s3://bucket/prefix, gs://..., hdfs://...: see
    _write_remote). Returns the rows written per kind."""
    if "://" in str(root):
        return _write_remote(str(root), parts, capture_id)
    files: dict[tuple, _File] = {}
    counts: dict[str, int] = {}
    try:
        for part in parts:
            key = (part.interface, part.kind, part.robot, part.date)
            out = files.get(key)
            if out is None:
                folder = part_folder(root, *key)
                folder.mkdir(parents=True, exist_ok=True)
                out = files[key] = _File(folder / f"part-{capture_id}-0.parquet", part.table.schema)
            out.add(part.table)
            counts[part.kind] = counts.get(part.kind, 0) + part.table.num_rows
        for out in files.values():
            out.close()
    except BaseException:
        for out in files.values():
            out.discard()
        raise
    written = {out.path for out in files.values()}
    for old in Path(root).glob(f"interface=*/kind=*/robot=*/date=*/part-{capture_id}-*.parquet"):
        if old not in written:
            old.unlink()
            _remove_empty(old.parent, Path(root))
    for out in files.values():
        os.replace(out.tmp, out.path)
    return counts


def _remove_empty(folder: Path, root: Path) -> None:
    """Remove a partition folder a capture's files left empty, and its parents up to `root`."""
    while folder != root and not any(folder.iterdir()):
        folder.rmdir()
        folder = folder.parent


def _write_remote(uri: str, parts: Iterable[Part], capture_id: str) -> dict[str, int]:
    """write_parts to a filesystem pyarrow knows by its URI (a cluster's object store): the
    capture's files are made in a local temporary folder, copied over, and then the capture's
    former files are removed, found by listing the dataset (object stores have no glob)."""
    import tempfile

    from pyarrow import fs

    filesystem, base = fs.FileSystem.from_uri(uri)
    base = base.rstrip("/")
    with tempfile.TemporaryDirectory(prefix="urwire-parts-") as local:
        counts = write_parts(local, parts, capture_id)
        written = set()
        for path in sorted(Path(local).rglob(f"part-{capture_id}-*.parquet")):
            target = f"{base}/{path.relative_to(local).as_posix()}"
            filesystem.create_dir(target.rsplit("/", 1)[0], recursive=True)
            fs.copy_files(str(path), target, source_filesystem=fs.LocalFileSystem(),
                          destination_filesystem=filesystem)
            written.add(target)
    for info in filesystem.get_file_info(fs.FileSelector(base, recursive=True, allow_not_found=True)):
        if (info.type == fs.FileType.File and info.base_name.startswith(f"part-{capture_id}-")
                and info.path not in written):
            filesystem.delete_file(info.path)
    return counts
