"""The bytes one side of a capture's TCP conversations on a port sent, reassembled, as a raw stream
for `urwire-decode --protocol NAME FILE` (which reads raw streams): the listening side's by
default, the client's with --client. Usage: port_stream.py [--client] CAPTURE PORT OUT"""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]

from urwire.capture import timed_streams  # noqa: E402
from urwire.capture_records import CaptureFault  # noqa: E402


def stream(capture: Path, port: int, from_listener: bool = True) -> bytes:
    out = bytearray()
    with capture.open("rb") as fh:
        for item in timed_streams(fh, {port}, frozenset({port})):
            # The bytes only: a raw stream has no place for a gap's or a retransmission's record.
            if not isinstance(item, CaptureFault) and item[1] == from_listener and isinstance(item[2], bytes):
                out += item[2]
    return bytes(out)


def main(argv: list[str]) -> int:
    client = argv[:1] == ["--client"]
    argv = argv[1:] if client else argv
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(argv[2])
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_bytes(stream(Path(argv[0]), int(argv[1]), not client))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
