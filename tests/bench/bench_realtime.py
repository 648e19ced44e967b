"""make bench-realtime: the real-time interface (30003), packets per second.

- Python: `urwire.realtime.decode_stream` over a stream of PACKETS real-time packets (the
  e-Series 1220-byte and CB3 1116-byte layouts, alternating), CPU time; then the same with a
  canonical JSON line per packet (`to_json_line`).
- C: `build/urwire-decode --protocol ur_realtime` on the same stream, JSON Lines to /dev/null,
  CPU time: packets per second, and against the Python command (`python3 -m urwire decode
  --protocol ur_realtime`) on the same file.
- Wireshark: tshark with generated/lua/ur_realtime.lua on a capture of the same packets, against
  the same tshark with `--disable-protocol ur_realtime`: no tree (`-q -z io,stat,0`), one field
  (`-T fields -e ur_realtime.q_actual`), the full tree (`-V`).

- Per packet at the sizes users have: Python (a `RealtimeConversation` fed a megabyte at a time,
  decode only) and C (`urwire-decode --protocol ur_realtime -`, JSON Lines to /dev/null, reading
  a pipe) at `--large` packets (default 1,000,000: half an hour at 500 Hz) against `--packets`,
  the same way in the same run: whether the cost per packet stays flat. The stream is a block
  of BLOCK distinct packets sent again and again, made in this process as it is read, so that
  no file of a gigabyte is written.

The inputs are built now, under build/bench-realtime (not committed). `--packets N` (default
30,000) sets the size; a smaller N gives a quick look.
"""
from __future__ import annotations

import argparse
import os
import random
import resource
import struct
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.tools import capture, measure  # noqa: E402

OUT = ROOT / "build" / "bench-realtime"
PLUGIN = ROOT / "generated" / "lua" / "ur_realtime.lua"
CLI = ROOT / "build" / "urwire-decode"
REPEAT = 3
BLOCK = 1000     # distinct packets in the block a long stream repeats (about 1.2 MB)


def stream(count: int) -> bytes:
    """`count` packets, their doubles moving as a robot's do (seeded)."""
    rng = random.Random(1)
    out = []
    for i in range(count):
        size = 1220 if i % 2 == 0 else 1116
        n = (size - 4) // 8
        out.append(struct.pack(f">i{n}d", size, *(rng.uniform(-3.0, 3.0) for _ in range(n))))
    return b"".join(out)


def cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def python_rates(data: bytes, count: int) -> None:
    import urwire
    from urwire.realtime import decode_stream

    def best(work) -> float:
        times = []
        for _ in range(REPEAT):
            start = cpu()
            work()
            times.append(cpu() - start)
        return min(times)

    decode = best(lambda: decode_stream(data))
    lines = best(lambda: [urwire.to_json_line(r) for r in decode_stream(data)])
    print(f"  Python decode_stream            {count / decode:12,.0f} packets/s")
    print(f"  Python decode + JSON line       {count / lines:12,.0f} packets/s")


def command_rates(raw: Path, count: int) -> None:
    def best(cmd) -> float:
        times = []
        for _ in range(REPEAT):
            res, _, seconds, _ = measure.run_cpu(cmd, output=False)
            if res.returncode not in (0, 1):
                sys.exit(f"{cmd[0]} failed: {res.stderr[:500]}")
            times.append(seconds)
        return min(times)

    c = best([str(CLI), "--protocol", "ur_realtime", str(raw)])
    py = best([sys.executable, "-m", "urwire", "decode", "--protocol", "ur_realtime", "--no-progress", str(raw)])
    print(f"  C urwire-decode (JSON Lines)    {count / c:12,.0f} packets/s   {py / c:5.1f}x the Python command "
          f"({count / py:,.0f} packets/s)")


def tshark_rates(pcap: Path, count: int) -> None:
    def best(args) -> float:
        times = []
        for _ in range(REPEAT):
            res, _, seconds, _ = measure.run_cpu(["tshark", "-r", str(pcap), "-X", f"lua_script:{PLUGIN}", *args],
                                                 output=False)
            if res.returncode != 0 or "Lua: Error" in res.stderr:
                sys.exit(f"tshark failed: {res.stderr[:500]}")
            times.append(seconds)
        return min(times)

    print(f"  tshark, {count:,} packets          {'ur_realtime':>12s} {'disabled':>9s} {'ratio':>6s}")
    for name, args in (("no tree (-q -z io,stat,0)", ["-q", "-z", "io,stat,0"]),
                       ("one field (-T fields)", ["-T", "fields", "-e", "ur_realtime.q_actual"]),
                       ("full tree (-V)", ["-V"])):
        on = best(args)
        off = best(["--disable-protocol", "ur_realtime", *args])
        print(f"  {name:32s} {on:10.2f} s {off:7.2f} s {on / off:6.2f}")


def blocks(count: int, block: bytes):
    """The block, as many times as `count` packets take (a multiple of BLOCK)."""
    for _ in range(max(1, count // BLOCK)):
        yield block


def python_per_packet(count: int, block: bytes) -> float:
    from urwire.realtime import RealtimeConversation

    start, got = cpu(), 0
    conv = RealtimeConversation()
    for data in blocks(count, block):
        for at in range(0, len(data), 1 << 20):
            got += len(conv.feed(data[at:at + (1 << 20)], True))
    seconds = cpu() - start
    assert got == max(1, count // BLOCK) * BLOCK, got
    return seconds / got


def c_per_packet(count: int, block: bytes) -> float:
    """The command's CPU seconds per packet, fed through a pipe (its own process's time only)."""
    proc = subprocess.Popen([str(CLI), "--protocol", "ur_realtime", "-"], stdin=subprocess.PIPE,
                            stdout=subprocess.DEVNULL)
    for data in blocks(count, block):
        proc.stdin.write(data)
    proc.stdin.close()
    _, status, usage = os.wait4(proc.pid, 0)
    if os.waitstatus_to_exitcode(status) not in (0, 1):
        sys.exit("urwire-decode failed on the long stream")
    return (usage.ru_utime + usage.ru_stime) / (max(1, count // BLOCK) * BLOCK)


def flatness(small: int, large: int) -> None:
    block = stream(BLOCK)
    py = [python_per_packet(n, block) for n in (small, large)]
    line = (f"  per packet at {large:,} against {small:,} packets: Python {py[1] / py[0]:.2f}x "
            f"({1 / py[1]:,.0f} packets/s decoded)")
    if CLI.exists():
        c = [c_per_packet(n, block) for n in (small, large)]
        line += f", C {c[1] / c[0]:.2f}x ({1 / c[1]:,.0f} packets/s with JSON)"
    print(line)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--packets", type=int, default=30_000)
    parser.add_argument("--large", type=int, default=1_000_000, help="the size the cost per packet is "
                        "compared at, against --packets (default 1,000,000)")
    args = parser.parse_args()
    # The Python command of this tree, not an installed one.
    os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")])
    OUT.mkdir(parents=True, exist_ok=True)
    data = stream(args.packets)
    raw = OUT / f"realtime_{args.packets}.bin"
    raw.write_bytes(data)
    pieces = capture.random_cuts([data], seed=2, max_len=1448)
    pcap = capture.write(OUT / f"realtime_{args.packets}.pcap", capture.robot_session(pieces, port=30003), step=0.002)
    print(f"real-time interface: {args.packets:,} packets of 1220 and 1116 bytes, best of {REPEAT}, CPU time "
          f"({time.strftime('%Y-%m-%d')})")
    python_rates(data, args.packets)
    if CLI.exists():
        command_rates(raw, args.packets)
    else:
        print("  (build/urwire-decode missing: `make` builds it)")
    flatness(args.packets, args.large)
    tshark_rates(pcap, args.packets)
    return 0


if __name__ == "__main__":
    sys.exit(main())
