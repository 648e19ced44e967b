"""Inputs built from the golden and conformance vectors, for the fuzzer and the demo.

    python3 tests/c/seeds.py DIR              one fuzz seed per vector (and per message) in DIR
    python3 tests/c/seeds.py --stream FILE    a raw stream: every conformance message, in order
    python3 tests/c/seeds.py --capture PCAP FILE
                                              the robot->client bytes of the first TCP stream
                                              of a .pcap/.pcapng (urwire-decode reads raw streams)

A fuzz input is one control byte (software version and chunking, see fuzz_urwire.c), then
the stream.
"""
from __future__ import annotations

import hashlib
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

import vectors  # noqa: E402


KNOWN_TYPES = {5, 16, 20, 22, 23, 24, 25, 255}


def messages(data: bytes) -> list[bytes]:
    """The well-framed messages at the start of a stream (stops at the first implausible header)."""
    out, pos = [], 0
    while pos + 5 <= len(data):
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or n > 1048576 or data[pos + 4] not in KNOWN_TYPES or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    return out


def seeds() -> list[bytes]:
    found = []
    for case in vectors.all_cases():
        control = {None: 0, "3.2": 1, "5.0": 2}.get(case.version, 3)
        found.append(bytes([control]) + case.data)
        found += [bytes([0]) + m for m in messages(case.data)]
    return found


def stream() -> bytes:
    return b"".join(case.data for case in vectors.conformance_cases())


def capture_stream(pcap: Path) -> bytes:
    """The first robot->client stream of a capture, reassembled by the Python bindings."""
    sys.path.insert(0, str(ROOT / "generated" / "python"))
    from urwire.capture import robot_streams
    from urwire.spec import PORTS

    first, out = None, bytearray()
    with pcap.open("rb") as fh:
        for key, data, _ in robot_streams(fh, set(PORTS)):
            first = first or key
            if key == first and data:
                out += data
    return bytes(out)


def main(argv: list[str]) -> int:
    if len(argv) == 3 and argv[0] == "--capture":
        Path(argv[2]).parent.mkdir(parents=True, exist_ok=True)
        Path(argv[2]).write_bytes(capture_stream(Path(argv[1])))
        return 0
    if len(argv) == 2 and argv[0] == "--stream":
        Path(argv[1]).parent.mkdir(parents=True, exist_ok=True)
        Path(argv[1]).write_bytes(stream())
        return 0
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    folder = Path(argv[0])
    folder.mkdir(parents=True, exist_ok=True)
    for seed in seeds():
        (folder / hashlib.sha1(seed).hexdigest()).write_bytes(seed)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
