"""Run a command and measure it: its output, wall time, CPU time and peak resident memory (of
that child alone, from wait4), optionally with its address space limited."""
from __future__ import annotations

import os
import resource
import subprocess
import tempfile
import time
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
