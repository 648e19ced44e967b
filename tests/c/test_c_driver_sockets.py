"""The ROS driver's sockets in C (generated/c/ur_reverse, ur_trajectory, ur_script_command) under
gcc, clang and ASan/UBSan: the golden vectors whole and byte by byte, the same lines as Python on
random bytes of every release, and the fuzz harness of each over its kept corpus."""
from __future__ import annotations

import json
import random
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

from tests.c.harness_c import GEN, OUT, ROOT, SANITIZE, VARIANTS, compile_c
from tests.interface_vectors import Segment, bytewise, conversation_cases
from urwire import to_json_line
from urwire.generated import ur_reverse, ur_script_command, ur_trajectory

MODULES = {m.NAME: m for m in (ur_reverse, ur_trajectory, ur_script_command)}
CASES = [(name, case) for name in MODULES for case in conversation_cases(name)]
DRIVER = ROOT / "tests" / "c" / "int32_records_driver.c"
HARNESS = ROOT / "tests" / "c" / "fuzz_int32_records.c"
# Byte 0 of a harness input picks one of these (fuzz_int32_records.c's releases).
HARNESS_RELEASES = ("0.0.1", "0.400.0", "1.0.0", "1.3.1", "1.3.2", "1.5.0", "2.10.0", "2.14.0")
_BUILT: dict[tuple, Path] = {}


def macros(name: str) -> list[str]:
    return [f"-DPREFIX={name}_", f"-DUPPER={name.upper()}_", f'-DHEADER="{name}.h"']


def driver(variant: str, name: str) -> Path:
    if (variant, name) not in _BUILT:
        cc, flags = VARIANTS[variant]
        if shutil.which(cc) is None:
            pytest.fail(f"{cc} is not installed (scripts/setup.sh installs it)")
        out = OUT / variant / f"{name}_driver"
        compile_c(cc, flags + macros(name), [DRIVER, GEN / f"{name}.c"], out)
        _BUILT[(variant, name)] = out
    return _BUILT[(variant, name)]


def c_lines(variant: str, name: str, segments, version=None) -> list[str]:
    data = b"".join(bytes([1 if s.from_robot else 0]) + struct.pack(">I", len(s.data)) + s.data for s in segments)
    result = subprocess.run([str(driver(variant, name))] + ([version] if version else []), input=data,
                            capture_output=True, timeout=60)
    assert result.returncode == 0 and result.stderr == b"", result.stderr.decode(errors="replace")
    return result.stdout.decode("utf-8").splitlines()


def python_lines(name: str, segments, version=None) -> list[str]:
    conversation = MODULES[name].conversation(version)
    records = [r for s in segments for r in conversation.feed(s.data, s.from_robot)] + conversation.close()
    return [to_json_line(r) for r in records]


@pytest.mark.parametrize("variant", sorted(VARIANTS))
@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors(variant, name, case):
    assert [json.loads(line) for line in c_lines(variant, name, case.segments, case.version)] == case.expect
    assert [json.loads(line) for line in c_lines(variant, name, bytewise(case.segments), case.version)] == case.expect


@pytest.mark.parametrize("name", sorted(MODULES))
def test_the_same_lines_as_python_on_random_int32s_of_every_release(name):
    rng = random.Random(name)
    for _ in range(40):
        version = rng.choice([None, "1.0.0", "1.3.2", "1.5.0", "2.9", "2.10.0"])
        segments = []
        for _ in range(rng.randint(1, 8)):
            ints = [rng.choice([0, 1, -1, 2147483647, -2147483648, 10, 1000000, rng.randrange(-2**31, 2**31)])
                    for _ in range(rng.randint(0, 40))]
            data = struct.pack(f">{len(ints)}i", *ints)[:rng.randint(0, 4 * len(ints))]
            segments.append(Segment(rng.random() < 0.3, data))
        assert c_lines("asan-clang", name, segments, version) == python_lines(name, segments, version)


def harness_segments(data: bytes) -> tuple[str, list[Segment]]:
    segments, at = [], 1
    while at < len(data):
        control = data[at]
        at += 1
        segments.append(Segment(bool(control & 1), data[at:at + (control >> 1)]))
        at += control >> 1
    return HARNESS_RELEASES[data[0] & 7], segments


@pytest.mark.parametrize("name", sorted(MODULES))
def test_every_kept_fuzz_input_gives_the_same_lines_in_c_and_python(name):
    inputs = sorted((ROOT / "tests" / "fuzz" / "corpus" / name).iterdir())
    assert inputs, "the kept corpus is empty"
    for path in inputs:
        release, segments = harness_segments(path.read_bytes())
        assert c_lines("asan-gcc", name, segments, release) == python_lines(name, segments, release), path.name


@pytest.mark.parametrize("name", sorted(MODULES))
def test_the_fuzz_harness_runs_over_its_kept_corpus(name):
    clang = shutil.which("clang")
    if clang is None:
        pytest.fail("clang is not installed (scripts/setup.sh installs it)")
    harness = OUT / "fuzz" / f"fuzz_{name}"
    harness.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run([clang, "-std=c99", "-g", "-O1", "-fsanitize=fuzzer", *SANITIZE, f"-I{GEN}", *macros(name),
                    "-o", str(harness), str(HARNESS), str(GEN / f"{name}.c")], check=True, capture_output=True)
    result = subprocess.run([str(harness), "-runs=0", str(ROOT / "tests" / "fuzz" / "corpus" / name)],
                            capture_output=True, timeout=120)
    assert result.returncode == 0, result.stderr.decode(errors="replace")[-2000:]
