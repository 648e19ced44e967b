"""make bench-c-cli: the C command (build/urwire-decode) against the Python command
(`python3 -m urwire decode`) on the same raw stream of real robot states, canonical JSON Lines
to /dev/null, in one run: MB of stream per second of CPU time (user + system, so that a busy
shared machine weighs less) and their ratio.

    python3 tests/bench/bench_cli.py [MB ...]      (default: 10 100)

The stream repeats the robot states of the bundled capture (a 5.11 robot) and of the
conformance captures that decode cleanly, built under build/ (tests/tools/robot_inputs.py).
Before the timed runs, both commands' output for the smallest stream is checked to be the same
bytes.
"""
from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from tests.tools import robot_inputs  # noqa: E402

C_CLI = ROOT / "build" / "urwire-decode"
PYTHON_CLI = [sys.executable, "-m", "urwire", "decode"]
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
C_ROUNDS = 5  # the C command runs in well under a second: the best of several
GOAL = 10  # the C command at least this many times the Python command's MB/s


def cpu_seconds(cmd: list[str], path: Path) -> float:
    """User + system CPU seconds of one run, its output thrown away."""
    with open(os.devnull, "wb") as sink:
        proc = subprocess.Popen([*cmd, str(path)], stdout=sink, env=ENV)
        _, status, usage = os.wait4(proc.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    assert code == 0, f"{cmd} exited {code}"
    return usage.ru_utime + usage.ru_stime


def output_digest(cmd: list[str], path: Path) -> str:
    result = subprocess.run([*cmd, str(path)], capture_output=True, env=ENV, check=True)
    return hashlib.sha256(result.stdout).hexdigest()


def main(argv: list[str]) -> int:
    sizes = [int(a) for a in argv] or [10, 100]
    if not C_CLI.is_file():
        print(f"{C_CLI} is missing: make build/urwire-decode", file=sys.stderr)
        return 2
    parts = robot_inputs.real_states()
    paths = {mb: robot_inputs.raw_stream(mb, parts) for mb in sorted(sizes)}
    print(f"== C command vs Python command: {len(parts)} real robot states "
          f"({sum(map(len, parts))} bytes) repeated, canonical JSON Lines to /dev/null")
    smallest = paths[min(paths)]
    same = output_digest([str(C_CLI)], smallest) == output_digest(PYTHON_CLI, smallest)
    print(f"   output on the {min(paths)} MB stream: {'the same bytes' if same else 'DIFFERENT'}")
    if not same:
        return 1
    worst = None
    for mb, path in paths.items():
        size = path.stat().st_size / 1e6
        c = min(cpu_seconds([str(C_CLI)], path) for _ in range(C_ROUNDS))
        py = cpu_seconds(PYTHON_CLI, path)
        ratio = py / c
        worst = ratio if worst is None else min(worst, ratio)
        print(f"   {size:6.1f} MB: C {size / c:7.1f} MB/s (best of {C_ROUNDS})   "
              f"Python {size / py:5.1f} MB/s (one run)   C/Python {ratio:6.1f}x")
    print(f"C command vs Python command: {worst:.1f}x the MB/s at worst (goal: {GOAL}x or more)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
