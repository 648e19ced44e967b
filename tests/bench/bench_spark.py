"""make bench-spark: robot-days of real robot states (864,000 each: a day at 10 Hz) written to
a dataset by `urwire spark` on Spark local[2] and by a sequential export of the same files, one
after the other, in one run: wall-clock seconds of each, states per second, and their ratio.

    python3 tests/bench/bench_spark.py [--days 10] [--states 864000] [--format pcap|raw]
    BENCH_SMALL=1 python3 tests/bench/bench_spark.py        (2,000 states a day: a quick look)

Each robot-day is a .pcap of one session in its own robot's folder, a state per TCP segment, its
frames 100 ms apart from its own midnight (so that days differ in their bytes and dates); or, with
--format raw, a raw primary stream of the same states (what a recorder of the port writes), its
day told by its modification time and its robot by --robot, as `urwire spark` reads raw streams.
Both are built once under build/bench-spark/ from the robot states of tests/tools/robot_inputs.py (the bundled
5.11 capture's and the conformance captures' that decode cleanly), repeated. The sequential
export runs in one process: for each file, dataset.capture_parts then dataset.write_parts, the
calls `urwire export --dataset` makes. Spark's time includes starting its JVM, as a submitted
job's does. Before the ratio, the two datasets are checked to hold the same part files with the
same row counts.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from tests.tools import capture, robot_inputs  # noqa: E402

WORK = ROOT / "build" / "bench-spark"
DAY = 864_000            # robot states in a day at 10 Hz
SMALL_DAY = 2_000
MIDNIGHT = 1_700_006_400.0   # 2023-11-15 00:00 UTC
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]),
           PYSPARK_PYTHON=sys.executable, PYSPARK_DRIVER_PYTHON=sys.executable,
           # local mode runs the tasks' JVM side in the driver: room for two robot-days in flight
           PYSPARK_SUBMIT_ARGS=os.environ.get("PYSPARK_SUBMIT_ARGS", "--driver-memory 8g pyspark-shell"))
SEQUENTIAL = """
import datetime, sys
from pathlib import Path
from urwire.data import dataset
from urwire.data.spark import utc_date
out, robot = sys.argv[1], sys.argv[3] or None
for path in sorted(p for p in Path(sys.argv[2]).rglob("*") if p.is_file()):
    data = path.read_bytes()
    day = utc_date(datetime.datetime.fromtimestamp(path.stat().st_mtime, datetime.timezone.utc))
    dataset.write_parts(out, dataset.capture_parts(data, path.name, None, robot, day), dataset.capture_id(data))
"""


def stamped(state: bytes, at: float) -> bytes:
    """A robot state whose robot mode data (its first sub-package: type 0 after the message's five
    header bytes and its own five) says `at` in microseconds: a .pcap's frames differ by their
    capture times, a raw stream's by what it holds, or two robot-days of the same states would be
    one capture to the dataset (a part's name comes from its capture's content)."""
    if len(state) < 18 or state[4] != 16 or state[9] != 0:
        return state
    return state[:10] + int(at * 1e6).to_bytes(8, "big") + state[18:]


RAW_ROBOT = "bench-robot"   # the robot of the raw streams (--robot): they carry no address


def robot_days(days: int, states: int, form: str = "pcap", hours: int = 1) -> Path:
    """The folder of `days` robot-days of `states` robot states each, robot-NN/day-HH.<form>: each
    day in `hours` files of consecutive states, as a recorder that starts a file every 24 / hours
    hours writes them (1: one file a day)."""
    real = robot_inputs.real_states()
    digest = hashlib.sha256(b"".join(real)).hexdigest()[:8]
    folder = WORK / f"captures-{digest}-{states}-{hours}"
    names = [f"robot-{day:02d}/day-{hour:02d}.{form}" for day in range(days) for hour in range(hours)]
    for name in names:
        path = folder / name
        if path.is_file():
            continue
        day, hour = divmod(names.index(name), hours)
        path.parent.mkdir(parents=True, exist_ok=True)
        first, last = states * hour // hours, states * (hour + 1) // hours
        payloads = [real[i % len(real)] for i in range(first, last)]
        partial = path.with_suffix(f".{os.getpid()}.partial")
        start = MIDNIGHT + day * 86_400 + first * 0.1
        if form == "raw":
            with open(partial, "wb") as out:
                out.write(b"".join(stamped(payload, start + i * 0.1) for i, payload in enumerate(payloads)))
            middle = start + len(payloads) * 0.05    # its file's middle: the day of its states
            os.utime(partial, (middle, middle))
        else:
            capture.write(partial, capture.robot_session(payloads, robot=f"192.168.56.{101 + day}"), start=start)
        partial.replace(path)
    # a folder of exactly `days` days: others built before by a larger run are left out
    chosen = WORK / f"run-{days}x{states}-{hours}-{form}"
    shutil.rmtree(chosen, ignore_errors=True)
    for name in names:
        (chosen / name).parent.mkdir(parents=True, exist_ok=True)
        os.link(folder / name, chosen / name)
    return chosen


def timed(cmd: list[str]) -> float:
    start = time.perf_counter()
    result = subprocess.run(cmd, env=ENV, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"{cmd[:4]} exited {result.returncode}:\n{result.stderr[-3000:]}")
    return seconds


def part_rows(root: Path) -> dict[str, int]:
    import pyarrow.parquet as pq

    return {str(p.relative_to(root)): pq.read_metadata(p).num_rows for p in root.rglob("*.parquet")}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--days", type=int, default=10, help="robot-days, each its own robot (default: 10)")
    parser.add_argument("--states", type=int, default=SMALL_DAY if os.environ.get("BENCH_SMALL") else DAY,
                        help=f"robot states a day (default: {DAY:,}; {SMALL_DAY:,} with BENCH_SMALL=1)")
    parser.add_argument("--format", choices=("pcap", "raw"), default="pcap",
                        help="each robot-day as a .pcap (default) or as a raw primary stream")
    parser.add_argument("--hours", type=int, default=1, choices=(1, 2, 3, 4, 6, 8, 12, 24),
                        help="files a robot-day is split into, by time (default: 1; Spark holds each "
                             "file whole in memory: a day of 1.2 GB needs room for several copies)")
    args = parser.parse_args()
    try:
        import pyspark  # noqa: F401
    except ImportError:
        print("bench-spark needs pyspark: pip install urwire[spark]", file=sys.stderr)
        return 2

    captures = robot_days(args.days, args.states, args.format, args.hours)
    size = sum(p.stat().st_size for p in captures.rglob(f"*.{args.format}"))
    robot = RAW_ROBOT if args.format == "raw" else ""
    total = args.days * args.states
    print(f"== {args.days} robot-days of {args.states:,} real robot states (.{args.format}, {args.hours} file(s) a day, {size / 1e6:,.0f} MB in all) "
          f"to a dataset: Spark local[2] against a sequential export")
    sequential_out, spark_out = WORK / "dataset-sequential", WORK / "dataset-spark"
    for out in (sequential_out, spark_out):
        shutil.rmtree(out, ignore_errors=True)
    sequential = timed([sys.executable, "-c", SEQUENTIAL, str(sequential_out), str(captures), robot])
    spark = timed([sys.executable, "-m", "urwire.data.spark", "--master", "local[2]", "--out", str(spark_out),
                   *(["--robot", robot] if robot else []), str(captures)])
    expected, got = part_rows(sequential_out), part_rows(spark_out)
    same = expected == got
    print(f"   the datasets: {'the same part files and rows' if same else 'DIFFERENT'} "
          f"({len(got)} parts, {sum(got.values()):,} rows)")
    print(f"   sequential export: {sequential:8.1f} s  {total / sequential:10,.0f} states/s")
    print(f"   Spark local[2]:    {spark:8.1f} s  {total / spark:10,.0f} states/s")
    print(f"   ratio: Spark local[2] is {sequential / spark:.2f}x the sequential export "
          f"(local[2]: two tasks at a time; the JVM's start included)")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
