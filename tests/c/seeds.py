"""Inputs built from the golden and conformance vectors, for the fuzzer and the demo.

    python3 tests/c/seeds.py [--harness urwire|json|python] DIR
                                              one fuzz seed per vector (and per message) in DIR
    python3 tests/c/seeds.py --stream FILE    a raw stream: every conformance message, in order
    python3 tests/c/seeds.py --capture PCAP FILE
                                              the robot->client bytes of the first primary
                                              stream of a .pcap/.pcapng (`urwire streams` writes
                                              every conversation's)

A fuzz input is one control byte (software version and chunking, see fuzz_urwire.c and
tests/tools/fuzz_inputs.py), then the stream. Besides the vectors, the seeds hold long messages at and around the 1 MiB length
limit, which mutation alone never grows to.
"""
from __future__ import annotations

import hashlib
import struct
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]

import vectors  # noqa: E402
from urwire.generated.spec import MAX_MESSAGE_LENGTH  # noqa: E402


KNOWN_TYPES = {5, 16, 20, 22, 23, 24, 25, 255}


def messages(data: bytes) -> list[bytes]:
    """The well-framed messages at the start of a stream (stops at the first implausible header)."""
    out, pos = [], 0
    while pos + 5 <= len(data):
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or n > MAX_MESSAGE_LENGTH or data[pos + 4] not in KNOWN_TYPES or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    return out


def message(mtype: int, body: bytes) -> bytes:
    return struct.pack(">iB", 5 + len(body), mtype) + body


def long_messages(resync: bool = True) -> list[bytes]:
    """Streams whose messages reach the length limit, pass it, or cross the CLI's 64 KiB reads.
    Their parts are about 1 KiB each: a run then costs milliseconds, not seconds. With resync
    False, none that resynchronises across a whole MiB (a second of Python's time each)."""
    limit = MAX_MESSAGE_LENGTH
    fill = bytes(range(256)) * (limit // 256 + 1)
    text = ("wörld € ✓ " * (limit // 8)).encode()

    def packages(count: int) -> bytes:   # unknown sub-packages filling a robot state to the limit
        size, rest = divmod(limit - 5, count)
        return b"".join(struct.pack(">iB", size + (rest if i == 0 else 0), 99) + fill[:size - 5 + (rest if i == 0 else 0)]
                        for i in range(count))

    at_limit = message(16, packages(1))
    many_packages = message(16, packages(1024))
    text_message = message(20, struct.pack(">QbB", 1, -2, 0) + text[:limit - 20] + b"\xc3\xff\xe2\x82")
    names = message(25, struct.pack(">QBH", 1, 0, 0) + (b"var_" + b"x" * 1019 + b"\n") * ((limit - 16) // 1024))
    strings = message(25, struct.pack(">QBH", 1, 1, 0) + (b"\x03\x7f\xf0" + text[:32752] + b"\n") * 31)
    short_strings = message(25, struct.pack(">QBH", 1, 1, 0) + (b"\x03\x03\xfb" + text[:1019] + b"\n") * 1000)
    above = struct.pack(">iB", limit + 1, 16) + fill[:limit - 4]
    cut = at_limit[:limit - 1000]
    # Small messages up to just before a 64 KiB boundary, then one that straddles it.
    short_text = message(20, struct.pack(">QbB", 1, -2, 0) + b"x" * 50)
    before = short_text * ((65536 - 10) // len(short_text))
    straddle = before + message(20, struct.pack(">QbB", 1, -2, 0) + text[:70000])
    found = [at_limit, many_packages, text_message, names, strings, short_strings, cut, straddle,
             at_limit + names]                     # two at the limit: the framer buffer slides
    if resync:
        found += [above, at_limit[:limit - 100] + at_limit]   # the second one cut short, then one whole
    return found


HINT_TEXTS = [b"5.25.1", b" 3.2\n", b"1.8", b"10.7", b"5.09", b"5.9.999999", b"5.x", b"5", b"5..9"]


def seeds(harness: str = "urwire") -> list[bytes]:
    """Seeds of one harness: urwire (tests/c/fuzz_urwire.c), json (tests/c/fuzz_json.c) or python
    (tests/python/fuzz_decoder.py), whose control bytes read alike but for the hint text the
    last two take (tests/tools/fuzz_inputs.py)."""
    found = []
    for case in vectors.all_cases():
        control = {None: 0, "3.2": 1, "5.0": 2}.get(case.version, 3)
        found.append(bytes([control]) + case.data)
        found += [bytes([0]) + m for m in messages(case.data)]
    found += [bytes([0]) + stream for stream in long_messages(resync=harness != "python")]
    if harness != "urwire":
        cases = vectors.golden_cases()
        found += [b"\x04" + text + b"\0" + cases[i % len(cases)].data for i, text in enumerate(HINT_TEXTS)]
    return found


def stream() -> bytes:
    return b"".join(case.data for case in vectors.conformance_cases())


def capture_stream(pcap: Path) -> bytes:
    """The first robot->client stream of the primary interface in a capture, as `urwire streams`
    writes it."""
    from urwire.reading import ports_read
    from urwire.streams import payloads

    first, out = None, bytearray()
    with pcap.open("rb") as fh:
        for direction, data in payloads(fh, ports_read("ur")):
            if direction is None or direction.direction != "from_robot" or not isinstance(data, bytes):
                continue
            first = first or direction
            if direction == first:
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
    harness = "urwire"
    if len(argv) == 3 and argv[0] == "--harness":
        harness, argv = argv[1], argv[2:]
    if len(argv) != 1 or harness not in ("urwire", "json", "python"):
        print(__doc__, file=sys.stderr)
        return 2
    folder = Path(argv[0])
    folder.mkdir(parents=True, exist_ok=True)
    for seed in seeds(harness):
        (folder / hashlib.sha1(seed).hexdigest()).write_bytes(seed)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
