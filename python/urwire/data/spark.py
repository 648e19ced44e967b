"""`urwire spark`: a folder of captures (raw streams, .pcap, .pcapng) decoded in parallel on
Apache Spark into the dataset `urwire export --dataset` writes, one Spark task per capture.

    spark-submit --archives urwire-env.tar.gz#env urwire/data/spark.py --out /mnt/plant/urwire s3a://plant/captures
    urwire spark --master local[2] --out dataset/ captures/      (or python -m urwire.data.spark)

How: Spark's `binaryFile` source lists the folder and gives each file's bytes; `mapInArrow`
runs urwire's decoder on each (where the folder is on a filesystem every executor mounts, a
`file:` path, each task reads its file itself, which spares moving every byte through the JVM) (dataset.capture_parts) and writes its tables with the same call
the export makes (dataset.write_parts), then returns one row per table part written (path,
interface, kind, robot, date, rows): the job's manifest.

Why the tasks write the parts rather than Spark's own writer (partitionBy): a capture feeds many
tables, and each is decoded once here, where a DataFrame per kind would decode it again or move
every table through a shuffle; the part files are those of the export, named by the capture's
content, so submitting a folder again replaces its captures' parts instead of adding their rows
twice, and a task that Spark runs twice writes the same files. Why not a Python data source
(`spark.read.format("urwire")`): a data source reads into one DataFrame of one schema, and a
capture gives a table per kind.
"""
from __future__ import annotations

import argparse
import datetime
import sys
from pathlib import PurePosixPath
from typing import Callable, Iterable, Iterator, Optional
from urllib.parse import unquote, urlparse

# By their absolute names: spark-submit runs this file as its main script, outside the package.
from urwire.arguments import software_version
from urwire.data import dataset


MANIFEST = "path string, interface string, kind string, robot string, date string, rows long"


def _counted(parts: Iterable, seen: list) -> Iterator:
    """The parts, each noted in `seen` as it goes to the writer."""
    for part in parts:
        seen.append((part.interface, part.kind, part.robot, part.date, part.table.num_rows))
        yield part


def utc_date(when: datetime.datetime) -> str:
    """The UTC day of a binaryFile modificationTime (Arrow gives Spark's timestamps in UTC,
    with or without the zone named)."""
    if when.tzinfo is None:
        when = when.replace(tzinfo=datetime.timezone.utc)
    return when.astimezone(datetime.timezone.utc).date().isoformat()


def local_path(uri: str) -> Optional[str]:
    """The path of a `file:` URI (as binaryFile names a local file), else None."""
    parsed = urlparse(uri)
    return unquote(parsed.path) if parsed.scheme == "file" else None


def reads_locally(captures: str) -> bool:
    """Whether the tasks can open the folder's files themselves: a local path or a file: URI."""
    return urlparse(captures).scheme in ("", "file")


def _read(path: str) -> bytes:
    with open(local_path(path), "rb") as f:
        return f.read()


def decode_files(root: str, version_hint=None, robot: Optional[str] = None, date: Optional[str] = None) -> Callable:
    """The mapInArrow function: each capture of a batch of binaryFile rows decoded and written
    under `root`, then a manifest batch of the parts it wrote. As `urwire export --dataset`
    reads a file: its source is its name, a raw stream's robot is `robot` and its day `date`,
    else the day the file was last modified (UTC). Rows without a content column are files the
    task reads itself (from a filesystem it mounts)."""
    def run(batches):
        import pyarrow as pa  # an optional extra (urwire[spark]), there wherever Spark runs this

        for batch in batches:
            paths, times = batch.column("path"), batch.column("modificationTime")
            contents = batch.column("content") if "content" in batch.schema.names else None
            for i in range(batch.num_rows):
                path = paths[i].as_py()
                # the bytes where Arrow holds them, not a copy: a robot-day is over a gigabyte
                data = memoryview(contents[i].as_buffer()) if contents is not None else _read(path)
                seen: list = []
                parts = dataset.capture_parts(data, PurePosixPath(path).name, version_hint, robot,
                                              date or utc_date(times[i].as_py()))
                dataset.write_parts(root, _counted(parts, seen), dataset.capture_id(data))
                columns = list(zip(*seen)) or [()] * 5
                yield pa.RecordBatch.from_arrays(
                    [pa.array([path] * len(seen), pa.string())] +
                    [pa.array(values, pa.string()) for values in columns[:4]] +
                    [pa.array(columns[4], pa.int64())],
                    names=["path", "interface", "kind", "robot", "date", "rows"])
    return run


def export_folder(spark, captures: str, root: str, version_hint=None, robot: Optional[str] = None,
                  date: Optional[str] = None, through_jvm: Optional[bool] = None):
    """Decode every file under `captures` (any Hadoop path: a folder, s3a://...) into the
    dataset at `root` (a path every executor can write); returns the manifest DataFrame,
    already computed. The files' bytes go through the JVM (binaryFile's content) unless the
    folder is local (a path or file:), where each task reads its own file: `through_jvm`
    chooses (default: only where it must)."""
    if through_jvm is None:
        through_jvm = not reads_locally(captures)
    # binaryFile never splits a file; one file per partition spreads the captures over the
    # tasks, where the default packs small files into one.
    spark.conf.set("spark.sql.files.maxPartitionBytes", "1")
    spark.conf.set("spark.sql.execution.arrow.maxRecordsPerBatch", "1")
    files = (spark.read.format("binaryFile").option("recursiveFileLookup", "true")
             .load(captures)   # names starting with . or _ are left out
             .select("path", "modificationTime", *(["content"] if through_jvm else [])))   # unread unless selected
    manifest = files.mapInArrow(decode_files(root, version_hint, robot, date), MANIFEST)
    return manifest.localCheckpoint(eager=True)


def add_parser(sub) -> None:
    p = sub.add_parser("spark", help="decode a folder of captures in parallel on Apache Spark into a dataset",
                       description="Decode every raw stream, .pcap and .pcapng under FOLDER on Apache Spark, "
                                   "a task per file, into the dataset `urwire export --dataset` writes "
                                   "(docs/tables.md). Needs pyspark: pip install urwire[spark].")
    _arguments(p)
    p.set_defaults(run=spark_command)


def _arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("captures", metavar="FOLDER", help="folder of captures (a path Spark reads: file:, hdfs:, s3a:)")
    p.add_argument("--out", required=True, metavar="ROOT", help="the dataset's root, written by every executor")
    p.add_argument("--master", help="Spark master (default: spark-submit's, else local[*])")
    p.add_argument("--version-hint", type=software_version, metavar="X.Y[.Z]",
                   help="software version to assume until a Version message is seen")
    p.add_argument("--robot", metavar="NAME", help="the robot of the raw streams (a capture's robots are in it)")
    p.add_argument("--date", metavar="YYYY-MM-DD",
                   help="the day of the raw streams, which have no capture times (default: each file's mtime, UTC)")


def spark_command(args: argparse.Namespace) -> int:
    try:
        from pyspark.sql import SparkSession  # an optional extra: urwire[spark]
    except ImportError:
        print("urwire spark: needs pyspark: pip install urwire[spark]", file=sys.stderr)
        return 2
    builder = SparkSession.builder.appName("urwire")
    if args.master:
        builder = builder.master(args.master)
    spark = builder.getOrCreate()
    try:
        rows = export_folder(spark, args.captures, args.out, args.version_hint, args.robot, args.date).collect()
    finally:
        spark.stop()
    files = len({row.path for row in rows})
    print(f"{files} captures, {len(rows)} table parts, {sum(row.rows for row in rows)} rows", file=sys.stderr)
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="urwire.data.spark", description=__doc__.split("\n\n")[0])
    _arguments(parser)
    return spark_command(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
