"""`urwire export --dataset ROOT FILE...`: each capture added to the dataset of dataset.py."""
from __future__ import annotations

import argparse
import datetime
import os
import sys

from . import dataset
from .export_failure import export_failed


def date_arg(text: str) -> str:
    try:
        return datetime.date.fromisoformat(text).isoformat()
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a date YYYY-MM-DD: {text!r}") from None


def _mtime_date(path: str) -> str:
    return datetime.datetime.fromtimestamp(os.stat(path).st_mtime, datetime.timezone.utc).date().isoformat()


def dataset_command(args: argparse.Namespace) -> int:
    if args.format != "parquet":
        print("urwire export: --dataset writes Parquet only", file=sys.stderr)
        return 2
    try:
        import pyarrow  # noqa: F401  (an optional extra: urwire[parquet]; the dataset's files are written with it)
    except ImportError:
        print("urwire export: --dataset needs pyarrow: pip install urwire[parquet]", file=sys.stderr)
        return 2
    errors = False
    for path in args.files:
        try:
            capture = dataset.file_capture_id(path)
            with open(path, "rb") as fh:
                parts = dataset.parts_of(fh, capture, os.path.basename(path), args.version_hint, args.robot,
                                         args.date or _mtime_date(path))
                counts = dataset.write_parts(args.dataset, parts, capture)
        except (OSError, ValueError) as exc:
            return export_failed(path, exc)
        rows = ", ".join(f"{kind} {n}" for kind, n in sorted(counts.items()))
        print(f"{path}: capture {capture}: {rows or 'no rows'}", file=sys.stderr)
        errors = errors or "errors" in counts
    return 1 if errors else 0
