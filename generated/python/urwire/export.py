# Copied from codegen/templates/python/runtime/export.py: edit it there and run `make generate`.
"""`urwire export`: a capture as tables, one per message kind and per sub-package kind.

Each table has one row per occurrence: `position` (the message's place in the input, from 0),
`capture_time` (for a .pcap or .pcapng: the time of the frame that completed the message, in
seconds since the epoch), then the fields as typed columns. Per-joint values take one column per joint, numbered from the
base: `q_actual_0` ... `q_actual_5` (a group's fields, prefixed with the group's name when a
kind has two groups; a list's items as `dh_a_0` ...). Global-variable values and text lists are
kept as their canonical JSON text. Records and sub-packages with an error go to `errors`, and
those of kinds the spec does not lay out (kept raw, as sub-package 14) to `unknown`, each with
its JSON; only errors make the exit status 1, as for `decode`. Parquet needs pyarrow (`pip install urwire[parquet]`); CSV needs nothing.
Hand-written; copied into generated/python/urwire/ by `make generate`.
"""
from __future__ import annotations

import argparse
import csv
import os
import sys
from pathlib import Path

from .canonical import has_error, to_json_line
from .reading import timed_records

_ARROW_TYPES = {"int": "int64", "bool": "bool_", "f32": "float32", "f64": "float64", "text": "string",
                "hex": "binary", "texts": "string", "values": "string", "list:int": "int64", "list:f64": "float64",
                "list:f32": "float32", "list:bool": "bool_"}


def add_parser(sub, version_arg) -> None:
    p = sub.add_parser("export", help="write a capture as Parquet or CSV tables, one per message kind",
                       description="Write one table per message kind and per sub-package kind "
                                   "(robot_mode_data, joint_data, ...), one row per occurrence.")
    p.add_argument("file", help="a raw stream, a .pcap or a .pcapng file")
    p.add_argument("--format", choices=("parquet", "csv"), default="parquet", help="table format (default: parquet)")
    p.add_argument("--out", required=True, metavar="DIR", help="folder for the tables (made if missing)")
    p.add_argument("--version-hint", type=version_arg, metavar="X.Y[.Z]",
                   help="software version to assume until a Version message is seen")
    p.set_defaults(run=export_command)


def _columns(obj) -> list[tuple[str, str, object]]:
    """(column, kind, value) of one message or sub-package, flattened as the module says."""
    groups = [name for name, kind, _ in obj.JSON if kind == "items"]
    out = []
    for name, kind, _ in obj.JSON:
        value = getattr(obj, name)
        if value is None and (kind == "items" or kind.startswith("list:")):
            continue  # not in this version's layout: its columns stay empty
        if kind == "items":
            prefix = f"{name}_" if len(groups) > 1 else ""
            for j, item in enumerate(value):
                out += [(f"{prefix}{col}_{j}", k, v) for col, k, v in _columns(item)]
        elif kind.startswith("list:"):
            out += [(f"{name}_{j}", kind, v) for j, v in enumerate(value)]
        elif kind in ("texts", "values"):
            out.append((name, kind, None if value is None else _json_of(kind, value)))
        else:
            out.append((name, kind, None if value is None else (int(value) if kind == "int" else value)))
    return out


def _json_of(kind: str, value) -> str:
    from .canonical import member_text
    return member_text(kind, value)


def _apart(part) -> str:
    """The table of a record or sub-package that has no columns of its own."""
    return "errors" if has_error(part) else "unknown"


class Tables:
    """Rows gathered per kind; each kind's columns in first-seen order."""

    def __init__(self) -> None:
        self.rows: dict[str, list[dict]] = {}
        self.kinds: dict[str, dict[str, str]] = {}

    def add(self, table: str, position: int, columns: list, time=None) -> None:
        kinds = self.kinds.setdefault(table, {"position": "int"})
        row = {"position": position}
        if time is not None:
            kinds.setdefault("capture_time", "f64")
            row["capture_time"] = time
        for name, kind, value in columns:
            kinds.setdefault(name, kind)
            row[name] = value
        self.rows.setdefault(table, []).append(row)

    def add_record(self, position: int, record, time=None) -> None:
        if has_error(record) or getattr(record, "TYPE", "unknown") == "unknown":
            self.add(_apart(record), position, [("record", "text", to_json_line(record))], time)
            return
        if hasattr(record, "packages"):
            self.add(record.TYPE, position, [("packages", "int", len(record.packages))], time)
            for pkg in record.packages:
                if hasattr(pkg, "JSON") and not has_error(pkg):
                    self.add(pkg.TYPE, position, _columns(pkg), time)
                else:
                    self.add(_apart(pkg), position, [("record", "text", to_json_line(pkg))], time)
            return
        self.add(record.TYPE, position, _columns(record), time)


def gather(path: str, hint=None) -> Tables:
    tables = Tables()
    for position, (time, record) in enumerate(timed_records(path, hint)):
        tables.add_record(position, record, time)
    return tables


def write_csv(tables: Tables, out: Path) -> None:
    for name, rows in tables.rows.items():
        columns = list(tables.kinds[name])
        with open(out / f"{name}.csv", "w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, columns)
            writer.writeheader()
            for row in rows:
                writer.writerow({k: (v.hex() if isinstance(v, bytes) else v) for k, v in row.items()})


def write_parquet(tables: Tables, out: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    for name, rows in tables.rows.items():
        kinds = tables.kinds[name]
        arrays = [pa.array([row.get(col) for row in rows], type=getattr(pa, _ARROW_TYPES.get(kind, "string"))())
                  for col, kind in kinds.items()]
        pq.write_table(pa.Table.from_arrays(arrays, names=list(kinds)), out / f"{name}.parquet")


def export_command(args: argparse.Namespace) -> int:
    if args.format == "parquet":
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            print("urwire export: Parquet needs pyarrow: pip install urwire[parquet] (or use --format csv)",
                  file=sys.stderr)
            return 2
    try:
        tables = gather(args.file, args.version_hint)
        out = Path(args.out)
        os.makedirs(out, exist_ok=True)
        (write_parquet if args.format == "parquet" else write_csv)(tables, out)
    except OSError as exc:
        print(f"urwire export: {exc.filename or args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except ValueError as exc:  # dpkt: a damaged capture file
        print(f"urwire export: cannot read capture {args.file}: {exc}", file=sys.stderr)
        return 2
    for name in sorted(tables.rows):
        print(f"{name}: {len(tables.rows[name])} rows", file=sys.stderr)
    return 1 if "errors" in tables.rows else 0
