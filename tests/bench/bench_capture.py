"""make bench-capture: `urwire decode` and `urwire export --dataset` of a capture of a cell against
the same bytes as a raw stream, and against the Python capture reader, in one run.

    python3 tests/bench/bench_capture.py [--mb 1024]

The capture is built in build/bench-capture/ (not committed) from the bundled capture of a cell
(dissector/samples/cell_session.pcapng): the robot's bytes of its primary conversation, repeated to
--mb megabytes, go out again as one TCP conversation of 1448-byte segments, each acknowledged by
the client, 100 us apart, as a .pcapng; the raw stream is the same bytes as a file. Each command
runs in its own process, with the decode backend the tree has (the C one where it is built):

- raw: `urwire decode RAW` and `urwire export --dataset ROOT RAW`;
- capture, C reader: the same of the capture (the C capture reader, runtime/c/capture);
- capture, Python reader: the same with capture.py's reader (dpkt and Python reassembly).

Each line gives wall and CPU time and MB/s of the capture's payload; the ratios, of CPU time, are the figures
(goal: the capture within 1.5x of the raw stream). Machines here are shared: ratios count. The run ends
with the figures of both commands as a table, the sizes and the command that made them.
"""
from __future__ import annotations

import argparse
import os
import shutil
import struct
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT)]

from tests.tools import measure  # noqa: E402
from urwire import capture  # noqa: E402

SAMPLE = ROOT / "dissector" / "samples" / "cell_session.pcapng"
FOLDER = ROOT / "build" / "bench-capture"
MSS = 1448
MIB = 1 << 20
GOAL = 1.5          # issue 39: decode and export --dataset of a capture within 1.5x of the raw stream
READERS = (("raw stream", "c"), ("capture, C reader", "c"), ("capture, Python reader", "python"))
ROBOT, CLIENT = bytes([192, 168, 56, 101]), bytes([192, 168, 56, 1])
PYTHON_READER = "import sys, urwire.capture as c; c.CCORE = None; from urwire.cli import main; sys.exit(main())"


def primary_bytes() -> bytes:
    """The robot's bytes of the bundled capture's primary conversation."""
    with open(SAMPLE, "rb") as fh:
        return b"".join(data for key, data, _ in capture.robot_streams(fh, {30001, 30002}))


def frame(src: bytes, dst: bytes, sport: int, dport: int, seq: int, ack: int, flags: int, payload: bytes) -> bytes:
    tcp = struct.pack("!HHIIBBHHH", sport, dport, seq, ack, 5 << 4, flags, 65535, 0, 0)
    ip = struct.pack("!BBHHHBBH4s4s", 0x45, 0, 40 + len(payload), 0, 0, 64, 6, 0, src, dst)
    return b"\x00\x11\x22\x33\x44\x55\x66\x77\x88\x99\xaa\xbb\x08\x00" + ip + tcp + payload


def block(stamp: int, data: bytes) -> bytes:
    pad = b"\x00" * (-len(data) % 4)
    length = 32 + len(data) + len(pad)
    return struct.pack("<IIIIIII", 6, length, 0, stamp >> 32, stamp & 0xFFFFFFFF, len(data), len(data)) + data + \
        pad + struct.pack("<I", length)


def build(mb: int) -> tuple[Path, Path]:
    """The raw stream and its capture, made once per size."""
    FOLDER.mkdir(parents=True, exist_ok=True)
    raw, pcapng = FOLDER / f"primary-{mb}mb.bin", FOLDER / f"cell-{mb}mb.pcapng"
    if raw.is_file() and pcapng.is_file():
        return raw, pcapng
    unit = primary_bytes()
    stream = unit * max(1, mb * MIB // len(unit))
    raw.write_bytes(stream)
    section = struct.pack("<IIIHHq", 0x0A0D0D0A, 28, 0x1A2B3C4D, 1, 0, -1) + struct.pack("<I", 28)
    interface = struct.pack("<IIHHI", 1, 20, 1, 0, 0) + struct.pack("<I", 20)
    stamp, seq, ack = 1_700_000_000_000_000, 1000, 5000
    with open(pcapng, "wb") as out:
        out.write(section + interface)
        out.write(block(stamp, frame(CLIENT, ROBOT, 50100, 30001, ack - 1, 0, 0x02, b"")))
        out.write(block(stamp, frame(ROBOT, CLIENT, 30001, 50100, seq - 1, ack, 0x12, b"")))
        out.write(block(stamp, frame(CLIENT, ROBOT, 50100, 30001, ack, seq, 0x10, b"")))
        for at in range(0, len(stream), MSS):
            stamp += 100
            piece = stream[at:at + MSS]
            out.write(block(stamp, frame(ROBOT, CLIENT, 30001, 50100, seq, ack, 0x18, piece)))
            seq += len(piece)
            out.write(block(stamp, frame(CLIENT, ROBOT, 50100, 30001, ack, seq, 0x10, b"")))
    return raw, pcapng


def run(args: list[str], reader: str) -> tuple[float, measure.Usage]:
    env = dict(os.environ, PYTHONPATH=f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}")
    start = time.perf_counter()
    code = ["-c", PYTHON_READER] if reader == "python" else ["-m", "urwire"]
    usage = measure.watch([sys.executable, *code, *args], env)
    return time.perf_counter() - start, usage


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mb", type=int, default=1024, help="megabytes of the robot's stream (default 1024)")
    options = parser.parse_args(argv)
    raw, pcapng = build(options.mb)
    payload = raw.stat().st_size / 1e6
    sizes = (f"a capture of {pcapng.stat().st_size / 1e6:.0f} MB ({pcapng.name}: {payload:.0f} MB of the robot's "
             f"primary stream, {MSS}-byte segments, each acknowledged) against the same bytes as a raw stream")
    print(f"== {sizes}")
    figures = {}
    for command in ("decode", "export"):
        times = figures[command] = {}
        for name, reader in READERS:
            path = raw if name == "raw stream" else pcapng
            dataset = FOLDER / "dataset"
            shutil.rmtree(dataset, ignore_errors=True)
            args = ["decode", "--no-progress", str(path)] if command == "decode" else \
                ["export", "--dataset", str(dataset), "--robot", "bench", str(path)]
            wall, usage = run(args, reader)
            if usage.returncode not in (0, 1):
                print(f"urwire {command} of {path.name} failed ({usage.returncode})", file=sys.stderr)
                return 1
            times[name] = usage.cpu     # the machine is shared: CPU time is the steadier figure
            print(f"  urwire {command:6} {name:24} {wall:7.2f} s wall {usage.cpu:7.2f} s CPU "
                  f"{payload / wall:7.1f} MB/s  peak {usage.peak / MIB:6.0f} MiB")
    report(figures, sizes, options.mb)
    return 0


def report(figures: dict, sizes: str, mb: int) -> None:
    """Both commands' CPU times as docs/benchmarks.md tables them, each capture against the raw
    stream (the goal) and the C reader against the Python one."""
    print(f"\n== CPU time, `BENCH_CAPTURE_MB={mb} make bench-capture`: {sizes}")
    print("| command | raw stream | capture, C reader | capture, Python reader | capture / raw | Python / C reader |")
    print("|---|---|---|---|---|---|")
    verdicts = []
    for command, label in (("decode", "`urwire decode`"), ("export", "`urwire export --dataset`")):
        times = figures[command]
        ratio = times["capture, C reader"] / times["raw stream"]
        print(f"| {label} | " + " | ".join(f"{times[name]:.2f} s" for name, _ in READERS) +
              f" | {ratio:.2f}x | {times['capture, Python reader'] / times['capture, C reader']:.2f}x |")
        verdicts.append(f"{label} {ratio:.2f}x ({'within' if ratio <= GOAL else 'beyond'} {GOAL}x)")
    print("goal, the capture within 1.5x of the raw stream: " + "; ".join(verdicts))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
