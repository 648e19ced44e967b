"""Python decode speed on real robot-state messages, against python-urx in the same run.

python-urx (urx.ursecmon.ParserUtils, the `urx` package on PyPI) decodes less than urwire:
it stops at the sub-packages it knows, types no enums and keeps no bytes for re-encoding.
The figure that counts is the ratio, measured here side by side: these machines are noisy.
Also: reading a capture whose TCP segments come in reverse order, against the same capture in
order (the reassembly holds early segments ordered, so the two should cost about the same).
"""
from __future__ import annotations

import logging
import sys
import tempfile
import timeit
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "generated" / "python"), str(ROOT)]

import urwire  # noqa: E402

CONFORMANCE = ROOT / "tests" / "conformance" / "Universal_Robots_Client_Library"
SAMPLES = ["robot_state_real_robot_5.11_pr137", "robot_state_ursim5.8_ur5e_first"]
REPEAT, NUMBER = 7, 300
CAPTURE_MESSAGES = 4000


def best(fn) -> float:
    """Seconds per call: the best of REPEAT runs of NUMBER calls (the least disturbed run)."""
    return min(timeit.repeat(fn, number=NUMBER, repeat=REPEAT)) / NUMBER


def main() -> int:
    logging.disable(logging.CRITICAL)  # urx logs every package it skips
    from urx.ursecmon import ParserUtils

    print("Python decode of real robot-state messages (best of %d x %d calls)" % (REPEAT, NUMBER))
    print(f"{'message':<38}{'bytes':>7}{'urx us':>10}{'urwire us':>11}{'speed-up':>10}")
    ratios = []
    for name in SAMPLES:
        data = bytes.fromhex((CONFORMANCE / f"{name}.hex").read_text().strip())
        record = urwire.decode_message(data)
        assert not urwire.canonical.has_error(record), name
        baseline = best(lambda: ParserUtils().parse(data))
        ours = best(lambda: urwire.decode_message(data))
        ratios.append(baseline / ours)
        print(f"{name:<38}{len(data):>7}{baseline * 1e6:>10.1f}{ours * 1e6:>11.1f}{baseline / ours:>9.2f}x")

    # The whole path a client runs: framing a stream of them, decoding, learning the version.
    stream = b"".join(bytes.fromhex((CONFORMANCE / f"{n}.hex").read_text().strip()) for n in SAMPLES) * 500
    framed = min(timeit.repeat(lambda: sum(1 for _ in urwire.decode_stream(stream)), number=1, repeat=3))
    print(f"framer + decode over a {len(stream) / 1e6:.1f} MB stream: {len(stream) / framed / 1e6:.1f} MB/s, "
          f"{1000 / framed:,.0f} messages/s")
    worst = min(ratios)
    print(f"urwire vs python-urx: {worst:.2f}x faster at worst (goal: 2x or more)")
    reversed_segments()
    return 0


def reversed_segments() -> None:
    """One message per TCP segment, CAPTURE_MESSAGES of them, in order and then reversed."""
    from tests.tools import capture

    messages = [bytes.fromhex((CONFORMANCE / f"{n}.hex").read_text().strip()) for n in SAMPLES]
    frames = capture.robot_session([messages[i % len(messages)] for i in range(CAPTURE_MESSAGES)])
    handshake, data, closing = frames[:3], frames[3:-3], frames[-3:]
    with tempfile.TemporaryDirectory() as tmp:
        in_order = capture.write(Path(tmp) / "in_order.pcap", frames)
        backwards = capture.write(Path(tmp) / "reversed.pcap", handshake + data[::-1] + closing)
        seconds = {}
        for path in (in_order, backwards):
            assert sum(1 for _ in urwire.decode_file(path)) == CAPTURE_MESSAGES, path.name
            seconds[path] = min(timeit.repeat(lambda: sum(1 for _ in urwire.decode_file(path)), number=1, repeat=3))
    print(f"capture of {CAPTURE_MESSAGES:,} messages: in order {seconds[in_order]:.2f} s, segments reversed "
          f"{seconds[backwards]:.2f} s ({seconds[backwards] / seconds[in_order]:.2f}x the in-order time; goal: about 1x)")


if __name__ == "__main__":
    sys.exit(main())
