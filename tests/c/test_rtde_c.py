"""The RTDE C library (generated/c/rtde.{h,c}), its stream framing (runtime/c/typed_messages/rtde_stream.c) and
the command's JSON writer of it (tools/urwire-decode/rtde_json.c): strict builds with gcc and
clang, the same JSON lines as the Python Conversation on every golden exchange (whole and byte by
byte) and on hostile bytes, under ASan and UBSan; the client API; the fuzz harness replayed over
its kept corpus."""
from __future__ import annotations

import random
import re
import shutil
import struct
import subprocess

import pytest

import urwire
from tests.c.harness_c import CLI, GEN, HELD, INCLUDES as INCLUDE_DIRS, JSON, OUT, RTDE_STREAM, ROOT, SANITIZE, STRICT
from tests.rtde_vectors import mismatches, python_records, rtde_cases, shown_as
from urwire.rtde import Conversation

CASES = rtde_cases()
JSON_SOURCES = [CLI / "rtde_json.c", CLI / "envelope.c", RTDE_STREAM, HELD, *JSON, GEN / "urwire.c", GEN / "rtde.c"]
INCLUDES = [f"-I{d}" for d in INCLUDE_DIRS]
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
    lines = c_lines(driver, case.messages, case.protocol)
    assert lines == python
    problems = mismatches(case.expect, [shown_as(line) for line in lines], partial=False, tolerance=0.0)
    assert not problems, "\n".join(problems)
    assert all(lines[i] == line for i, line in case.exact.items())
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


def test_every_value_type_is_written_as_its_kind(driver):
    """One recipe of every value type the spec has, one data package whose bytes all have their top
    bit set: a bool is true, a signed item negative, an unsigned one large, a float a float, as
    Python writes them (a writer that read one kind's items as another's would differ)."""
    from urwire.generated import rtde as g

    types = list(g.VALUE_TYPES)
    names = [f"value_{t.lower()}" for t in types]
    reply = ",".join(types).encode()
    size = sum(struct.calcsize(">" + v.code) * v.count for v in g.VALUE_TYPES.values())
    values = bytes((0xF7 - 13 * i) % 256 | 0x80 for i in range(size))
    messages = [(False, urwire.rtde.setup_outputs(names, 125.0)),
                (True, struct.pack(">HBB", 4 + len(reply), ord("O"), 1) + reply),
                (True, struct.pack(">HBB", 4 + size, ord("U"), 1) + values)]
    lines = c_lines(driver, messages)
    assert lines == python_lines(messages)
    assert '"value_bool": true' in lines[-1] and '"value_int32": -' in lines[-1], lines[-1]


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
    assert lines[9] == "index actual_q 1 robot_mode 2: -1.5 3 7, absent names none"   # resolved once
    assert lines[10] == "values 2 0 1: 7 12.5 3, past the recipe refused"
    assert lines[11] == "typed: 12.5 -1.5 3 7, as another type refused"


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_inline_readers_read_what_rtde_data_value_reads(cc):
    """Each value type's inline reader (rtde_data_double, rtde_data_vector6d, ...) on a recipe of every
    type, in packages of random bytes (tests/c/rtde_typed.c): the items rtde_data_value reads, at its
    own type's indexes only; nothing written for another type, past the recipe or without values."""
    exe = build(cc, ["-O2", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_typed.c", GEN / "rtde.c"], "typed")
    res = subprocess.run([exe], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stderr == "", res.stdout[-2000:] + res.stderr
    assert res.stdout == "4000 reads as rtde_data_value reads, 38000 refusals, 0 failures\n"


def test_the_variable_table_reads_as_the_spec_has_it():
    """rtde_variable_at gives every row of the spec's variable table, in its order, from the table's
    small integers and its pool of texts (tests/c/rtde_variables.c prints them), and no row past it."""
    from codegen.compile import SPEC_DIR, compile_file
    exe = build("gcc", ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_variables.c", GEN / "rtde.c"],
                "variables")
    res = subprocess.run([exe], capture_output=True, timeout=60)
    assert res.returncode == 0 and res.stderr == b"", res.stderr
    variables = compile_file(SPEC_DIR / "rtde.yaml").variables
    expected = ["\t".join([v.name, v.value_type.name, v.direction, v.label, v.unit or "-",
                           *(v.since_text(g) for g in ("cb3", "eseries", "polyscope_x"))]) for v in variables]
    assert res.stdout.decode("utf-8").splitlines() == expected + [f"rows: {len(variables)} of {len(variables)}"]


def test_a_decoder_alone_links_no_variable_table(tmp_path):
    """A program that decodes and builds messages but never reads the variable table (rtde_api.c),
    linked with --gc-sections, holds none of the table's rows or texts, nor the layouts' labels
    that only rtde_layout_of reads: each is an object of its own, sharing no section with what the
    decoder reads (a firmware's flash)."""
    exe = tmp_path / "api"
    cmd = ["gcc", *STRICT, "-Os", "-ffunction-sections", "-fdata-sections", "-Wl,--gc-sections", f"-I{GEN}",
           "-o", str(exe), str(ROOT / "tests" / "c" / "rtde_api.c"), str(GEN / "rtde.c")]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    symbols = subprocess.run(["nm", str(exe)], capture_output=True, text=True, check=True).stdout
    assert "rtde_decode" in symbols and "rtde__variable" not in symbols
    binary = exe.read_bytes()
    assert b"actual_q" in binary                    # rtde_api.c's own recipe names
    assert b"Speed slider fraction" not in binary and b"speed_slider_fraction" not in binary
    assert b"Setup outputs reply (protocol 1)" not in binary


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
                      'rtde_data none = {NULL, NULL}; double q[6];\n'
                      'return rtde_protocol_in_force(&c) == RTDE_DEFAULT_PROTOCOL && !rtde_data_vector6d(&none, 0, q) '
                      '? 0 : 1; }\n')
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


# ---- what the protocol can carry: the command keeps it all, as Python does ----

def _setup(names: list[str], frequency: float = 125.0) -> bytes:
    body = struct.pack(">d", frequency) + ",".join(names).encode()
    return struct.pack(">HB", 3 + len(body), ord("O")) + body


def _reply(recipe_id: int, types: list[str], code: str = "O") -> bytes:
    body = bytes([recipe_id]) + ",".join(types).encode()
    return struct.pack(">HB", 3 + len(body), ord(code)) + body


def _data(recipe_id: int, values: bytes, from_robot: bool = True) -> tuple[bool, bytes]:
    return from_robot, struct.pack(">HBB", 4 + len(values), ord("U"), recipe_id) + values


def _large_sessions() -> dict[str, list]:
    many = [f"standard_analog_input_number_{k:03d}" for k in range(200)]          # 200 variables, 7000 bytes
    wide = [(False, _setup(many)), (True, _reply(1, ["DOUBLE"] * 200)),
            _data(1, b"".join(struct.pack(">d", k / 4) for k in range(200)))]
    # The most a reply can type: 13106 BOOLs in 65533 bytes, and a setup of as many one-letter names.
    most = 13106
    widest = [(False, _setup(["a"] * most)), (True, _reply(7, ["BOOL"] * most)), _data(7, bytes([1, 0, 2]) * (most // 3) + bytes(most % 3))]
    # Every recipe id both ways, each set up and answered in turn, then data of some of them.
    recipes = []
    for recipe_id in range(256):
        recipes += [(False, _setup([f"output_int_register_{recipe_id % 24}"])), (True, _reply(recipe_id, ["INT32"]))]
        body = f"input_int_register_{recipe_id % 24}".encode()
        recipes += [(False, struct.pack(">HB", 3 + len(body), ord("I")) + body), (True, _reply(recipe_id, ["INT32"], "I"))]
    for recipe_id in (0, 8, 9, 100, 255):
        recipes += [_data(recipe_id, struct.pack(">i", -recipe_id)), _data(recipe_id, struct.pack(">i", recipe_id), False)]
    # Version requests awaiting replies: more than the 4 the command kept, and more than the 8 all keep.
    versions = [(False, struct.pack(">HBH", 5, ord("V"), 2)) for _ in range(10)] + \
               [(True, struct.pack(">HBB", 4, ord("V"), 1)) for _ in range(10)] + \
               [(False, _setup(["timestamp"])), (True, _reply(1, ["DOUBLE"])), _data(1, struct.pack(">d", 1.5))]
    return {"200 variables, 7000 bytes of names": wide, "13106 variables": widest, "512 recipes": recipes,
            "10 version requests awaiting replies": versions}


@pytest.mark.parametrize("name", list(_large_sessions()))
def test_the_command_keeps_what_the_protocol_can_carry(driver, fast_cli, name, tmp_path):
    """Sessions past the fixed limits the command had (64 variables, 2048 bytes of names, 8
    recipes, 4 version requests awaiting replies): the C lines are Python's, byte for byte, with no
    error of a limit; the command on the two raw streams prints what `urwire decode` prints."""
    import os
    import sys
    messages = _large_sessions()[name]
    python = python_lines(messages, 2)
    assert c_lines(driver, messages, 2) == python
    assert not any("limits" in line for line in python)
    robot, client = tmp_path / "robot.bin", tmp_path / "client.bin"
    robot.write_bytes(b"".join(d for fr, d in messages if fr))
    client.write_bytes(b"".join(d for fr, d in messages if not fr))
    args = ["--protocol", "rtde", str(robot), "--to-robot", str(client)]
    c = subprocess.run([fast_cli, *args], capture_output=True, timeout=120)
    py = subprocess.run([sys.executable, "-m", "urwire", "decode", *args], capture_output=True, timeout=120,
                        env={**os.environ, "PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"})
    assert c.stderr == b"" and (c.returncode, c.stdout) == (py.returncode, py.stdout)


def test_an_embedded_caller_past_its_limits_is_told(tmp_path):
    """rtde_conversation_init's small limits (8 recipes, 64 variables, 2048 bytes of names), and
    rtde_conversation_init_in's own: past one, rtde_decode says RTDE_TOO_MANY for that message, a
    later reply still pairs with its own request, and data of a recipe not kept is of no recipe
    (never read by the recipe its id had before)."""
    exe = build("gcc", ["-O1", "-g", *SANITIZE], [ROOT / "tests" / "c" / "rtde_limits.c", GEN / "rtde.c"], "limits")
    res = subprocess.run([exe], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    assert res.stdout.splitlines() == [
        "65 variables: reply too many",                     # more variables than a recipe holds
        "data of recipe 1 after it: unknown recipe",        # recipe 1 (timestamp) is not read instead
        "2100 bytes of names: setup too many",              # the names do not fit: kept in place
        "its reply: too many",
        "the next setup's reply: ok, recipe 2 reads actual_q",
        "recipes 3 to 9: ok",                               # recipe 1 is gone: 2 to 9 are the 8 kept
        "recipe 10: reply too many",
        "data of recipe 10: unknown recipe",
        "storage for 2 recipes of 4 variables and 64 bytes: ok",
        "storage one byte short: refused",
        "a third recipe: reply too many",
        "limits above the protocol's: no storage size",
    ]
