"""Run a command and measure it: its output, wall time, CPU time and peak resident memory (of
that command alone, from wait4 in a small watcher process, whatever the size of the caller),
optionally with its address space limited."""
from __future__ import annotations

import os
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
    time also counts the other jobs. With `output` false, its standard output is dropped. The
    command is started by the watcher (below), so its peak is its own, not the caller's."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        start = time.perf_counter()
        proc, report = _watched(cmd, limit, out if output else subprocess.DEVNULL, err)
        proc.wait()
        elapsed = time.perf_counter() - start
        out.seek(0)
        err.seek(0)
        code, peak, cpu = _report(report, err.read())
        err.seek(0)
        res = subprocess.CompletedProcess(cmd, code, out.read(), err.read())
    return res, elapsed, cpu, peak


# Linux counts into a child's peak RSS the peak of the process it was started from (the copy or
# the shared memory it runs on until exec), so a large parent such as a pytest worker would show
# through. The command is started by this small watcher instead, which caps the address space
# it inherits (argv[2] bytes, 0 for none) and reports on the pipe it is given (argv[1]).
_WATCHER = """import os, resource, sys
limit = int(sys.argv[2])
if limit:
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
pid = os.posix_spawnp(sys.argv[3], sys.argv[3:], os.environ)
_, status, usage = os.wait4(pid, 0)
os.write(int(sys.argv[1]), b"%d %d %r" % (os.waitstatus_to_exitcode(status), usage.ru_maxrss,
                                          usage.ru_utime + usage.ru_stime))
"""


def _watched(cmd: list[str], limit: Optional[int], stdout, stderr=None,
             env: Optional[dict] = None) -> tuple[subprocess.Popen, int]:
    """The watcher running cmd, and the read end of its report's pipe."""
    report, writer = os.pipe()
    try:
        proc = subprocess.Popen([sys.executable, "-c", _WATCHER, str(writer), str(limit or 0), *cmd],
                                stdout=stdout, stderr=stderr, env=env, pass_fds=(writer,))
    finally:
        os.close(writer)
    return proc, report


def _report(report: int, stderr: str = "") -> tuple[int, int, float]:
    """The exit status, peak RSS in bytes and CPU seconds the watcher reported (it reports
    nothing when the command could not be started: its error is then in `stderr`)."""
    with os.fdopen(report, "rb") as fh:
        text = fh.read()
    if not text:
        raise OSError(f"the command did not start: {stderr[-2000:]}")
    code, peak_kib, cpu = text.split()
    return int(code), int(peak_kib) * 1024, float(cpu)   # ru_maxrss is in KiB on Linux


@dataclass
class Usage:
    returncode: int
    peak: int       # bytes of resident memory at most
    cpu: float      # seconds, user + system
    lines: int      # of its standard output, counted as it came and not kept
    last: bytes     # the last bytes of its standard output


def watch(cmd: list[str], env: Optional[dict] = None) -> Usage:
    """Run a command through the watcher: its peak RSS and CPU time, its output counted."""
    proc, report = _watched(cmd, None, subprocess.PIPE, env=env)
    lines, last = 0, b""
    while chunk := proc.stdout.read(1 << 20):
        lines += chunk.count(b"\n")
        last = chunk
    proc.wait()
    code, peak, cpu = _report(report)
    return Usage(code, peak, cpu, lines, last)
