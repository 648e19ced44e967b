"""make bench-wireshark: tshark with the native plugin (generated/epan, built by dissector/native)
and with the Lua dissector of the same interface, in one run, each against the same tshark with
`--disable-protocol <protocol>` on the same file. Times are tshark's CPU seconds (user + system):
on a shared machine its wall time also counts the other jobs. The runs with and without the
dissector take turns (with, without, with, ...: 5 of each for the native plugin, 3 for Lua), so
that a slow stretch of the machine falls on both.

For each interface whose native dissector exists (and the Lua one beside it, always), at two
sizes (30,000 and 100,000 messages; BENCH_SMALL=1 or --sizes for a quick look), three measures:
no tree (`-q -z io,stat,0`), one field (`-T fields -e <field>`) and the full tree (`-V`), each a
ratio of the least times with its goal and PASS or MISS (goals, never asserted: a benchmark is no
test). Then the dissector's cost per message at the larger size over the smaller (flat is 1): the
median of the turns' differences (with - without) per message. No ratio is given where that cost
is smaller than the differences' own spread (their interquartile range, per message): such a ratio
would measure the machine's noise.

Workloads: the primary interface as tests/bench/bench_lua.py builds it (a Version message, then
real robot states with a key message every 50th, half packed two per segment, half cut at
random); RTDE, a driver's recipe at 500 Hz as tests/bench/bench_rtde.py builds it; the real-time
interface as tests/bench/bench_realtime.py does; the dashboard server and the driver's sockets,
the conversation of the cell sample (tests/tools/cell_session.py) repeated. The captures are
written under build/bench-wireshark by a child process (writing 100,000 messages takes memory).
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "generated" / "python")]
from tests.tools import capture, measure  # noqa: E402

OUT = ROOT / "build" / "bench-wireshark"
SIZES = (30_000, 100_000)
SMALL_SIZES = (2_000, 6_000)

# name, tshark arguments before the field, goal (ratio to tshark with the protocol disabled)
MEASURES = [
    ("no tree", ["-q", "-z", "io,stat,0"], 1.15),
    ("one field", ["-T", "fields", "-e"], 1.5),
    ("-V", ["-V"], 2.5),
]


@dataclass(frozen=True)
class Interface:
    protocol: str
    field: str      # the one field of the middle measure
    unit: str       # what a message of its workload is called


INTERFACES = [
    Interface("ur", "ur.joint_data.q_actual", "messages"),
    Interface("rtde", "rtde.actual_q", "packages"),
    Interface("ur_realtime", "ur_realtime.q_actual", "packets"),
    Interface("ur_dashboard", "ur_dashboard.reply", "segments"),
    Interface("ur_reverse", "ur_reverse.target", "segments"),
    Interface("ur_script_sender", "ur_script_sender.reply", "segments"),
    Interface("ur_trajectory", "ur_trajectory.positions", "segments"),
    Interface("ur_script_command", "ur_script_command.arguments", "segments"),
]


# Captures (written in a child process: see main)

def write_ur(path: Path, count: int) -> None:
    from tests.bench import bench_lua
    bench_lua.build(path, count)


def write_rtde(path: Path, count: int) -> None:
    from tests.tools.rtde_inputs import client_bytes, packages, robot_head
    segments = [capture.Segment(False, client_bytes()), capture.Segment(True, robot_head()),
                *(capture.Segment(True, p) for p in packages(count))]
    capture.write(path, capture.session_frames(segments, port=30004), step=0.002)


def write_ur_realtime(path: Path, count: int) -> None:
    from tests.bench import bench_realtime
    pieces = capture.random_cuts([bench_realtime.stream(count)], seed=2, max_len=1448)
    capture.write(path, capture.robot_session(pieces, port=30003), step=0.002)


def write_repeated_conversation(protocol: str, path: Path, count: int) -> None:
    """The cell sample's conversation of this interface, its segments repeated to `count`."""
    from tests.tools import cell_session
    conversation = next(c for c in cell_session.conversations() if c.vector.startswith(f"{protocol}/"))
    if protocol == "ur_dashboard":    # the banner once, then the commands and replies again and again
        head, body = conversation.segments[:1], conversation.segments[1:]
    else:
        head, body = (), conversation.segments
    segments = [*head, *(body[i % len(body)] for i in range(count))]
    repeated = cell_session.Conversation(conversation.vector, conversation.port, conversation.client_port,
                                         tuple(segments), conversation.robot_listens)
    capture.write(path, repeated.frames(), step=0.002)


def write(protocol: str, path: Path, count: int) -> None:
    writers = {"ur": write_ur, "rtde": write_rtde, "ur_realtime": write_ur_realtime}
    if protocol in writers:
        writers[protocol](path, count)
    else:
        write_repeated_conversation(protocol, path, count)


def workload(protocol: str, count: int) -> Path:
    path = OUT / f"{protocol}_{count}.pcap"
    if not path.exists():
        partial = path.with_suffix(".partial")
        subprocess.run([sys.executable, __file__, "--write", protocol, str(partial), str(count)], check=True)
        partial.rename(path)
    return path


# Running tshark

@dataclass(frozen=True)
class Dissector:
    name: str                  # "native" or "Lua"
    prefix: list[str]          # before "tshark": the user and the HOME it runs with (both exec)
    args: list[str]            # after it
    turns: int                 # runs with it, and as many without; Lua costs 10-100x the noise


def in_home(home: Path) -> list[str]:
    return ["env", "-u", "XDG_CONFIG_HOME", f"HOME={home}"]


def native_dissector() -> Dissector:
    """The plugin the tests build (RelWithDebInfo: -O2), run as nobody under root: Wireshark
    loads no personal plugin for root."""
    from tests.native import harness
    built = harness.plugin("gcc")
    return Dissector("native", [*(harness.NOBODY if os.geteuid() == 0 else []), *in_home(built.home)], [], 5)


def lua_dissector(protocol: str) -> Dissector:
    from tests.native import harness
    return Dissector("Lua", in_home(harness._empty_home()), ["-X", f"lua_script:{harness.lua_plugin(protocol)}"], 3)


@dataclass(frozen=True)
class Turns:
    """CPU seconds of runs with the dissector and without it, in the order they took turns."""
    on: list[float]
    off: list[float]

    def ratio(self) -> float:
        return min(self.on) / min(self.off)

    def differences(self) -> list[float]:
        return [a - b for a, b in zip(self.on, self.off)]

    def cost(self) -> float:
        """What the dissector adds, by the median of the turns: robust to one slow stretch."""
        return statistics.median(self.differences())

    def spread(self) -> float:
        """The interquartile range of the differences (with three turns, the most less the least)."""
        low, _, high = statistics.quantiles(self.differences(), n=4)
        return high - low


def cpu_seconds(dissector: Dissector, pcap: Path, args: list[str]) -> float:
    cmd = [*dissector.prefix, "tshark", "-r", str(pcap), *dissector.args, *args]
    res, _, cpu, _ = measure.run_cpu(cmd, output=False)
    if res.returncode != 0 or "Lua: Error" in res.stderr:
        sys.exit(f"tshark ({dissector.name}) failed: {res.stderr[:500]}")
    return cpu


def take_turns(dissector: Dissector, pcap: Path, args: list[str], off: list[str]) -> Turns:
    on_times, off_times = [], []
    for _ in range(dissector.turns):
        on_times.append(cpu_seconds(dissector, pcap, args))
        off_times.append(cpu_seconds(dissector, pcap, [*off, *args]))
    return Turns(on_times, off_times)


def verdict(ratio: float, goal: float) -> str:
    return "PASS" if ratio <= goal else "MISS"


def bench(interface: Interface, sizes: tuple[int, int], dissectors: list[Dissector]) -> None:
    off = ["--disable-protocol", interface.protocol]
    turns: dict[tuple[str, str, int], Turns] = {}
    print(f"{interface.protocol}: tshark CPU seconds, the least of the turns with the dissector / with {' '.join(off)}"
          f" ({', '.join(f'{d.name} {d.turns}' for d in dissectors)} turns)")
    header = "".join(f" | {d.name:>6s} {'off':>6s} {'ratio':>6s} {'':4s}" for d in dissectors)
    for count in sizes:
        pcap = workload(interface.protocol, count)
        print(f"  {count:,} {interface.unit} ({pcap.stat().st_size >> 20} MiB)")
        print(f"    {'measure':10s} {'goal':>5s}{header}")
        for name, args, goal in MEASURES:
            args = [*args, interface.field] if name == "one field" else args
            row = ""
            for dissector in dissectors:
                timed = turns[dissector.name, name, count] = take_turns(dissector, pcap, args, off)
                row += f" | {min(timed.on):6.2f} {min(timed.off):6.2f} {timed.ratio():6.2f} {verdict(timed.ratio(), goal)}"
            print(f"    {name:10s} {goal:5.2f}{row}")
    small, large = sizes
    print(f"  cost per message, the median of the turns' (with - off) / {interface.unit}, "
          f"{large:,} against {small:,}: flat is 1.00")
    for name, *_ in MEASURES:
        cells = []
        for dissector in dissectors:
            at_large, at_small = turns[dissector.name, name, large], turns[dissector.name, name, small]
            a, b = at_large.cost() / large, at_small.cost() / small
            spread = max(at_large.spread() / large, at_small.spread() / small)
            # without a tree the native dissector can cost less than the baseline, where another
            # dissector (MRCPv2 on 30001-30004) reads the stream: no ratio then; nor when the cost
            # is smaller than the turns' own spread, where a ratio would measure the noise
            if a <= 0 or b <= 0:
                ratio = "  n/a (below the baseline)"
            elif min(a, b) < spread:
                ratio = f"  n/a (within the turns' spread, {spread * 1e6:.2f} us)"
            else:
                ratio = f"{a / b:5.2f}"
            cells.append(f"{dissector.name} {a * 1e6:7.2f} us against {b * 1e6:7.2f} us, {ratio}")
        print(f"    {name:10s} " + "   ".join(cells))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs=2, help="the two sizes (default 30,000 and 100,000; "
                        f"{SMALL_SIZES[0]:,} and {SMALL_SIZES[1]:,} with BENCH_SMALL=1)")
    parser.add_argument("--interfaces", nargs="*", help="protocols to measure (default: every one)")
    parser.add_argument("--write", nargs=3, metavar=("PROTOCOL", "PATH", "COUNT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.write:
        protocol, path, count = args.write
        write(protocol, Path(path), int(count))
        return 0
    sizes = tuple(args.sizes or (SMALL_SIZES if os.environ.get("BENCH_SMALL") else SIZES))
    OUT.mkdir(parents=True, exist_ok=True)
    native = {p.stem[len("packet-"):].replace("-", "_") for p in (ROOT / "generated" / "epan").glob("packet-*.c")}
    chosen = [i for i in INTERFACES if not args.interfaces or i.protocol in args.interfaces]
    for interface in chosen:
        dissectors = [lua_dissector(interface.protocol)]
        if interface.protocol in native:
            dissectors.insert(0, native_dissector())
        else:
            print(f"{interface.protocol}: no native dissector yet (generated/epan), Lua alone")
        bench(interface, sizes, dissectors)
    return 0


if __name__ == "__main__":
    sys.exit(main())
