"""make bench-export: `urwire export` of one robot-day, the dataset against the baseline, in one run.

    python3 tests/bench/bench_export.py [--base REV] [--states N]   (default: 864000, a robot-day)

A robot sends a robot state every 100 ms: 864,000 a day. A raw stream of that many real robot
states (those of tests/tools/robot_inputs.py, repeated) is exported, each command in its own
process:

- the baseline: `urwire export --out DIR` of the package at --base (the revision before the
  dataset), taken from git into build/bench-export/REV/ (hand-written and generated parts);
- now: `urwire export --dataset ROOT` of this tree, with the decode backend it finds.

Each line gives wall and CPU time, robot states per second of wall time and peak resident memory;
the last the ratio of their times. Machines here are shared: the ratio is what counts.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from tests.tools import measure, robot_inputs  # noqa: E402
from tests.tools.revision_package import unpack_package  # noqa: E402

BASE = "a8e2eb2"        # main before `urwire export --dataset`
ROBOT_DAY = 864_000      # robot states a day at 10 Hz
MIB = 1 << 20


def package_of(revision: str) -> Path:
    """The whole urwire package of a revision (python/urwire with its generated subpackage)."""
    return unpack_package(revision, ROOT / "build" / "bench-export" / revision)


def robot_day(count: int) -> Path:
    """A raw stream of `count` real robot states, written a state at a time under build/."""
    states = robot_inputs.real_states()
    digest = hashlib.sha256(b"".join(states)).hexdigest()[:8]
    path = ROOT / "build" / f"robot-day-{digest}-{count}.bin"
    if not path.is_file():
        partial = path.with_suffix(f".{os.getpid()}.partial")
        with open(partial, "wb") as fh:
            for i in range(count):
                fh.write(states[i % len(states)])
        partial.replace(path)
    return path


def export(package: Path, args: list[str]) -> tuple[float, measure.Usage]:
    env = dict(os.environ, PYTHONPATH=str(package))
    start = time.perf_counter()
    usage = measure.watch([sys.executable, "-m", "urwire", "export", *args], env)
    wall = time.perf_counter() - start
    assert usage.returncode == 0, (args, usage.returncode)
    return wall, usage


def backend(package: str) -> str:
    """The decode backend the package uses: what urwire says, else pure Python."""
    probe = "import urwire; print(getattr(urwire, 'BACKEND', None) or getattr(urwire, 'backend', lambda: 'python')())"
    found = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                           env=dict(os.environ, PYTHONPATH=package))
    return found.stdout.strip() or "python"


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default=BASE)
    parser.add_argument("--states", type=int, default=ROBOT_DAY)
    args = parser.parse_args(argv)
    stream = robot_day(args.states)
    now = os.pathsep.join(str(ROOT / part) for part in ("python", "generated/python"))
    print(f"== urwire export of one robot-day: {args.states:,} real robot states, a raw stream of "
          f"{stream.stat().st_size / 1e6:,.0f} MB, each command in its own process")
    with tempfile.TemporaryDirectory(dir=ROOT / "build") as tmp:
        rows = {}
        for name, package, form in (
                (f"baseline {args.base}, --out", package_of(args.base), ["--out", f"{tmp}/tables"]),
                (f"now ({backend(now)} decode), --dataset", now,
                 ["--dataset", f"{tmp}/fleet", "--robot", "bench", "--date", "2024-01-01"])):
            rows[name] = export(package, [*form, str(stream)])
            wall, usage = rows[name]
            print(f"   {name:<40}{wall:>8.1f} s wall {usage.cpu:>8.1f} s CPU {args.states / wall:>10,.0f} states/s"
                  f"{usage.peak / MIB:>8.0f} MiB peak")
            shutil.rmtree(f"{tmp}/tables", ignore_errors=True)
        (old, old_usage), (new, new_usage) = rows.values()
        print(f"   speed-up: {old / new:.2f}x the baseline's wall time, "
              f"{old_usage.cpu / new_usage.cpu:.2f}x its CPU time (goal: >= 10x with the C backend)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
