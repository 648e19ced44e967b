"""The dataset's files (dataset.py): a capture's Parts written as
`ROOT/interface=/kind=/robot=/date=/part-<capture id>-<n>.parquet`, in row groups sized for scans,
replacing the files a former export of the same capture left.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable, Union

from .dataset_columns import Part
# pyarrow, an optional extra (urwire[parquet]), is imported by the functions that write.

# The size of a row group: DuckDB and Spark give each row group to one thread, and skip a row
# group whose statistics rule it out, so a group wants to be large enough to be worth a thread
# (DuckDB's guidance is 100k to 1M rows) and small enough to be skipped often and held in memory
# while it is written: 1M rows, or fewer where a row is wide (joint_data's 52 columns reach
# 128 MiB at about 365k rows).
ROW_GROUP_ROWS = 1 << 20
ROW_GROUP_BYTES = 128 << 20
# Columns whose values differ from row to row, so that a dictionary of them never pays: Parquet's
# writer would build one per column chunk until it outgrew its page and then write them plainly.
UNIQUE_COLUMNS = ("position", "capture_time")


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
                pq.ParquetWriter(self.tmp, self.schema, compression="zstd", write_statistics=True,
                                 use_dictionary=[n for n in self.schema.names if n not in UNIQUE_COLUMNS]) as writer:
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
