"""The C capture reader (runtime/c/capture) on its own: clean under the strict flags with gcc and
clang, and its fuzz harness (tests/c/fuzz_capture.c, ASan and UBSan) run once over every capture
the tests have and damaged copies of them, each read whole and in small chunks, which must
give the same items. What it reads is compared with the Python reader in
tests/python/test_capture_readers.py."""
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


def python_lines(path) -> tuple[bytes, int]:
    """What `urwire decode --protocol ur CAPTURE` prints, and its exit status."""
    import urwire
    from urwire.canonical import has_error

    records = list(urwire.decode_capture(path, protocol="ur"))
    return b"".join(urwire.to_json_line(r).encode() + b"\n" for r in records), int(any(map(has_error, records)))


def primary_captures(tmp_path) -> list:
    """Every capture of the tests, and primary sessions whose segments are reordered, lost,
    repeated and changed (as tests/python/test_capture_readers.py makes them)."""
    from tests.python.test_capture_readers import shuffled_session
    from tests.tools import capture as pcap

    made = [pcap.write(tmp_path / f"primary{seed}.pcapng", shuffled_session(seed, 30001), pcapng=bool(seed % 2))
            for seed in range(6)]
    return CAPTURES + made


@pytest.mark.parametrize("variant", ["fast", "asan"])
def test_the_command_reads_a_capture_as_python_does(variant, request, tmp_path):
    """build/urwire-decode CAPTURE: the primary interface's records, each in its conversation's
    envelope, gaps and differing retransmissions named, byte for byte `urwire decode --protocol ur`."""
    import subprocess

    build = request.getfixturevalue(variant)
    compared = 0
    for path in primary_captures(tmp_path):
        result = subprocess.run([str(build.cli), str(path)], capture_output=True)
        expected, status = python_lines(path)
        assert result.stdout == expected, path.name
        assert result.returncode == status, path.name
        compared += bool(expected)
    assert compared >= 8
    with open(ROOT / "dissector" / "samples" / "cell_session.pcapng", "rb") as fh:     # stdin too
        result = subprocess.run([str(build.cli), "-"], stdin=fh, capture_output=True)
    assert result.stdout == python_lines(ROOT / "dissector" / "samples" / "cell_session.pcapng")[0] != b""
