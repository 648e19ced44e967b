"""Inputs of a given size made of real robot states, built once under build/: a raw stream, and
the same bytes as a .pcap or .pcapng capture of one session (a state per TCP segment).

The states are the robot states of the bundled capture (a 5.11 robot) and of the conformance
captures that decode cleanly, repeated. A file's name carries a digest of them, so that other
states give other files; `megabytes` counts the stream, so a capture is somewhat larger.
"""
from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"
CAPTURE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
for path in (ROOT, ROOT / "tests", ROOT / "tests" / "c", ROOT / "generated" / "python", ROOT / "python"):
    if str(path) not in sys.path:
        sys.path.append(str(path))


def real_states() -> list[bytes]:
    """Robot-state messages of the bundled capture and the conformance captures, each decoding
    cleanly (a CB2 capture, read in its own forms by their sizes, is left out)."""
    import urwire
    import vectors
    from urwire.canonical import has_error
    from seeds import capture_stream, messages

    found = messages(capture_stream(CAPTURE)) + [m for case in vectors.conformance_cases() for m in messages(case.data)]
    clean = []
    for msg in found:
        records = list(urwire.decode_stream(msg)) if msg[4] == 16 else []
        if records and not any(has_error(r) or getattr(r, "implied_version", None) for r in records):
            clean.append(msg)
    return clean


def _name(states: list[bytes], megabytes: int, suffix: str) -> Path:
    digest = hashlib.sha256(b"".join(states)).hexdigest()[:8]
    return BUILD / f"robot-states-{digest}-{megabytes}MB.{suffix}"


def _repeated(states: list[bytes], megabytes: int) -> list[bytes]:
    one = sum(map(len, states))
    return states * (megabytes * 1_000_000 // one + 1)


def message_count(megabytes: int, states: list[bytes] | None = None) -> int:
    """How many states the inputs of that size hold."""
    return len(_repeated(states or real_states(), megabytes))


def raw_stream(megabytes: int, states: list[bytes] | None = None) -> Path:
    states = states or real_states()
    path = _name(states, megabytes, "bin")
    if not path.is_file():
        BUILD.mkdir(exist_ok=True)
        partial = path.with_suffix(f".{os.getpid()}.partial")   # another test process may build it too
        partial.write_bytes(b"".join(_repeated(states, megabytes)))
        partial.replace(path)
    return path


def capture(megabytes: int, pcapng: bool = False, states: list[bytes] | None = None) -> Path:
    from tests.tools import capture as pcap

    states = states or real_states()
    path = _name(states, megabytes, "pcapng" if pcapng else "pcap")
    if not path.is_file():
        BUILD.mkdir(exist_ok=True)
        partial = path.with_suffix(f".{os.getpid()}.partial")
        pcap.write(partial, pcap.robot_session(_repeated(states, megabytes)), pcapng=pcapng)
        partial.replace(path)
    return path
