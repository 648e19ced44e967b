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


# Where bytes are lost from a text-line or RTDE conversation, Python marks the line after the gap
# and the replies whose request is then unknown; the C libraries' conversations have no such
# state yet, so the command's lines differ there (docs/c.md#captures). These captures' fuzzed
# segments lose bytes so.
AFTER_GAP = "after bytes lost from the capture: its"
KNOWN_AFTER_GAP = {"ur_script_sender-golden_vectors_1_7_byte_segments-seed2-o0.pcap",
                   "rtde-golden_vectors-seed7-o0.pcap", "ur_dashboard-golden_vectors-seed1-o0.pcap",
                   "ur_dashboard-golden_vectors_1_7_byte_segments-seed1-o0.pcap"}


@pytest.mark.parametrize("variant", ["fast", "asan"])
def test_the_command_reads_a_capture_as_python_does(variant, request, tmp_path):
    """build/urwire-decode CAPTURE: every interface's records, each in its conversation's envelope,
    gaps and differing retransmissions named, byte for byte `urwire decode CAPTURE`; and with
    --protocol NAME, for each interface the capture holds, `urwire decode --protocol NAME`."""
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
            if AFTER_GAP in expected.decode():
                after_gap.add(path.name)
                continue
            assert result.stdout == expected, (path.name, protocol)
            assert result.returncode == status, (path.name, protocol)
            compared += bool(expected)
        interfaces |= held
    assert after_gap == KNOWN_AFTER_GAP
    assert len(interfaces) == 10 and compared >= 60
    with open(ROOT / "dissector" / "samples" / "cell_session.pcapng", "rb") as fh:     # stdin too
        result = subprocess.run([str(build.cli), "-"], stdin=fh, capture_output=True)
    assert result.stdout == python_lines(ROOT / "dissector" / "samples" / "cell_session.pcapng")[0] != b""
