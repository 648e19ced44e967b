"""make bench-lua: tshark with the generated dissector against the same tshark with
`--disable-protocol ur`, on the same large capture built now (not committed), in one run.

Three workloads: no tree (`-q -z io,stat,0`), selected fields (`-T fields -e ...`) and the full
tree (`-V`, on a tenth of the file to keep the bench short). Prints each ratio.

Then bytes carried by hand: a 100 KB message in 1-7 byte segments after one bad header, against
the same message without it (which TCP reassembly puts together), both with the dissector:
the ratios of time and of tshark's peak memory.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
from tests.tools import after_fault, capture, measure  # noqa: E402
from tests.vectors import parse_hex  # noqa: E402

PLUGIN = ROOT / "generated" / "lua" / "urwire.lua"
MESSAGES = 100_000
CARRIED = 100_000   # bytes of the message carried after the bad header


def build(path: Path, count: int) -> Path:
    conf = ROOT / "tests" / "conformance" / "Universal_Robots_Client_Library"
    state = parse_hex((conf / "robot_state_real_robot_5.11_pr137.hex").read_text(), "state")
    key = parse_hex((conf / "key_message_program_started.hex").read_text(), "key")
    version = parse_hex((conf / "version_message_urcontrol5.24.hex").read_text(), "version")
    msgs = [version] + [key if i % 50 == 49 else state for i in range(count - 1)]
    # Realistic framing: mostly one message per segment, some packed, some split.
    segs = capture.packed(msgs[:count // 2], per_segment=2) + capture.random_cuts(msgs[count // 2:], seed=1, max_len=1460)
    return capture.write(path, capture.robot_session(segs))


def measured(args: list[str]) -> tuple[float, int]:
    """tshark's seconds and peak RSS (bytes)."""
    res, elapsed, peak = measure.run(["tshark", *args])
    if res.returncode != 0 or "Lua: Error" in res.stderr:
        sys.exit(f"tshark failed: {res.stderr[:500]}")
    return elapsed, peak


def carried_by_hand(tmp: Path, lua: list[str]) -> None:
    """The message after a bad header against the same message without it, same tshark run."""
    clean = after_fault.write(tmp / "clean.pcap", size=CARRIED, bad_header=False)
    bad = after_fault.write(tmp / "bad.pcap", size=CARRIED)
    args = ["-2", "-T", "fields", "-e", "ur.text.text"]
    clean_s, clean_rss = measured(["-r", str(clean), *lua, *args])
    bad_s, bad_rss = measured(["-r", str(bad), *lua, *args])
    mib = 1 << 20
    print(f"bench-lua: a {CARRIED // 1000} KB message in 1-7 byte segments after a bad header, against "
          f"without it ({' '.join(args[:3])})")
    print(f"  {'time':28s} after {bad_s:6.2f} s     without {clean_s:6.2f} s     ratio {bad_s / clean_s:5.2f}")
    print(f"  {'peak RSS':28s} after {bad_rss / mib:6.0f} MiB   without {clean_rss / mib:6.0f} MiB   "
          f"ratio {bad_rss / clean_rss:5.2f}")


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        big = build(Path(tmp) / "big.pcap", MESSAGES)
        small = build(Path(tmp) / "small.pcap", MESSAGES // 10)
        lua = ["-X", f"lua_script:{PLUGIN}"]
        off = ["--disable-protocol", "ur"]
        fields = ["-T", "fields", "-e", "ur.type", "-e", "ur.robot_mode_data.robot_mode", "-e", "ur.joint_data.q_actual"]
        runs = [
            ("no tree (-q -z io,stat,0)", big, ["-q", "-z", "io,stat,0"]),
            ("fields (-T fields -e ...)", small, fields),
            ("full tree (-V)", small, ["-V"]),
        ]
        print(f"bench-lua: {MESSAGES} messages ({big.stat().st_size // 1024} KiB); fields and -V on {MESSAGES // 10}")
        for name, pcap, args in runs:
            base, _ = measured(["-r", str(pcap), *lua, *off, *args])
            with_ur, _ = measured(["-r", str(pcap), *lua, *args])
            print(f"  {name:28s} ur {with_ur:6.2f} s   ur disabled {base:6.2f} s   ratio {with_ur / base:5.2f}")
        carried_by_hand(Path(tmp), lua)
    return 0


if __name__ == "__main__":
    sys.exit(main())
