"""Real-time stream framing on its own (runtime/c/sized_packets/ur_realtime_stream.c, beside the
real-time parser it frames for): tests/c/ur_realtime_stream_unit.c under gcc and clang with ASan and
UBSan, each stream framed whole, a byte at a time and cut at every point: whole packets, garbage
prefixes (one fault however cut), sizes of no layout, the largest packet, streams longer than the
buffer, tails. The framer's files compile alone, and each key step of it, broken, fails the unit
test."""
from __future__ import annotations

import subprocess

import pytest

from tests.c.harness_c import GEN, HELD, OUT, ROOT, SANITIZE, STRICT, UR_REALTIME_STREAM, compile_c

UNIT = ROOT / "tests" / "c" / "ur_realtime_stream_unit.c"
HEADER = UR_REALTIME_STREAM.with_suffix(".h")


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_ur_realtime_stream_unit_checks(cc):
    exe = OUT / f"ur-realtime-stream-unit-{cc}"
    compile_c(cc, ["-O1", "-g", *SANITIZE], [UNIT, UR_REALTIME_STREAM, HELD, GEN / "ur_realtime.c"], exe)
    result = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert result.stdout.strip() == "all ur_realtime stream checks passed"


@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("path", [UR_REALTIME_STREAM, HEADER], ids=lambda p: p.name)
def test_each_file_compiles_on_its_own(cc, path):
    """Only the real-time parser's header beside it: no JSON, no stdio, no allocation."""
    header = ["-x", "c"] if path.suffix == ".h" else []
    out = OUT / "ur_realtime" / f"{path.name}-alone-{cc}.o"
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, "-O2", "-c", *header, f"-I{GEN}", f"-I{path.parent}", str(path), "-o", str(out)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr
    undefined = subprocess.run(["nm", "-u", str(out)], capture_output=True, text=True, check=True).stdout.split()
    assert not {"malloc", "calloc", "realloc", "free", "fread", "fprintf", "printf"} & set(undefined)


# Each a key step of the framer and a way to break it: (what breaks, the text, its replacement).
BREAKS = [
    ("no scan after a bad size", "s->scanning = true;", "s->scanning = false;"),
    ("the scan stops at sizes of no layout",
     "ur_realtime_decode(s->probe, (size_t)size, 0, &packet) == UR_REALTIME_OK",
     "ur_realtime_decode(s->probe, (size_t)size, 0, &packet) != UR_REALTIME_E_SHORT"),
    ("the scan resumes after the size field", "        s->head++;\n        return UR_REALTIME_FRAME_BAD_SIZE;",
     "        s->head += UR_REALTIME_SIZE_FIELD_BYTES;\n        return UR_REALTIME_FRAME_BAD_SIZE;"),
    ("a packet ending the bytes waits", "(size_t)size > s->length - s->head", "(size_t)size >= s->length - s->head"),
    ("a cut size field needs its size", "e == UR_REALTIME_E_SHORT ? UR_REALTIME_SIZE_FIELD_BYTES : (size_t)size",
     "(size_t)size"),
]


@pytest.mark.parametrize("what,text,broken", BREAKS, ids=[b[0] for b in BREAKS])
def test_breaking_a_step_fails_the_unit_test(what, text, broken, tmp_path):
    source = UR_REALTIME_STREAM.read_text()
    assert source.count(text) == 1, what
    (tmp_path / UR_REALTIME_STREAM.name).write_text(source.replace(text, broken))
    (tmp_path / HEADER.name).write_text(HEADER.read_text())
    exe = tmp_path / "unit"
    # -I the file's own folder: its #include "../common/held.h" is found from there.
    build = subprocess.run(["gcc", "-std=c99", "-O1", f"-I{GEN}", f"-I{tmp_path}", f"-I{UR_REALTIME_STREAM.parent}",
                            "-o", str(exe), str(UNIT), str(tmp_path / UR_REALTIME_STREAM.name), str(HELD),
                            str(GEN / "ur_realtime.c")],
                           capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    result = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert result.returncode != 0, what
