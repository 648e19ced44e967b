"""make bench-c: write the robot-state messages of the conformance captures into one raw file,
then run the C benchmark on it, built at each optimisation level (decode vs memcpy of the same
bytes, measured in the same run), and compare the levels.

    python3 tests/bench/bench_c.py build/bench_c-O3 build/bench_c-O2 build/bench_c-Os [BYTES]

Each binary is named after its level (bench_c-O3: -O3) and runs ROUNDS times, the levels taking
turns so that a busy moment of a shared machine falls on all of them; each figure is the best
of its own column over those runs.
A binary named bench_c-base-O3 (make bench-c BENCH_C_BASE=<git revision>: the library that
revision generated) is compared with the current one at the same level, in the same run.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python"), str(ROOT / "tests")]

import urwire  # noqa: E402
from urwire.canonical import has_error  # noqa: E402
import vectors  # noqa: E402

sys.path.insert(0, str(ROOT / "tests" / "c"))
from seeds import messages  # noqa: E402

ROUNDS = 5
NS = re.compile(r"ns per state: decode ([\d.]+)\s+framer\+decode ([\d.]+)\s+memcpy ([\d.]+)\s+known ([\d.]+)")
# Goals for the decoder built without -O3, against -O3 (the ratio of ns per state).
GOALS = {"-O2": 1.3, "-Os": 1.8}


def robot_states() -> list[bytes]:
    """Every conformance robot state of an e-Series controller that decodes cleanly (real
    captures, not damaged ones): the ones whose layout sizes are those of the default version
    (a CB2 capture, read in its own forms by their sizes, is left out)."""
    out = []
    for case in vectors.conformance_cases():
        for msg in messages(case.data):
            if msg[4] != 16:
                continue
            records = list(urwire.decode_stream(msg))
            if not any(has_error(r) or getattr(r, "implied_version", None) for r in records):
                out.append(msg)
    return out


def level(binary: str) -> str:
    return Path(binary).name.rpartition("bench_c")[2] or "?"


def main(argv: list[str]) -> int:
    binaries = [a for a in argv if not a.isdigit()]
    extra = [a for a in argv if a.isdigit()]
    states = robot_states()
    assert states, "no robot-state messages in tests/conformance"
    path = ROOT / "build" / "bench-robot-states.bin"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"".join(states))
    print(f"== C: {len(states)} distinct conformance robot states, sizes {sorted(len(s) for s in states)}")
    best: dict[str, tuple[float, float, float, float]] = {}
    last: dict[str, str] = {}
    for _ in range(ROUNDS):
        for binary in binaries:
            result = subprocess.run([binary, str(path), *extra], capture_output=True, text=True)
            if result.returncode != 0:
                sys.stderr.write(result.stdout + result.stderr)
                return result.returncode
            ns = tuple(float(x) for x in NS.search(result.stdout).groups())
            # Each figure is the best of its own column: a run busy in one phase may be quiet in another.
            if level(binary) not in best or ns[0] < best[level(binary)][0]:
                last[level(binary)] = result.stdout
            best[level(binary)] = tuple(min(pair) for pair in zip(best.get(level(binary), ns), ns))
    for name, out in last.items():
        print(f"-- {name} (best of {ROUNDS} runs)")
        sys.stdout.write(out)
    base = best.get("-O3")
    print(f"== ns per robot state, every field of every sub-package decoded (best of {ROUNDS} runs each):")
    print("   (framer + decode: the version assumed, as in a capture that starts mid-stream; known: "
          "as after a Version message)")
    for name, (decode, frame, copy, known) in best.items():
        ratio = f"{decode / base[0]:.2f}x -O3" if base else ""
        goal = f" (goal: within {GOALS[name]}x)" if name in GOALS else ""
        if name.startswith("-base") and name[5:] in best:
            now = best[name[5:]]
            ratio = (f"now {now[0] / decode:.2f}x of it (framer + decode {now[1] / frame:.2f}x, "
                     f"known {now[3] / known:.2f}x)")
            goal = ""
        print(f"   {name:4} decode {decode:6.1f} ns   framer + decode {frame:6.1f} ns   known {known:6.1f} ns   "
              f"memcpy of the same bytes {copy:5.1f} ns   {ratio}{goal}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
