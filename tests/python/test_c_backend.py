"""The C backend (the extension urwire._ccore: the generated C parser and the C command's JSON
writer) against pure Python: every golden and conformance vector, every input of the fuzzers' kept
corpora and sessions of every controller generation (tests/tools/valid.py) give the same canonical
JSON Lines, byte for byte, and the same error flag, whole and fed in pieces; and the backend is
picked as URWIRE_BACKEND says.

The extension is built by `make python-ext` (and by scripts/setup.sh and `make test`); without it
these tests fail, as the differential cannot run."""
from __future__ import annotations

import os
import random
import subprocess
import sys
from pathlib import Path

import pytest

from tests.tools import valid
from tests.tools.fuzz_inputs import HARNESSES, kept, split
from tests.vectors import all_cases

import urwire
from urwire.canonical import has_error

ROOT = Path(__file__).resolve().parents[2]
PIECES = (1, 7, 64, 4093)       # chunk sizes: inside a header, inside a field, across messages


@pytest.fixture(scope="module")
def ccore():
    try:
        from urwire import _ccore
    except ImportError:
        pytest.fail("the C extension urwire._ccore is not built (make python-ext)")
    return _ccore


def python_json_lines(data: bytes, hint) -> tuple[bytes, bool]:
    """What pure Python prints: each record of the Framer as to_json_line, and whether one held an error."""
    records = list(urwire.decode_stream(data, hint))
    return "".join(urwire.to_json_line(r) + "\n" for r in records).encode(), any(map(has_error, records))


def c_json_lines(ccore, data: bytes, hint, piece: int = 0) -> tuple[bytes, bool]:
    version = urwire.parse_version(hint)
    lines = ccore.PrimaryJsonLines(None if version is None else "%d.%d.%d" % version)
    step = piece or max(len(data), 1)
    out = b"".join(lines.feed(data[at:at + step]) for at in range(0, len(data), step)) + lines.close()
    return out, lines.errors


def assert_same(ccore, data: bytes, hint, what: str, pieces=PIECES) -> None:
    expected = python_json_lines(data, hint)
    assert c_json_lines(ccore, data, hint) == expected, what
    for piece in pieces:
        assert c_json_lines(ccore, data, hint, piece) == expected, f"{what} in pieces of {piece}"


@pytest.mark.parametrize("case", all_cases(), ids=lambda c: c.name)
def test_every_vector_gives_the_same_lines(ccore, case):
    assert_same(ccore, case.data, case.version, case.name)


@pytest.mark.parametrize("harness", HARNESSES)
def test_every_kept_fuzz_input_gives_the_same_lines(ccore, harness):
    inputs = kept(harness)
    assert len(inputs) > 20
    for raw in inputs:
        hint, data = split(harness, raw)
        try:
            urwire.parse_version(hint or None)
        except ValueError:
            continue                # not a version: the command stops before decoding (exit 2)
        assert_same(ccore, data, hint or None, f"{harness} input {raw[:40].hex()}", pieces=(1, 97))


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_give_the_same_lines(ccore, version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    for _ in range(6):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]          # as a capture that starts mid-stream
        for stream, given in ((data, None), (cut, None), (cut, hint)):
            assert_same(ccore, stream, given, f"{given} {stream[:40].hex()}", pieces=(5, 1000))


def test_the_extension_refuses_what_is_not_a_stream_or_version(ccore):
    with pytest.raises(TypeError):
        ccore.PrimaryJsonLines(None).feed("text")
    with pytest.raises(ValueError):
        ccore.PrimaryJsonLines("five")
    lines = ccore.PrimaryJsonLines(None)
    lines.close()
    with pytest.raises(ValueError):
        lines.feed(b"\0\0\0\5\x14")


def backend_under(value) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
    env.pop("URWIRE_BACKEND", None)
    if value is not None:
        env["URWIRE_BACKEND"] = value
    return subprocess.run([sys.executable, "-c", "import urwire; print(urwire.backend())"],
                          env=env, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("value, expected", [(None, "c"), ("c", "c"), ("python", "python"), ("PYTHON", "python")])
def test_urwire_backend_picks_the_decoder(ccore, value, expected):
    result = backend_under(value)
    assert (result.returncode, result.stdout.strip()) == (0, expected), result.stderr


def test_an_unknown_backend_is_refused(ccore):
    result = backend_under("rust")
    assert result.returncode != 0 and "URWIRE_BACKEND" in result.stderr


def test_the_command_prints_the_same_bytes_under_both_backends(ccore, tmp_path):
    """`urwire decode` of a raw stream: the C backend's lines and exit status are pure Python's."""
    stream = tmp_path / "stream.bin"
    stream.write_bytes(b"".join(case.data for case in all_cases() if case.version is None))
    runs = {}
    for value in ("c", "python"):
        env = dict(os.environ, URWIRE_BACKEND=value,
                   PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
        result = subprocess.run([sys.executable, "-m", "urwire", "decode", str(stream)], env=env,
                                capture_output=True, timeout=120)
        runs[value] = (result.returncode, result.stdout, result.stderr)
    assert runs["c"] == runs["python"]
    assert runs["c"][0] == 1 and runs["c"][1].count(b"\n") > 100


def test_the_command_writes_to_a_text_stdout_in_its_place(ccore, tmp_path, monkeypatch):
    """In-process, with stdout an io.StringIO: the C backend's lines come out as text (the C
    backend chosen here whatever URWIRE_BACKEND says)."""
    import contextlib
    import io

    from urwire import backends, cli

    case = next(c for c in all_cases() if c.name == "text_message_invalid_utf8")
    stream = tmp_path / "stream.bin"
    stream.write_bytes(case.data)
    monkeypatch.setattr(backends, "_CCORE", ccore)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = cli.main(["decode", "--no-progress", str(stream)])
    assert (code, out.getvalue().encode()) == (0, python_json_lines(case.data, None)[0])


def test_the_extension_under_asan_and_ubsan(tmp_path):
    """urwire._ccore's own C (the module, and the memory stream each feed writes into) built with
    ASan and UBSan and run over every vector and kept fuzz input (tests/python/ccore_asan_peer.py):
    no report, the same lines."""
    import sysconfig

    library = tmp_path / ("_ccore" + sysconfig.get_config_var("EXT_SUFFIX"))
    sources = ["ext/ccore/module.c", "ext/ccore/columns.c", "generated/c/urwire.c", "tools/urwire-decode/json.c",
               "tools/urwire-decode/shortest.c", "tools/urwire-decode/records.c"]
    subprocess.run(["gcc", "-shared", "-fPIC", "-g", "-O1", "-std=c99", "-fsanitize=address,undefined",
                    "-fno-sanitize-recover=all", "-Iext/ccore", "-Igenerated/c", "-Itools/urwire-decode",
                    "-I" + sysconfig.get_paths()["include"], *sources, "-lm", "-o", str(library)],
                   cwd=ROOT, check=True, timeout=300)
    runtimes = [subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True,
                               check=True).stdout.strip() for name in ("libasan.so", "libubsan.so")]
    env = dict(os.environ, LD_PRELOAD=":".join(runtimes), ASAN_OPTIONS="detect_leaks=0")
    result = subprocess.run([sys.executable, str(ROOT / "tests" / "python" / "ccore_asan_peer.py"), str(library)],
                            env=env, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0 and "ERROR" not in result.stderr, result.stderr[-3000:]
    assert int(result.stdout) > 300
