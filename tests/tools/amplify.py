"""Counts that claim far more than their bytes hold, and how much a decoder prints for them.

A MATRIX of 32767 rows and 0 columns is five bytes; read naively it is 32767 empty rows. Every
decoder must answer such a value with an error, so that its output stays in proportion to its
input, whatever the bytes: at most OUTPUT_PER_INPUT bytes printed per byte read.
"""
from __future__ import annotations

import os
import resource
import struct
import subprocess
import threading
from dataclasses import dataclass
from typing import Optional, Sequence

OUTPUT_PER_INPUT = 64             # 64 KB of output per KB of input, at the most
MEMORY_LIMIT = 2 << 30            # address space of a decoder under test: a runaway fails, not the machine
TIMEOUT = 120                     # seconds: a bound on a runaway, not a speed goal

EMPTY_ROWS = b"\x12\x7f\xff\x00\x00"     # MATRIX (5.9 code 18): 32767 rows of 0 columns


def update_message(values: bytes, timestamp: int = 0) -> bytes:
    """A global_variables_update message (start index 0) of the given value bytes."""
    body = struct.pack(">QBH", timestamp, 1, 0) + values
    return struct.pack(">iB", len(body) + 5, 25) + body


def empty_row_matrices(count: int = 167) -> bytes:
    """About 1 KB: one message of `count` top-level values, each a MATRIX of empty rows."""
    return update_message((EMPTY_ROWS + b"\x0a") * count)


def nested_empty_rows(count: int = 200) -> bytes:
    """A LIST of `count` such matrices: the LIST's count fits, its items do not."""
    return update_message(b"\x11" + struct.pack(">h", count) + EMPTY_ROWS * count + b"\x0a")


def hostile_messages() -> list[bytes]:
    """Both, and a legal message after them: about 2 KB in all."""
    return [empty_row_matrices(), nested_empty_rows(), update_message(b"\x0f\x00\x00\x00\x07\x0a", 1)]


def hostile_stream() -> bytes:
    return b"".join(hostile_messages())


def legal_stream() -> bytes:
    """As many bytes of legal matrices (1x1, of an INT), to measure a decoder's usual cost against."""
    one = b"\x12\x00\x01\x00\x01\x0f\x00\x00\x00\x07\x0a"
    return update_message(one * ((len(hostile_stream()) - 16) // len(one)))


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


@dataclass(frozen=True)
class Run:
    printed: int           # bytes on stdout, counted up to the cap
    code: Optional[int]    # exit code; None when cut off at the cap
    peak: int              # peak resident memory, bytes


def run(cmd: Sequence[str], stdin: Optional[bytes] = None, cap: Optional[int] = None,
        env: Optional[dict] = None) -> Run:
    """cmd under MEMORY_LIMIT and TIMEOUT. Reading stops once more than `cap` bytes came, and the
    process is killed, so that a runaway costs little."""
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE if stdin is not None else subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env, preexec_fn=_limit_memory)
    watchdog = threading.Timer(TIMEOUT, proc.kill)
    watchdog.start()
    printed, cut = 0, False
    try:
        if stdin is not None:
            proc.stdin.write(stdin)
            proc.stdin.close()
        while chunk := proc.stdout.read(1 << 16):
            printed += len(chunk)
            if cap is not None and printed > cap:
                cut = True
                proc.kill()
                break
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    finally:
        watchdog.cancel()
        proc.stdout.close()
    return Run(printed, None if cut else proc.returncode, usage.ru_maxrss * 1024)
