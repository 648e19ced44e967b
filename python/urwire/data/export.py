"""`urwire export`: a capture as tables, one per message kind and per sub-package kind of the
primary interface, and per interface for the cell's other interfaces (export_cell.py).

Each table has one row per occurrence: `position` (the message's place in the input, from 0),
then, for a .pcap or .pcapng, `capture_time` (the time of the frame that completed the message,
in seconds since the epoch) and `conversation` (its TCP conversation, as decode names it), then
the fields as typed columns. Per-joint values take one column
per joint, numbered from the base: `q_actual_0` ... `q_actual_5` (a group's fields, prefixed
with the group's name when a kind has two groups; a list's items as `dh_a_0` ...).
Global-variable values and text lists are kept as their canonical JSON text. Records and
sub-packages with an error go to `errors`, and those of kinds the spec does not lay out (kept
raw, as sub-package 14) to `unknown`, each with its JSON (an error of a capture as decode prints
it, envelope included); only errors make the exit status 1, as for `decode`. Parquet needs
pyarrow (`pip install urwire[parquet]`); CSV needs nothing.
Rows are kept in a temporary file per table until the capture ends (a table's columns are
known only then), and written BATCH_ROWS rows at a time, so memory stays flat however long the
capture.
"""
from __future__ import annotations

import argparse
import csv
import marshal
import os
import sys
import tempfile
from pathlib import Path
from typing import BinaryIO, Iterator

from ..arguments import software_version
from ..canonical import has_error, member_text, shown_text, to_json_line
from ..cell import PRIMARY
from ..envelope import Enveloped
from . import export_dataset, mcap_export
from .export_cell import CellRows
from .export_failure import export_failed
from .records import conversation_text, records_of_file
# pyarrow, an optional extra (urwire[parquet]), is imported where Parquet is written: CSV needs none.

# A switch member that holds an int32 or a float32 (int|f32) fits a float64 column exactly.
_ARROW_TYPES = {"int": "int64", "uint64": "uint64", "list:uint64": "uint64", "enum": "int64", "bool": "bool_", "f32": "float32", "f64": "float64", "text": "string",
                "hex": "binary", "texts": "string", "values": "string", "list:int": "int64", "list:f64": "float64",
                "list:f32": "float32", "list:bool": "bool_", "int|f32": "float64", "int|f64": "float64"}


def add_parser(sub) -> None:
    p = sub.add_parser("export", help="write a capture as Parquet or CSV tables, one per message kind",
                       description="Write one table per message kind and per sub-package kind "
                                   "(robot_mode_data, joint_data, ...), one row per occurrence; a capture's "
                                   "other interfaces get tables named by interface (rtde_outputs_<hash> per "
                                   "RTDE recipe, ur_realtime, ur_dashboard, ...: docs/tables.md).")
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="a raw stream, a .pcap or a .pcapng file (--dataset: any number)")
    p.add_argument("--format", choices=("parquet", "csv", "mcap"), default="parquet",
                   help="table format (default: parquet); mcap: one OUT/<capture>.mcap for Foxglove (docs/mcap.md)")
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--out", metavar="DIR", help="folder for one capture's tables (made if missing)")
    where.add_argument("--dataset", metavar="ROOT",
                       help="add the captures to the Hive-partitioned Parquet dataset at ROOT (docs/tables.md): "
                            "interface=/kind=/robot=/date= folders; a capture exported again replaces its own rows")
    p.add_argument("--robot", metavar="NAME", help="--dataset: the robot of a raw stream (a capture's robots are "
                                                   "their addresses)")
    p.add_argument("--date", type=export_dataset.date_arg, metavar="YYYY-MM-DD",
                   help="--dataset: the day of a raw stream, which has no capture times (default: its file's "
                        "modification time, UTC)")
    p.add_argument("--version-hint", type=software_version, metavar="X.Y[.Z]",
                   help="software version to assume until a Version message is seen")
    p.set_defaults(run=export_command)


def _columns(obj) -> list[tuple[str, str, object]]:
    """(column, kind, value) of one message or sub-package, flattened as the module says, each
    value as `decode` shows it (see _cell)."""
    groups = [name for name, kind, _ in obj.JSON if kind == "items"]
    fields = type(obj).__dataclass_fields__
    out = []
    for name, kind, _ in obj.JSON:
        value = getattr(obj, name)
        if fields[name].metadata.get("wire") == "uint64":
            kind = "list:uint64" if kind.startswith("list:") else "uint64"
        if value is None and (kind == "items" or kind.startswith("list:")):
            continue  # not in this version's layout: its columns stay empty
        if kind == "items":
            prefix = f"{name}_" if len(groups) > 1 else ""
            for j, item in enumerate(value):
                out += [(f"{prefix}{col}_{j}", k, v) for col, k, v in _columns(item)]
        elif kind.startswith("list:"):
            item_kind = kind[len("list:"):]
            out += [(f"{name}_{j}", kind, _cell(item_kind, v)) for j, v in enumerate(value)]
        elif kind in ("texts", "values"):
            out.append((name, kind, None if value is None else _json_of(kind, value)))
        else:
            out.append((name, kind, None if value is None else _cell(kind, value)))
    return out


def _cell(kind: str, value):
    """A value as `decode` shows it, in a plain type a table takes: enums as their numbers, any
    nonzero bool byte as true, float32 NaNs (kept with their bits) as plain NaN, text with each
    invalid UTF-8 byte as U+FFFD."""
    if kind == "bool":
        return bool(value)
    if kind == "text":
        return shown_text(value)
    if isinstance(value, float):
        return float(value)
    if isinstance(value, int):
        return int(value)
    return value


def _json_of(kind: str, value) -> str:
    return member_text(kind, value)


def _apart(part) -> str:
    """The table of a record or sub-package that has no columns of its own."""
    return "errors" if has_error(part) else "unknown"


BATCH_ROWS = 1 << 13    # rows read back and written at a time (a Parquet row group)
SPILL_ROWS = 1 << 10    # rows a table holds in memory before they go to its file


class Tables:
    """Rows per kind, each kind's columns in first-seen order. They are held by column, a
    chunk of SPILL_ROWS rows at a time, and each full chunk goes to a temporary file per kind
    (marshal: its lists hold only numbers, text, bytes and None)."""

    def __init__(self, spill: Path) -> None:
        self.kinds: dict[str, dict[str, str]] = {}
        self.counts: dict[str, int] = {}
        self._spill = spill
        self._files: dict[str, BinaryIO] = {}
        self._chunks: dict[str, dict[str, list]] = {}
        self.cell = CellRows(self.add)

    def add(self, table: str, position: int, columns: list, time=None, where: tuple = ()) -> None:
        """A row: its position, capture time (when given), `where` (a capture's conversation), then
        its columns."""
        kinds = self.kinds.setdefault(table, {"position": "int"})
        chunk = self._chunks.setdefault(table, {})
        count = self.counts.get(table, 0)
        held = count % SPILL_ROWS  # rows already in the chunk
        columns = [("position", "int", position), *([("capture_time", "f64", time)] if time is not None else []),
                   *where, *columns]
        for name, kind, value in columns:
            values = chunk.get(name)
            if values is None:
                kinds.setdefault(name, kind)
                values = chunk[name] = [None] * held
            values.append(value)
        if len(columns) < len(chunk):  # columns that this row lacks stay empty
            for values in chunk.values():
                if len(values) == held:
                    values.append(None)
        self.counts[table] = count + 1
        if held + 1 == SPILL_ROWS:
            self._spill_chunk(table)

    def _spill_chunk(self, table: str) -> None:
        fh = self._files.get(table)
        if fh is None:
            fh = self._files[table] = open(self._spill / f"{table}.rows", "w+b")
        marshal.dump(self._chunks.pop(table), fh)

    def add_record(self, position: int, record) -> None:
        """One record of a capture (Enveloped, with its capture time) or of a raw stream (as it is)."""
        if not isinstance(record, Enveloped):
            self._add_primary(position, record, record, (), None)
        elif record.interface in (PRIMARY, None):   # None: a fault of the capture file, with the primary's errors
            self._add_primary(position, record.record, record, (("conversation", "text", conversation_text(record)),),
                              record.capture_time)
        else:                                       # another interface of the cell (export_cell.py)
            self.cell.add(position, record, record.capture_time)

    def _add_primary(self, position: int, record, printed, where: tuple, time) -> None:
        """A primary record's rows, each opening with `where` (a capture's conversation); one with
        an error goes to `errors` as decode prints it (`printed`: in a capture, with its envelope)."""
        if has_error(record):
            self.add("errors", position, [("record", "text", to_json_line(printed))], time, where)
            return
        if getattr(record, "TYPE", "unknown") == "unknown":
            self.add("unknown", position, [("record", "text", to_json_line(record))], time, where)
            return
        if hasattr(record, "packages"):
            self.add(record.TYPE, position, [("packages", "int", len(record.packages))], time, where)
            for pkg in record.packages:
                if hasattr(pkg, "JSON") and not has_error(pkg):
                    self.add(pkg.TYPE, position, _columns(pkg), time, where)
                else:
                    self.add(_apart(pkg), position, [("record", "text", to_json_line(pkg))], time, where)
            return
        self.add(record.TYPE, position, _columns(record), time, where)

    def batches(self, table: str) -> Iterator[tuple[int, list[list]]]:
        """The rows of a table in order, BATCH_ROWS at a time: (rows, one list per column)."""
        if self._chunks.get(table):
            self._spill_chunk(table)
        fh = self._files[table]
        fh.flush()
        fh.seek(0)
        names, left = list(self.kinds[table]), self.counts[table]
        while left:
            count, columns = 0, [[] for _ in names]
            while left and count < BATCH_ROWS:
                chunk = marshal.load(fh)
                rows = len(chunk["position"])
                for values, name in zip(columns, names):
                    values += chunk.get(name) or [None] * rows
                count, left = count + rows, left - rows
            yield count, columns

    def close(self) -> None:
        for fh in self._files.values():
            fh.close()


def gather(path: str, tables: Tables, hint=None) -> None:
    """Every record of the file: a raw stream of the primary interface, or every conversation of
    a capture that an interface of the cell reads, each by its port."""
    with open(path, "rb") as fh:
        for position, record in enumerate(records_of_file(fh, hint)):
            tables.add_record(position, record)
    tables.cell.finish()


def write_csv(tables: Tables, out: Path) -> None:
    for name, kinds in tables.kinds.items():
        hex_columns = [i for i, kind in enumerate(kinds.values()) if kind == "hex"]
        with open(out / f"{name}.csv", "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(kinds)
            for _, columns in tables.batches(name):
                for i in hex_columns:
                    columns[i] = [None if v is None else v.hex() for v in columns[i]]
                writer.writerows(zip(*columns))


def write_parquet(tables: Tables, out: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    for name, kinds in tables.kinds.items():
        schema = pa.schema([(col, getattr(pa, _ARROW_TYPES.get(kind, "string"))()) for col, kind in kinds.items()])
        with pq.ParquetWriter(out / f"{name}.parquet", schema) as writer:
            for _, columns in tables.batches(name):
                arrays = [pa.array(values, type=field.type) for values, field in zip(columns, schema)]
                writer.write_table(pa.Table.from_arrays(arrays, schema=schema))


def export_command(args: argparse.Namespace) -> int:
    if args.dataset is not None:
        return export_dataset.dataset_command(args)
    if len(args.files) > 1:
        print("urwire export: --out takes one capture (--dataset takes many)", file=sys.stderr)
        return 2
    args.file = args.files[0]
    if args.format == "mcap":
        return mcap_export.export_mcap(args.file, args.out, args.version_hint)
    if args.format == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            print("urwire export: Parquet needs pyarrow: pip install urwire[parquet] (or use --format csv)",
                  file=sys.stderr)
            return 2
    try:
        out = Path(args.out)
        os.makedirs(out, exist_ok=True)
        # The rows wait beside the tables, on the disk they go to (a temporary folder may be
        # in memory), and go when the tables are written.
        with tempfile.TemporaryDirectory(prefix=".urwire-rows-", dir=out) as spill:
            tables = Tables(Path(spill))
            try:
                gather(args.file, tables, args.version_hint)
                (write_parquet if args.format == "parquet" else write_csv)(tables, out)
            finally:
                tables.close()
    except (OSError, ValueError) as exc:
        return export_failed(args.file, exc)
    for name in sorted(tables.counts):
        print(f"{name}: {tables.counts[name]} rows", file=sys.stderr)
    return 1 if "errors" in tables.counts else 0
