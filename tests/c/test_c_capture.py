"""The C capture reader (runtime/c/capture) on its own: clean under the strict flags with gcc and
clang, and its fuzz harness (tests/c/fuzz_capture.c, ASan and UBSan) run once over every capture
the tests have and damaged copies of them, each read whole and in small chunks, which must
give the same items. What it reads is compared with the Python reader in
tests/python/test_capture_readers.py. And the command over it: `build/urwire-decode CAPTURE`
prints what `urwire decode CAPTURE` prints, with and without --protocol."""
from __future__ import annotations

import random
import shutil

import pytest

from tests.c.harness_c import OUT, ROOT, compile_c
from tests.tools.fuzz_inputs import libfuzzer_runs, run_once

CAPTURE = ROOT / "runtime" / "c" / "capture"
SOURCES = sorted(CAPTURE.glob("*.c"))
CAPTURES = sorted(p for folder in ("tests", "dissector") for pattern in ("*.pcap", "*.pcapng")
                  for p in (ROOT / folder).rglob(pattern))


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_reader_is_clean_under_the_strict_flags(cc, tmp_path):
    for source in SOURCES:
        compile_c(cc, ["-O2", "-c", f"-I{CAPTURE}"], [source], tmp_path / f"{source.stem}.o")


def test_every_capture_and_damaged_copies_pass_the_harness(tmp_path):
    if shutil.which("clang") is None:
        pytest.fail("clang is not installed (scripts/setup.sh installs it)")
    fuzzer = OUT / "fuzz" / "fuzz_capture"
    compile_c("clang", ["-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all",
                        f"-I{CAPTURE}"], [ROOT / "tests" / "c" / "fuzz_capture.c", *SOURCES], fuzzer)
    inputs = tmp_path / "inputs"
    inputs.mkdir()
    rng = random.Random(0)
    for path in CAPTURES:
        data = path.read_bytes()
        (inputs / path.name).write_bytes(data)
        for n in range(8):
            damaged = bytearray(data[:rng.randrange(1, len(data) + 1)] if n % 2 else data)
            for _ in range(1 + n % 4):
                damaged[rng.randrange(len(damaged))] = rng.randrange(256)
            (inputs / f"{path.stem}-{n}{path.suffix}").write_bytes(bytes(damaged))
    result = run_once([str(fuzzer)], [inputs], tmp_path / "crashes")
    assert result.returncode == 0, result.stderr[-3000:]
    assert libfuzzer_runs(result.stderr) >= 9 * len(CAPTURES) >= 150


def python_lines(path, protocol=None) -> tuple[bytes, int]:
    """What `urwire decode [--protocol NAME] CAPTURE` prints, and its exit status."""
    import urwire
    from urwire.canonical import fails

    records = list(urwire.decode_capture(path, protocol=protocol))
    return b"".join(urwire.to_json_line(r).encode() + b"\n" for r in records), int(any(map(fails, records)))


def shuffled_captures(tmp_path) -> list:
    """Sessions whose segments are reordered, lost, repeated and changed (as
    tests/python/test_capture_readers.py makes them): the primary interface's, the real-time
    interface's, and a driver socket's, where the robot is the client."""
    from tests.python.test_capture_readers import shuffled_session
    from tests.tools import capture as pcap

    return [pcap.write(tmp_path / f"shuffled{port}-{seed}.pcapng", shuffled_session(seed, port), pcapng=bool(seed % 2))
            for port in (30001, 30003, 50003) for seed in range(6)]


# Where bytes are lost from a text-line or RTDE conversation, the line after the gap and the
# replies whose request is then unknown say so. The fuzzed segments of some captures lose bytes
# so, of the dashboard, the script sender and RTDE: the comparison covers them.
AFTER_GAP = ("line after bytes lost from the capture", "its command is unknown", "its setup is unknown")


# Under ASan and UBSan in test-deep; make test runs the capture reader's harness and the
# interfaces' fuzz corpora under them.
@pytest.mark.parametrize("variant", ["fast", pytest.param("asan", marks=pytest.mark.deep)])
def test_the_command_reads_a_capture_as_python_does(variant, request, tmp_path):
    """build/urwire-decode CAPTURE: every interface's records, each in its conversation's envelope,
    gaps and differing retransmissions named, and the lines and replies after a gap marked, byte
    for byte `urwire decode CAPTURE`; and with --protocol NAME, for each interface the capture
    holds, `urwire decode --protocol NAME`."""
    import json
    import subprocess

    build = request.getfixturevalue(variant)
    compared, interfaces, after_gap = 0, set(), set()
    for path in CAPTURES + shuffled_captures(tmp_path):
        expected, status = python_lines(path)
        held = {json.loads(line).get("interface") for line in expected.splitlines()} - {None}
        for protocol in [None, *sorted(held)]:
            if protocol is not None:
                expected, status = python_lines(path, protocol)
            result = subprocess.run([str(build.cli), *(["--protocol", protocol] if protocol else []), str(path)],
                                    capture_output=True)
            after_gap |= {text for text in AFTER_GAP if text in expected.decode()}
            assert result.stdout == expected, (path.name, protocol)
            assert result.returncode == status, (path.name, protocol)
            compared += bool(expected)
        interfaces |= held
    assert after_gap == set(AFTER_GAP)
    assert len(interfaces) == 10 and compared >= 60
    with open(ROOT / "dissector" / "samples" / "cell_session.pcapng", "rb") as fh:     # stdin too
        result = subprocess.run([str(build.cli), "-"], stdin=fh, capture_output=True)
    assert result.stdout == python_lines(ROOT / "dissector" / "samples" / "cell_session.pcapng")[0] != b""


def gap_sessions() -> dict:
    """Sessions of the text-line and RTDE interfaces that lose one segment, as
    tests/python/test_gap_pairing.py makes them: (port, steps, the step lost), by what each shows."""
    from urwire import rtde
    from urwire.generated import rtde as g

    from tests.python.test_gap_pairing import BANNER, COMMANDS, REPLIES
    from tests.tools.capture import FIN

    answered = [(True, BANNER)] + [step for c, r in zip(COMMANDS, REPLIES) for step in ((False, c), (True, r))]
    at_once = [(True, BANNER)] + [(False, c) for c in COMMANDS] + [(False, FIN)] + [(True, r) for r in REPLIES]
    program = [(False, b"request_program\n"), (True, b"def prog():\n"), (True, b"x = 1\n"), (True, b"end\n")]
    setup = [(False, rtde.setup_outputs(["timestamp"], 125.0)), (True, g.SetupOutputsReply(1, ["DOUBLE"]).encode())]
    return {
        "a dashboard reply lost": (29999, answered + [(True, FIN), (False, FIN)], 6),
        "a dashboard command lost": (29999, at_once + [(True, FIN)], 2),
        "an interpreter statement lost": (30020, [(False, b"x = 1\n"), (False, b"y = 2\n"), (True, b"ack: 1: x = 1\n"),
                                                  (True, b"ack: 2: y = 2\n"), (False, FIN), (True, FIN)], 0),
        # The robot asks for the program (it is the client of 50002): the lines answer the latest ask,
        # unknown from a lost one until the next comes (here the end of a line the gap cut).
        "a script sender request lost": (50002, program + [(False, b"request_program\n"), (False, b"request_"),
                                                           (True, b"def prog():\n"), (False, b"program\n"),
                                                           (True, b"end\n"), (False, FIN), (True, FIN)], 4),
        "a script sender program line lost": (50002, program + program + [(False, FIN), (True, FIN)], 2),
        "an RTDE version request lost": (30004, [(False, rtde.request_protocol_version(2)),
                                                 (False, rtde.get_controller_version()),
                                                 (True, g.RequestProtocolVersionReply(True).encode()), *setup,
                                                 (False, FIN), (True, FIN)], 0),
        "an RTDE setup reply lost": (30004, setup + setup + [(False, rtde.start()), (True, g.StartReply(True).encode()),
                                                            (False, FIN), (True, FIN)], 1),
    }


def test_the_command_marks_what_a_gap_leaves_unsure_as_python_does(fast, tmp_path):
    """After a segment lost from either side of a text-line or RTDE conversation: the line after
    the gap, and every reply whose request the gap leaves unknown, byte for byte as Python says
    them, whichever queue (one reply per request, the latest request, RTDE's three)."""
    import subprocess

    from tests.tools import capture

    said = set()
    for name, (port, steps, lose) in gap_sessions().items():
        path = capture.write(tmp_path / f"{port}-{lose}.pcap", capture.exchange_frames(steps, port, lose=lose))
        expected, status = python_lines(path)
        result = subprocess.run([str(fast.cli), str(path)], capture_output=True)
        assert (result.stdout.decode(), result.returncode) == (expected.decode(), status), name
        said |= {text for text in ("its start may be lost", "its command is unknown", "its setup is unknown",
                                   "its protocol version request is unknown") if text in expected.decode()}
    assert len(said) == 4


def random_gap_session(seed: int, port: int) -> list[bytes]:
    """A dashboard or RTDE session whose client sends requests, some before the last reply came,
    each message in one to three segments, the robot's data packages between replies; then a few
    segments of either side are lost."""
    from collections import deque

    from urwire import rtde
    from urwire.generated import rtde as g

    from tests.python.test_gap_pairing import BANNER, COMMANDS, REPLIES
    from tests.tools.capture import FIN, exchange_frames

    rng = random.Random(seed)
    recipe = rtde.Recipe(7, "outputs", ["timestamp"], ["DOUBLE"], g.VALUE_TYPES)
    pairs = list(zip(COMMANDS, REPLIES)) if port == 29999 else [
        (rtde.request_protocol_version(2), g.RequestProtocolVersionReply(True).encode()),
        (rtde.setup_outputs(["timestamp"], 125.0), g.SetupOutputsReply(7, ["DOUBLE"]).encode()),
        (rtde.setup_inputs(["input_int_register_0"]), g.SetupInputsReply(3, ["INT32"]).encode()),
        (rtde.start(), g.StartReply(True).encode())]
    steps, awaiting = ([(True, BANNER)] if port == 29999 else []), deque()

    def send(from_robot: bool, message: bytes) -> None:
        cuts = sorted(rng.sample(range(1, len(message)), min(rng.randrange(3), len(message) - 1)))
        steps.extend((from_robot, message[a:b]) for a, b in zip([0, *cuts], [*cuts, len(message)]))

    for _ in range(30):
        if awaiting and rng.random() < 0.5:
            send(True, awaiting.popleft())
            if port == 30004 and rng.random() < 0.5:
                send(True, g.DataPackage(7, {"timestamp": 0.5}).encode(recipe))
        else:
            request, reply = rng.choice(pairs)
            send(False, request)
            awaiting.append(reply)
    lost = set(rng.sample(range(len(steps)), 3))
    frames = exchange_frames(steps + [(False, FIN), (True, FIN)], port, client_port=40000 + seed)
    return [frame for i, frame in enumerate(frames) if (i - 3) // 2 not in lost or (i - 3) % 2]


def test_the_command_reads_random_sessions_that_lose_segments_as_python_does(fast, tmp_path):
    """Dashboard and RTDE sessions made at random, each losing three segments: the same lines and
    exit status as `urwire decode`."""
    import subprocess

    from tests.tools import capture

    said = set()
    for seed in range(8):
        path = capture.write(tmp_path / f"gaps-{seed}.pcap", random_gap_session(seed, 29999)
                             + random_gap_session(seed + 100, 30004))
        expected, status = python_lines(path)
        result = subprocess.run([str(fast.cli), str(path)], capture_output=True)
        assert (result.stdout.decode(), result.returncode) == (expected.decode(), status), seed
        said |= {text for text in AFTER_GAP if text in expected.decode()}
    assert said == set(AFTER_GAP)
