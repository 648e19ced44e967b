"""The RTDE C library (generated/c/rtde.{h,c}) and its JSON writer
(tools/urwire-decode/rtde_json.c): strict builds with gcc and clang, the same JSON lines as the
Python Conversation on every golden exchange (whole and byte by byte) and on hostile bytes, under
ASan and UBSan; the client API; the fuzz harness replayed over its kept corpus."""
from __future__ import annotations

import random
import re
import shutil
import struct
import subprocess

import pytest

import urwire
from tests.c.harness_c import CLI, GEN, OUT, ROOT, SANITIZE, STRICT
from tests.rtde_vectors import python_records, rtde_cases
from urwire.rtde import Conversation

CASES = rtde_cases()
JSON_SOURCES = [CLI / "rtde_json.c", CLI / "envelope.c", CLI / "json.c", CLI / "shortest.c", GEN / "urwire.c", GEN / "rtde.c"]
INCLUDES = [f"-I{GEN}", f"-I{CLI}"]
CORPUS = ROOT / "tests" / "fuzz" / "corpus" / "rtde"


def build(cc: str, flags: list[str], sources: list, name: str) -> str:
    exe = OUT / "rtde" / f"{name}-{cc}"
    exe.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, *flags, *INCLUDES, "-o", str(exe), *map(str, sources), "-lm"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0 and res.stderr == "", " ".join(cmd) + "\n" + res.stderr
    return str(exe)


@pytest.fixture(scope="module")
def fast_cli():
    from tests.c.harness_c import get_build
    return str(get_build("asan-gcc").cli)


@pytest.fixture(scope="module", params=["gcc", "clang"])
def driver(request):
    if shutil.which(request.param) is None:
        pytest.fail(f"{request.param} is not installed")
    return build(request.param, ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_driver.c", *JSON_SOURCES],
                 "driver")


def pieces(messages) -> bytes:
    return b"".join((b"r" if fr else b"c") + struct.pack(">I", len(d)) + d for fr, d in messages)


def c_lines(driver: str, messages, protocol=None) -> list[str]:
    res = subprocess.run([driver, *([str(protocol)] if protocol else [])], input=pieces(messages),
                         capture_output=True, timeout=60)
    assert res.returncode == 0 and res.stderr == b"", res.stderr.decode()[-2000:]
    return res.stdout.decode("utf-8").splitlines()


def python_lines(messages, protocol=None) -> list[str]:
    conversation = Conversation(protocol=protocol)
    records = []
    for from_robot, data in messages:
        records += conversation.feed(data, from_robot)
    return [urwire.to_json_line(r) for r in records + conversation.close()]


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_library_builds_strictly_and_alone(cc):
    """rtde.c compiles on its own (no urwire.c) under the strict flags, and uses only the four
    headers the library promises, no malloc and no stdio."""
    obj = OUT / "rtde" / f"rtde-{cc}.o"
    obj.parent.mkdir(parents=True, exist_ok=True)
    res = subprocess.run([cc, *STRICT, "-O2", "-c", f"-I{GEN}", "-o", str(obj), str(GEN / "rtde.c")],
                         capture_output=True, text=True)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    for name in ("rtde.h", "rtde.c"):
        text = (GEN / name).read_text()
        includes = set(re.findall(r"#include [<\"]([^>\"]+)[>\"]", text))
        assert includes <= {"stdint.h", "stddef.h", "stdbool.h", "string.h", "rtde.h"}, includes
        code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        assert not re.search(r"\b(malloc|calloc|realloc|free|printf|fopen|FILE)\b", code), name
    symbols = subprocess.run(["nm", "-g", "--defined-only", str(obj)], capture_output=True, text=True).stdout
    exported = [line.split()[-1] for line in symbols.splitlines()]
    assert exported and all(s.startswith("rtde_") for s in exported), exported


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_c_prints_what_python_prints(driver, case):
    """Every golden exchange: the C lines equal the Python lines byte for byte, and equal the vector."""
    python = python_lines(case.messages, case.protocol)
    assert c_lines(driver, case.messages, case.protocol) == python
    bytewise = [(fr, d[i:i + 1]) for fr, d in case.messages for i in range(len(d))]
    assert c_lines(driver, bytewise, case.protocol) == python


@pytest.mark.parametrize("seed", range(4))
def test_hostile_bytes_give_the_same_lines(driver, seed):
    """Cut, flipped and random bytes, huge sizes: no sanitizer report, and the lines Python prints."""
    rng = random.Random(seed)
    session = [c for c in CASES if c.name == "protocol2_session"][0].messages
    messages = []
    for _ in range(300):
        from_robot, data = rng.choice(session)
        data = bytearray(data)
        roll = rng.random()
        if roll < 0.3 and data:
            data[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
        elif roll < 0.5:
            data = data[:rng.randrange(len(data) + 1)]
        elif roll < 0.6:
            data = bytearray(struct.pack(">HB", rng.choice([0xFFFF, 2, 3, 4]), rng.choice(b"UOIVMR")))
        elif roll < 0.7:
            data = bytearray(rng.getrandbits(8) for _ in range(rng.randrange(1, 80)))
        messages.append((from_robot, bytes(data)))
    assert c_lines(driver, messages) == python_lines(messages)


def test_the_client_api(tmp_path):
    exe = build("gcc", ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_api.c", GEN / "rtde.c"], "api")
    res = subprocess.run([exe], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    lines = res.stdout.splitlines()
    sent = [d.hex() for fr, d in [c for c in CASES if c.name == "protocol2_session"][0].messages if not fr]
    from urwire import rtde
    assert lines[0] == sent[0] and lines[1] == sent[1]          # version request, controller version
    assert lines[2] == sent[3]                                   # setup outputs, protocol 2
    assert lines[2] == rtde.setup_outputs(["timestamp", "actual_q", "robot_mode"], 125.0).hex()
    assert lines[3] == sent[5]                                   # setup inputs
    assert lines[4] == sent[6] and lines[5] == sent[8]           # start, pause
    assert lines[6] == sent[7]                                   # an input data package by its recipe
    assert lines[7] == "too small: 0"
    assert lines[8] == "actual_q 0 -1.5 1.5 -0.5 0.25 3 robot_mode 7 recipe 2"


def test_the_fuzz_harness_replays_its_corpus(tmp_path):
    """tests/c/fuzz_rtde.c as libFuzzer builds it, run once over the kept corpus and every golden
    exchange as a seed (no fuzzing): no sanitizer report, no failed check."""
    if shutil.which("clang") is None:
        pytest.fail("clang is not installed")
    fuzzer = OUT / "rtde" / "fuzz_rtde"
    cmd = ["clang", "-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all", *INCLUDES,
           "-o", str(fuzzer), str(ROOT / "tests" / "c" / "fuzz_rtde.c"), *map(str, JSON_SOURCES), "-lm"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    seeds = tmp_path / "seeds"
    seeds.mkdir()
    for case in CASES:
        raw = bytearray([case.protocol or 0])
        for from_robot, data in case.messages:
            for i in range(0, len(data), 127):
                piece = data[i:i + 127]
                raw += bytes([(0x80 if from_robot else 0) | len(piece)]) + piece
        (seeds / case.name).write_bytes(bytes(raw))
    count = len(list(CORPUS.iterdir()))
    assert count >= 50
    res = subprocess.run([str(fuzzer), "-runs=0", str(CORPUS), str(seeds)], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr[-3000:]


def test_the_header_compiles_as_cpp(tmp_path):
    source = tmp_path / "use.cpp"
    source.write_text('#include "rtde.h"\nint main() { static rtde_conversation c; rtde_conversation_init(&c); '
                      'return rtde_protocol_in_force(&c) == RTDE_DEFAULT_PROTOCOL ? 0 : 1; }\n')
    res = subprocess.run(["g++", "-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic", f"-I{GEN}", "-c",
                          str(source), "-o", str(tmp_path / "use.o")], capture_output=True, text=True)
    assert res.returncode == 0 and res.stderr == "", res.stderr


def test_urwire_decode_protocol_rtde_prints_what_python_prints(fast_cli):
    """`urwire-decode --protocol rtde` on each exchange's robot stream: the lines and the exit
    status of `urwire decode --protocol rtde` on the same file."""
    import sys
    for case in CASES:
        data = case.robot_bytes
        c = subprocess.run([fast_cli, "--protocol", "rtde", "-"], input=data, capture_output=True, timeout=60)
        py = subprocess.run([sys.executable, "-m", "urwire", "decode", "--protocol", "rtde", "-"], input=data,
                            capture_output=True, timeout=60,
                            env={**__import__("os").environ, "PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"})
        assert (c.returncode, c.stdout) == (py.returncode, py.stdout), case.name
