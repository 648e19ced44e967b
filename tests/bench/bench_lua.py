"""make bench-lua: tshark with the generated dissector against the same tshark with
`--disable-protocol ur`, on the same captures built now in build/bench-lua (not committed), in
one run. Times are tshark's CPU seconds (user + system, the best of a few runs): on a shared
machine its wall time also counts the other jobs.

Three workloads, on 30,000 messages: no tree (`-q -z io,stat,0`), one field (`-T fields -e
ur.joint_data.q_actual`) and the full tree (`-V`); each ratio with its goal. Then the
dissector's own cost per message at 30,000 against 10,000 messages: its time over that of a
dissector that only frames (tests/bench/framing_only.lua, on the same ports: TCP reassembly,
whose cost grows with the stream whatever dissects it), over the messages; flat when the
dissector keeps nothing per frame and what it leaves behind costs the same to collect at any
point of the capture. tshark is flat here by itself (-V without the dissector: 0.78, 2.02 and
6.16 s at 10k, 30k and 100k messages, 0.71, 1.83 and 5.69 s with the dissector that only
frames), and so is the Lua heap with the dissector (1 to 2 MB at any length); what grew was
collecting the TvbRange and TreeItem of every field at Lua's default pace from a C heap that
grows with the capture (runtime/lua/packages/collector.lua). Without a tree the figure is a difference of a
few hundredths of a second at 10k: it takes more runs. Then memory: peak RSS with the
dissector, less without it, per message, on 100,000 messages, beside what TCP reassembly alone
costs (the dissector that only frames).

Then bytes carried by hand: a 100 KB message in 1-7 byte segments after one bad header, against
the same message without it (which TCP reassembly puts together), both with the dissector:
the ratios of time and of tshark's peak memory.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from tests.tools import after_fault, capture, measure  # noqa: E402
from tests.vectors import parse_hex  # noqa: E402

# Another build of the dissector may be measured the same way: BENCH_LUA_PLUGIN=path.
PLUGIN = Path(os.environ.get("BENCH_LUA_PLUGIN", ROOT / "generated" / "lua" / "urwire.lua"))
FRAMING_ONLY = Path(__file__).resolve().parent / "framing_only.lua"
OUT = ROOT / "build" / "bench-lua"
MESSAGES = 30_000      # the workloads' capture
SHORTER = 10_000       # the same, shorter: cost per message against length
LONGER = 100_000       # memory per message
REPEAT = 3             # runs per figure, the best kept
CARRIED = 100_000      # bytes of the message carried after the bad header

# name, tshark arguments, goal (ratio to tshark without the dissector), runs on the workloads'
# capture and on the shorter one (where a run's noise weighs more; without a tree the
# dissector's own share is a few hundredths of a second there)
WORKLOADS = [
    ("no tree (-q -z io,stat,0)", ["-q", "-z", "io,stat,0"], 1.5, (9, 9)),
    ("one field (-T fields -e ...)", ["-T", "fields", "-e", "ur.joint_data.q_actual"], 4.0, (REPEAT, 5)),
    ("full tree (-V)", ["-V"], 6.0, (REPEAT, 5)),
]
GROWTH_GOAL = 1.15


def build(path: Path, count: int) -> Path:
    """A robot session of `count` messages: a Version message, then robot states with a key
    message every 50th; the first half packed two per segment, the rest cut at random (seeded)."""
    conf = ROOT / "tests" / "conformance" / "Universal_Robots_Client_Library"
    state = parse_hex((conf / "robot_state_real_robot_5.11_pr137.hex").read_text(), "state")
    key = parse_hex((conf / "key_message_program_started.hex").read_text(), "key")
    version = parse_hex((conf / "version_message_urcontrol5.24.hex").read_text(), "version")
    msgs = [version] + [key if i % 50 == 49 else state for i in range(count - 1)]
    # Realistic framing: mostly one message per segment, some packed, some split.
    segs = capture.packed(msgs[:count // 2], per_segment=2) + capture.random_cuts(msgs[count // 2:], seed=1, max_len=1460)
    return capture.write(path, capture.robot_session(segs))


def built(kind: str, path: Path, count: int) -> Path:
    """A capture written by a child process: a child's peak RSS counts its parent's memory at
    the fork, and writing 100,000 messages takes the writer gigabytes."""
    subprocess.run([sys.executable, __file__, kind, str(path), str(count)], check=True)
    return path


def write(kind: str, path: Path, count: int) -> None:
    if kind == "robot":
        build(path, count)
    else:
        after_fault.write(path, size=count, bad_header=kind == "bad")


def measured(args: list[str]) -> tuple[float, int]:
    """tshark's CPU seconds and peak RSS (bytes)."""
    res, _, cpu, peak = measure.run_cpu(["tshark", *args], output=False)
    if res.returncode != 0 or "Lua: Error" in res.stderr:
        sys.exit(f"tshark failed: {res.stderr[:500]}")
    return cpu, peak


def best(args: list[str], repeat: int = REPEAT) -> float:
    return min(measured(args)[0] for _ in range(repeat))


def lua(plugin: Path = PLUGIN) -> list[str]:
    return ["-X", f"lua_script:{plugin}"]


OFF = ["--disable-protocol", "ur"]


def workloads(big: Path, small: Path) -> None:
    print(f"  {'workload':30s} {'ur':>8s} {'disabled':>9s} {'ratio':>6s} {'goal':>5s}")
    own = {}
    for name, args, goal, repeats in WORKLOADS:
        base = best(["-r", str(big), *lua(), *OFF, *args], repeats[0])
        for pcap, count, repeat in ((big, MESSAGES, repeats[0]), (small, SHORTER, repeats[1])):
            with_ur = best(["-r", str(pcap), *lua(), *args], repeat)
            framed = best(["-r", str(pcap), *lua(FRAMING_ONLY), *args], repeat)
            own[name, count] = (with_ur - framed) / count
            if count == MESSAGES:
                print(f"  {name:30s} {with_ur:6.2f} s {base:7.2f} s {with_ur / base:6.2f} {goal:5.1f}")
    print(f"  cost per message, {MESSAGES // 1000}k against {SHORTER // 1000}k messages: the dissector's own, over "
          f"a dissector that only frames (TCP reassembly's cost, which grows with the stream, is the same "
          f"for both; goal {GROWTH_GOAL}):")
    for name, *_ in WORKLOADS:
        long_, short_ = own[name, MESSAGES], own[name, SHORTER]
        print(f"    {name:28s} {long_ * 1e6:6.1f} us against {short_ * 1e6:6.1f} us   ratio {long_ / short_:5.2f}")


def memory(longer: Path) -> None:
    args = ["-r", str(longer), "-q", "-z", "io,stat,0"]
    _, base = measured([*args, *lua(), *OFF])
    _, with_ur = measured([*args, *lua()])
    _, framed = measured([*args, *lua(FRAMING_ONLY)])
    per = lambda peak: (peak - base) / LONGER
    print(f"  memory, {LONGER // 1000}k messages, no tree: peak RSS with the dissector less without it, "
          f"{per(with_ur):6.0f} bytes per message")
    print(f"  {'':8s}of which TCP reassembly (a dissector that only frames) {per(framed):6.0f} bytes per message")


def carried_by_hand(tmp: Path) -> None:
    """The message after a bad header against the same message without it, same tshark run."""
    clean = built("clean", tmp / "clean.pcap", CARRIED)
    bad = built("bad", tmp / "bad.pcap", CARRIED)
    args = ["-2", "-T", "fields", "-e", "ur.text.text"]
    clean_s, clean_rss = measured(["-r", str(clean), *lua(), *args])
    bad_s, bad_rss = measured(["-r", str(bad), *lua(), *args])
    mib = 1 << 20
    print(f"bench-lua: a {CARRIED // 1000} KB message in 1-7 byte segments after a bad header, against "
          f"without it ({' '.join(args[:3])})")
    print(f"  {'CPU time':28s} after {bad_s:6.2f} s     without {clean_s:6.2f} s     ratio {bad_s / clean_s:5.2f}")
    print(f"  {'peak RSS':28s} after {bad_rss / mib:6.0f} MiB   without {clean_rss / mib:6.0f} MiB   "
          f"ratio {bad_rss / clean_rss:5.2f}")


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    big = built("robot", OUT / f"robot_{MESSAGES}.pcap", MESSAGES)
    small = built("robot", OUT / f"robot_{SHORTER}.pcap", SHORTER)
    longer = built("robot", OUT / f"robot_{LONGER}.pcap", LONGER)
    print(f"bench-lua: tshark CPU seconds, best of {REPEAT} runs or more, with the dissector and with "
          f"--disable-protocol ur; {MESSAGES} messages ({big.stat().st_size >> 20} MiB)")
    workloads(big, small)
    memory(longer)
    carried_by_hand(OUT)
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 4:   # a child writing one capture (see built)
        write(sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]))
        sys.exit(0)
    sys.exit(main())
