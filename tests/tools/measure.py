"""Run a command and measure it: its output, wall time, CPU time and peak resident memory (of
that child alone, from wait4), optionally with its address space limited; or, through a small
watcher process, its peak memory and CPU time whatever the size of the caller."""
from __future__ import annotations

import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from typing import Optional


def run(cmd: list[str], limit: Optional[int] = None) -> tuple[subprocess.CompletedProcess, float, int]:
    """The finished command, its seconds and its peak RSS in bytes. With `limit` (bytes), its
    address space is capped, so that a runaway fails fast instead of taking the machine's memory."""
    res, elapsed, _, peak = run_cpu(cmd, limit)
    return res, elapsed, peak


def run_cpu(cmd: list[str], limit: Optional[int] = None,
            output: bool = True) -> tuple[subprocess.CompletedProcess, float, float, int]:
    """run(), with the child's CPU seconds (user + system) too: on a shared machine its wall
    time also counts the other jobs. With `output` false, its standard output is dropped: read
    into this process, a large one would count in the peak RSS of every later child (a child
    starts as a copy of its parent)."""

    def limit_memory():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=out if output else subprocess.DEVNULL, stderr=err, text=True,
                                preexec_fn=limit_memory if limit else None)
        _, status, usage = os.wait4(proc.pid, 0)
        elapsed = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        res = subprocess.CompletedProcess(cmd, proc.returncode, out.read(), err.read())
    return res, elapsed, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024   # ru_maxrss is in KiB on Linux


# Linux counts into a child's peak RSS the peak of the process it was started from (the copy or
# the shared memory it runs on until exec), so a large parent such as pytest would show through.
# The command is started by this small watcher instead, which reports on the pipe it is given.
_WATCHER = """import os, sys
pid = os.posix_spawnp(sys.argv[2], sys.argv[2:], os.environ)
_, status, usage = os.wait4(pid, 0)
os.write(int(sys.argv[1]), b"%d %d %r" % (os.waitstatus_to_exitcode(status), usage.ru_maxrss,
                                          usage.ru_utime + usage.ru_stime))
"""


@dataclass
class Usage:
    returncode: int
    peak: int       # bytes of resident memory at most
    cpu: float      # seconds, user + system
    lines: int      # of its standard output, counted as it came and not kept
    last: bytes     # the last bytes of its standard output


def watch(cmd: list[str], env: Optional[dict] = None) -> Usage:
    """Run a command through the watcher: its peak RSS and CPU time, its output counted."""
    report, writer = os.pipe()
    try:
        proc = subprocess.Popen([sys.executable, "-c", _WATCHER, str(writer), *cmd], stdout=subprocess.PIPE,
                                env=env, pass_fds=(writer,))
    finally:
        os.close(writer)
    lines, last = 0, b""
    while chunk := proc.stdout.read(1 << 20):
        lines += chunk.count(b"\n")
        last = chunk
    proc.wait()
    with os.fdopen(report, "rb") as fh:
        code, peak_kib, cpu = fh.read().split()
    return Usage(int(code), int(peak_kib) * 1024, float(cpu), lines, last)
