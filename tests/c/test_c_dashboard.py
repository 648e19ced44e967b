"""The text-line interfaces in C (generated/c/ur_dashboard.{h,c}, ur_script_sender.{h,c}) under
gcc, clang and ASan/UBSan: the golden vectors whole and byte by byte, the same records as Python
on random and hostile conversations, and the dashboard's fuzz harness over its kept corpus."""
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
from urwire.generated import robotiq_gripper, ur_dashboard, ur_interpreter, ur_script_sender

MODULES = {m.NAME: m for m in (ur_dashboard, ur_script_sender, ur_interpreter, robotiq_gripper)}
CASES = [(name, case) for name in MODULES for case in conversation_cases(name)]
DRIVER = ROOT / "tests" / "c" / "lines_driver.c"
HARNESS = ROOT / "tests" / "c" / "fuzz_ur_dashboard.c"
CORPUS = ROOT / "tests" / "fuzz" / "corpus" / "ur_dashboard"
HARNESS_VERSIONS = (None, "3.15", "5.4", "5.11")   # byte 0 of a harness input, as fuzz_ur_dashboard.c reads it
_BUILT: dict[tuple, Path] = {}


def driver(variant: str, name: str = "ur_dashboard") -> Path:
    if (variant, name) not in _BUILT:
        cc, flags = VARIANTS[variant]
        if shutil.which(cc) is None:
            pytest.fail(f"{cc} is not installed (scripts/setup.sh installs it)")
        out = OUT / variant / f"{name}_driver"
        macros = [f"-DPREFIX={name}_", f"-DUPPER={name.upper()}_", f'-DHEADER="{name}.h"']
        compile_c(cc, flags + macros, [DRIVER, GEN / f"{name}.c"], out)
        _BUILT[(variant, name)] = out
    return _BUILT[(variant, name)]


def driver_input(segments) -> bytes:
    return b"".join(bytes([1 if s.from_robot else 0]) + struct.pack(">I", len(s.data)) + s.data for s in segments)


def c_lines(variant: str, segments, version=None, name: str = "ur_dashboard") -> list[str]:
    args = [str(driver(variant, name))] + ([version] if version else [])
    result = subprocess.run(args, input=driver_input(segments), capture_output=True, timeout=60)
    assert result.returncode == 0 and result.stderr == b"", result.stderr.decode(errors="replace")
    return result.stdout.decode("utf-8").splitlines()


def python_lines(segments, version=None, name: str = "ur_dashboard") -> list[str]:
    conversation = MODULES[name].conversation(version)
    records = [r for s in segments for r in conversation.feed(s.data, s.from_robot)] + conversation.close()
    return [to_json_line(r) for r in records]


@pytest.mark.parametrize("variant", sorted(VARIANTS))
@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors(variant, name, case):
    assert [json.loads(line) for line in c_lines(variant, case.segments, case.version, name)] == case.expect
    assert [json.loads(line) for line in c_lines(variant, bytewise(case.segments), case.version, name)] \
        == case.expect


def random_conversation(rng: random.Random) -> list[Segment]:
    """Lines a client and a server might send, and bytes neither would: long lines, no newline,
    binary junk, CR without LF, commands of every version."""
    words = [c.text for c in ur_dashboard.COMMANDS] + ["request_program", "URSoftware 5.6.0.1 (x)", "URSoftware 3.15.7", "could not "
             "understand: 'x'", "Connected: Universal Robots Dashboard Server", "File not found: a", "true", "\xff"]
    segments = []
    for _ in range(rng.randint(1, 12)):
        kind = rng.random()
        if kind < 0.6:
            data = "\n".join(rng.choice(words) + rng.choice(["", " arg", " \u00e9"]) for _ in range(rng.randint(1, 4)))
            data = (data + rng.choice(["\n", "\r\n", ""])).encode("utf-8", "surrogateescape")
        elif kind < 0.8:
            data = bytes(rng.randrange(256) for _ in range(rng.randint(0, 200)))
        else:
            data = b"y" * rng.randint(ur_dashboard.MAX_LINE - 2, ur_dashboard.MAX_LINE * 3) + rng.choice([b"", b"\n"])
        segments.append(Segment(rng.random() < 0.5, data))
    return segments


@pytest.mark.parametrize("name", sorted(MODULES))
@pytest.mark.parametrize("variant", ["gcc", "asan-clang"])
def test_the_same_lines_as_python_on_random_and_hostile_conversations(variant, name):
    rng = random.Random(29999)
    for _ in range(60):
        segments = random_conversation(rng)
        version = rng.choice([None, "3.15", "5.11"])
        assert c_lines(variant, segments, version, name) == python_lines(segments, version, name)


def harness_segments(data: bytes) -> tuple[str | None, list[Segment]]:
    """A fuzz input as fuzz_ur_dashboard.c reads it: the version, then the segments."""
    segments, at = [], 1
    while at < len(data):
        control = data[at]
        at += 1
        segments.append(Segment(bool(control & 1), data[at:at + (control >> 1)]))
        at += control >> 1
    return HARNESS_VERSIONS[data[0] & 3] if data else None, segments


def test_every_kept_fuzz_input_gives_the_same_lines_in_c_and_python():
    inputs = sorted(CORPUS.iterdir())
    assert inputs, "the kept corpus is empty"
    for path in inputs:
        version, segments = harness_segments(path.read_bytes())
        assert c_lines("asan-gcc", segments, version) == python_lines(segments, version), path.name


def test_the_fuzz_harness_runs_over_its_kept_corpus(tmp_path):
    clang = shutil.which("clang")
    if clang is None:
        pytest.fail("clang is not installed (scripts/setup.sh installs it)")
    harness = OUT / "fuzz" / "fuzz_ur_dashboard"
    harness.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run([clang, "-std=c99", "-g", "-O1", "-fsanitize=fuzzer", *SANITIZE, f"-I{GEN}", "-o", str(harness),
                    str(HARNESS), str(GEN / "ur_dashboard.c")], check=True, capture_output=True)
    (tmp_path / "seeds").mkdir()
    long_line = tmp_path / "seeds" / "long_line"
    long_line.write_bytes(b"\x01" + (b"\xfe" + b"z" * 127) * 80 + b"\x03\n")   # a 10 KB line from the robot
    result = subprocess.run([str(harness), "-runs=0", str(CORPUS), str(long_line.parent)], capture_output=True, timeout=120)
    assert result.returncode == 0, result.stderr.decode(errors="replace")[-2000:]


@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_urwire_decode_protocol_prints_what_python_prints_of_the_robots_stream(name, case):
    from tests.c.harness_c import get_build

    robot = [s for s in case.segments if s.from_robot]
    args = [str(get_build("asan-gcc").cli), "--protocol", name] + (["--version-hint", case.version] if case.version else [])
    result = subprocess.run(args + ["-"], input=b"".join(s.data for s in robot), capture_output=True, timeout=60)
    lines = python_lines(robot, case.version, name)
    assert result.stdout.decode("utf-8").splitlines() == lines, result.stderr
    assert result.returncode == (1 if any('"type": "error"' in line for line in lines) else 0)


def overflowing_session(rng: random.Random) -> list[Segment]:
    """More commands awaiting replies than a conversation keeps, answered in bursts of every size,
    so that lost commands sit behind kept ones and new commands come while lost ones are ahead."""
    words = [b"robotmode", b"play", b"stop", b"PolyscopeVersion", b"nonsense"]
    answers = [b"Robotmode: IDLE", b"Starting program", b"Stopped", b"URSoftware 5.11.1.1 (x)", b"could not understand: 'x'"]
    segments = [Segment(True, b"Connected: Universal Robots Dashboard Server\n")]
    for _ in range(rng.randint(2, 6)):
        segments.append(Segment(False, b"".join(rng.choice(words) + b"\n" for _ in range(rng.randint(1, 400)))))
        segments.append(Segment(True, b"".join(rng.choice(answers) + b"\n" for _ in range(rng.randint(1, 400)))))
    return segments


@pytest.mark.parametrize("variant", ["gcc", "asan-clang"])
def test_past_the_kept_commands_the_same_lines_as_python_and_no_reply_paired_wrongly(variant):
    rng = random.Random(256)
    lost = 0
    for _ in range(12):
        segments = overflowing_session(rng)
        lines = c_lines(variant, segments)
        assert lines == python_lines(segments)
        lost += sum('"error": "reply to a command that was not kept' in line for line in lines)
    assert lost > 100         # the sessions did overflow


def test_urwire_decode_to_robot_of_a_long_session_pairs_each_reply_with_its_own_command(tmp_path):
    # The client's file is read first, so all 301 commands await their replies at once: raw files
    # keep PENDING_KEPT_RAW of them, and every reply is paired with its own command.
    from tests.c.harness_c import get_build
    from tests.python.test_cell import urwire_decode

    client, robot = tmp_path / "client.raw", tmp_path / "robot.raw"
    client.write_bytes(b"robotmode\n" * 300 + b"play\n")
    robot.write_bytes(b"Connected: Universal Robots Dashboard Server\n" + b"Robotmode: IDLE\n" * 300 + b"Starting program\n")
    c = subprocess.run([str(get_build("asan-gcc").cli), "--protocol", "ur_dashboard", str(robot), "--to-robot", str(client)],
                       capture_output=True, timeout=60)
    python = urwire_decode("--protocol", "ur_dashboard", "--to-robot", str(client), str(robot))
    assert c.stdout.decode() == python.stdout and c.returncode == python.returncode == 0
    replies = [json.loads(line) for line in python.stdout.splitlines() if '"type": "reply"' in line]
    assert [r.get("command_name") for r in replies] == [None] + ["robotmode"] * 300 + ["play"]
