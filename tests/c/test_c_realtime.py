"""The real-time interface in C (generated/c/ur_realtime.{h,c}) and in urwire-decode --protocol
ur_realtime: strict builds with the promised headers only, its runtime files on their own, the
golden vectors, the same JSON as Python on valid and hostile streams under ASan/UBSan, and the
fuzz harness over its kept corpus."""
from __future__ import annotations

import json
import random
import re
import shutil
import struct
import subprocess

import pytest

from codegen.emit import runtime_source
from tests.c.harness_c import CLI_LIBRARY, GEN, OUT, ROOT, STRICT, compile_c, get_build
from tests.vectors import interface_cases, mismatches

CASES = interface_cases("ur_realtime")
RUNTIME = ROOT / "runtime" / "c" / "sized_packets"
# The files joined into generated/c/ur_realtime.c; the stream framing beside them is compiled by the
# command and tested by test_c_ur_realtime_stream.py.
FILES = sorted(p.name for p in RUNTIME.glob("ur_realtime_*") if p.stem != "ur_realtime_stream")
CORPUS = ROOT / "tests" / "fuzz" / "corpus" / "ur_realtime"
FUZZER_FLAGS = ["-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all"]


def python_lines(data: bytes, hint: str = "") -> tuple[list[str], int]:
    import urwire
    from urwire.realtime import decode_stream

    lines = [urwire.to_json_line(r) for r in decode_stream(data, hint or None)]
    return lines, 1 if any('"error": ' in line for line in lines) else 0


def c_lines(cli, data: bytes, tmp_path, hint: str = "") -> tuple[list[str], int]:
    path = tmp_path / "stream.bin"
    path.write_bytes(data)
    cmd = [str(cli), "--protocol", "ur_realtime", *(["--version-hint", hint] if hint else []), str(path)]
    res = subprocess.run(cmd, capture_output=True, timeout=60)
    assert res.stderr == b"", res.stderr.decode(errors="replace")
    return res.stdout.decode().splitlines(), res.returncode


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_library_builds_clean_and_alone(cc):
    compile_c(cc, ["-O2", "-c"], [GEN / "ur_realtime.c"], OUT / "ur_realtime" / f"ur_realtime-{cc}.o")


def test_only_the_promised_headers_and_no_allocation():
    text = (GEN / "ur_realtime.h").read_text() + (GEN / "ur_realtime.c").read_text()
    includes = set(re.findall(r'#include [<"]([^>"]+)[>"]', text))
    assert includes == {"stdint.h", "stddef.h", "stdbool.h", "string.h", "ur_realtime.h"}
    code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    for word in ("malloc", "free(", "printf", "FILE"):
        assert word not in code, word


@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("name", FILES)
def test_each_runtime_file_compiles_on_its_own(cc, name):
    out = OUT / "ur_realtime" / f"{name}-{cc}.o"
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, "-O2", "-c", "-x", "c", f"-I{RUNTIME}", f"-I{ROOT / 'tests' / 'c'}", "-o", str(out),
           str(RUNTIME / name)]
    res = subprocess.run(cmd, capture_output=True, text=True)
    assert res.returncode == 0 and res.stderr == "", res.stderr


def test_each_runtime_file_is_joined_once():
    generated = (GEN / "ur_realtime.c").read_text()
    for name in FILES:
        assert generated.count(f"---- runtime/c/sized_packets/{name} ----") == 1
        assert runtime_source("c", f"sized_packets/{name}").rstrip("\n") in generated
    assert "standalone>" not in generated


@pytest.mark.parametrize("variant", ["gcc", "asan-clang"])
@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_vector(variant, case, tmp_path):
    lines, status = c_lines(get_build(variant).cli, case.data, tmp_path, case.version or "")
    got = [json.loads(line) for line in lines]
    assert mismatches(case.expect, got, partial=False, tolerance=0.0) == []
    assert status == (1 if any("error" in r for r in case.expect) else 0)


def _random_stream(rng: random.Random) -> bytes:
    """Packets of every layout's size and of other sizes, their doubles of every kind of bit
    pattern (NaN payloads, -0.0, subnormals, the largest), built with struct."""
    from urwire.generated.ur_realtime import FORMS_BY_SIZE

    sizes = list(FORMS_BY_SIZE) + [12, 20, 100]
    out = []
    for _ in range(rng.randint(1, 6)):
        size = rng.choice(sizes)
        doubles = []
        for _ in range((size - 4) // 8):
            kind = rng.random()
            if kind < 0.2:
                doubles.append(struct.pack(">Q", rng.getrandbits(64)))
            else:
                doubles.append(struct.pack(">d", rng.choice([0.0, -0.0, 1e-310, 1.7976931348623157e308, 0.1,
                                                             rng.uniform(-10, 10), float(rng.randint(-1, 300))])))
        out.append(struct.pack(">i", size) + b"".join(doubles))
    return b"".join(out)


def test_the_same_json_as_python_on_valid_streams(tmp_path):
    cli = get_build("asan-clang").cli
    rng = random.Random(7)
    for i in range(40):
        data = _random_stream(rng)
        hint = rng.choice(["", "3.12", "5.2", "5.10"])
        assert c_lines(cli, data, tmp_path, hint) == python_lines(data, hint), i


def test_the_same_json_as_python_on_hostile_streams(tmp_path):
    """Random bytes, cut and mutated streams, huge and negative sizes: no sanitizer report, no
    hang, and the lines and status Python gives."""
    cli = get_build("asan-clang").cli
    rng = random.Random(11)
    base = _random_stream(rng)
    inputs = [b"", b"\x00", bytes(3), struct.pack(">i", -5) + bytes(40), struct.pack(">i", 1 << 30) + bytes(40),
              struct.pack(">i", 0x7FFFFFFF), base[:-1], base[:5]]
    for _ in range(30):
        inputs.append(bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 2000))))
        mutated = bytearray(base)
        for _ in range(rng.randint(1, 5)):
            mutated[rng.randrange(len(mutated))] = rng.getrandbits(8)
        inputs.append(bytes(mutated[:rng.randint(0, len(mutated))]))
    for i, data in enumerate(inputs):
        assert c_lines(cli, data, tmp_path) == python_lines(data), i


def test_after_a_size_that_cannot_frame_a_packet_both_go_on_at_the_next_one(tmp_path):
    """A stream joined across lost bytes, in the middle of a packet: one error, then every packet
    after it, the same lines and status from C and Python."""
    cli = get_build("asan-clang").cli
    rng = random.Random(5)
    packets = [struct.pack(">i", 1116) + b"".join(struct.pack(">d", rng.uniform(-4, 4)) for _ in range(139))
               for _ in range(12)]
    cut = b"".join(packets[:5]) + packets[6][700:] + b"".join(packets[7:])
    lines, status = c_lines(cli, cut, tmp_path)
    assert (lines, status) == python_lines(cut)
    assert [json.loads(line)["type"] for line in lines] == ["rt_3_10"] * 5 + ["error"] + ["rt_3_10"] * 5
    assert status == 1


@pytest.mark.deep          # the whole kept corpus under the sanitizers: `make test-deep`
def test_the_kept_corpus_passes_the_fuzz_harness():
    if shutil.which("clang") is None:
        pytest.fail("clang is not installed (scripts/setup.sh installs it)")
    fuzzer = OUT / "fuzz" / "fuzz_ur_realtime"
    compile_c("clang", FUZZER_FLAGS, [ROOT / "tests" / "c" / "fuzz_ur_realtime.c", *CLI_LIBRARY, GEN / "urwire.c"],
              fuzzer, ["-lm"])
    assert len(list(CORPUS.iterdir())) >= 5
    res = subprocess.run([str(fuzzer), "-runs=0", str(CORPUS)], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]


def test_the_kept_corpus_gives_the_same_json_as_python(tmp_path):
    cli = get_build("asan-clang").cli
    hints = ["", "3.12", "5.2", "5.10"]
    for path in sorted(CORPUS.iterdir()):
        data = path.read_bytes()
        hint = hints[data[0] & 3] if data else ""
        assert c_lines(cli, data[1:], tmp_path, hint) == python_lines(data[1:], hint), path.name


def test_the_command_dispatches_by_protocol(tmp_path):
    cli = get_build("gcc").cli
    path = tmp_path / "x.bin"
    path.write_bytes(REALTIME_PACKET := struct.pack(">i3d", 28, 1.0, 2.0, 3.0))
    res = subprocess.run([str(cli), "--protocol", "nope", str(path)], capture_output=True, text=True)
    from urwire.interfaces import INTERFACES
    known = res.stderr.partition("unknown protocol: nope (known: ")[2].partition(")")[0].split()
    assert res.returncode == 2 and sorted(known) == sorted(INTERFACES)   # every interface, as Python knows them
    primary = [subprocess.run([str(cli), *args, str(path)], capture_output=True, text=True).stdout
               for args in ([], ["--protocol", "ur"], ["--protocol=ur"])]
    assert primary[0] == primary[1] == primary[2] != ""
    realtime = subprocess.run([str(cli), "--protocol=ur_realtime", str(path)], capture_output=True, text=True)
    assert realtime.returncode == 1 and json.loads(realtime.stdout)["raw"] == REALTIME_PACKET[4:].hex()


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_unit_checks_of_the_api(cc):
    exe = OUT / "ur_realtime" / f"unit-{cc}"
    compile_c(cc, ["-O1", "-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all"],
              [ROOT / "tests" / "c" / "ur_realtime_unit.c", GEN / "ur_realtime.c"], exe)
    res = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stdout.strip() == "all real-time checks passed", res.stdout + res.stderr
