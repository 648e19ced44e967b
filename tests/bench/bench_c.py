"""make bench-c: write the robot-state messages of the conformance captures into one raw file,
then run the C benchmark on it (decode vs memcpy of the same bytes, measured in the same run).

    python3 tests/bench/bench_c.py build/bench_c [BYTES]
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "generated" / "python"), str(ROOT / "tests")]

import urwire  # noqa: E402
from urwire.canonical import has_error  # noqa: E402
import vectors  # noqa: E402

sys.path.insert(0, str(ROOT / "tests" / "c"))
from seeds import messages  # noqa: E402


def robot_states() -> list[bytes]:
    """Every conformance robot state that decodes cleanly (real captures, not damaged ones)."""
    out = []
    for case in vectors.conformance_cases():
        for msg in messages(case.data):
            if msg[4] == 16 and not any(has_error(r) for r in urwire.decode_stream(msg)):
                out.append(msg)
    return out


def main(argv: list[str]) -> int:
    states = robot_states()
    assert states, "no robot-state messages in tests/conformance"
    path = ROOT / "build" / "bench-robot-states.bin"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"".join(states))
    print(f"== C: {len(states)} distinct conformance robot states, sizes {sorted(len(s) for s in states)}")
    return subprocess.run([argv[0], str(path), *argv[1:]]).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
