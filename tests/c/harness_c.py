"""Helpers for the C tests: builds: the CLI and the test driver, under gcc, clang and the sanitizers.

Every build uses the strict flags the library promises to pass (C99, -Wall -Wextra -Werror
-pedantic -Wconversion -Wshadow). Outputs go to build/c-tests/<variant>/.
"""
from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GEN = ROOT / "generated" / "c"
CLI = ROOT / "tools" / "urwire-decode"
# The C runtime compiled beside generated/c (as mk/c.mk's C_RUNTIME): canonical JSON, float digits
# and the record loop (urwire._ccore compiles them too), and the stream framing of RTDE and of the
# real-time interface.
JSON_RUNTIME = ROOT / "runtime" / "c" / "json"
RTDE_STREAM = ROOT / "runtime" / "c" / "typed_messages" / "rtde_stream.c"
UR_REALTIME_STREAM = ROOT / "runtime" / "c" / "sized_packets" / "ur_realtime_stream.c"
RUNTIME_SOURCES = sorted(JSON_RUNTIME.glob("*.c")) + [RTDE_STREAM, UR_REALTIME_STREAM]
CAPTURE = ROOT / "runtime" / "c" / "capture"    # the capture reader, which the command reads captures with
INCLUDES = [GEN, JSON_RUNTIME, RTDE_STREAM.parent, UR_REALTIME_STREAM.parent, CLI, CAPTURE]  # as mk/c.mk's C_INCLUDES
# The other interfaces' parsers (generated/c/<interface>.c), which the CLI links beside urwire.c,
# whichever urwire.c (full or pinned) a test builds.
INTERFACES_C = [p for p in sorted(GEN.glob("*.c")) if p.name != "urwire.c"]
# The UTF-8 decoder the JSON writer writes text with, from what every kind's C runtime shares (as
# mk/c.mk's C_CLI): the command compiles it beside the runtime above.
UTF8 = ROOT / "runtime" / "c" / "common" / "utf8.c"
RUNTIME_SOURCES.append(UTF8)
# The bytes the stream framers hold between feeds, one window for both (runtime/c/common/held.c).
HELD = ROOT / "runtime" / "c" / "common" / "held.c"
RUNTIME_SOURCES.append(HELD)
RUNTIME_SOURCES += sorted(CAPTURE.glob("*.c"))
CLI_SOURCES = sorted(CLI.glob("*.c")) + RUNTIME_SOURCES + INTERFACES_C   # main.c and what it links
CLI_LIBRARY = [p for p in CLI_SOURCES if p.name != "main.c"]   # the same, for the test driver
JSON = [JSON_RUNTIME / "json.c", JSON_RUNTIME / "shortest.c", UTF8]  # the JSON writer, its floats, its UTF-8
# One folder per test process (pytest-xdist names its workers), so parallel runs never build over each other.
OUT = ROOT / "build" / "c-tests" / os.environ.get("PYTEST_XDIST_WORKER", "main")
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-Wconversion", "-Wshadow"]
SANITIZE = ["-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-fno-omit-frame-pointer"]
VARIANTS = {
    "gcc": ("gcc", ["-O2"]),
    "clang": ("clang", ["-O2"]),
    "asan-gcc": ("gcc", ["-Os", "-g"] + SANITIZE),   # -Os: the paths written out for size (__OPTIMIZE_SIZE__)
    "asan-clang": ("clang", ["-O1", "-g"] + SANITIZE),
}
# Builds with the library's compile-time options (docs/c.md), which only their own tests take.
OPTION_VARIANTS = {
    "small-gcc": ("gcc", ["-Os", "-DURWIRE_NO_NAMES", "-DURWIRE_NO_FAST_PATHS"]),
}

sys.path[:0] = [str(ROOT / "python"), str(ROOT / "generated" / "python")]
sys.path.insert(0, str(ROOT / "tests"))

from tests.c import state_members  # noqa: E402


@dataclass(frozen=True)
class Build:
    name: str
    cli: Path
    driver: Path

    def object(self, source: Path) -> Path:
        """The object this build compiled a library source into (strict flags, no diagnostic)."""
        return self.cli.parent / f"{source.stem}.o"


def compile_c(cc: str, flags: list[str], sources: list[Path], output: Path, extra: list[str] = ()) -> None:
    output.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, *flags, *(f"-I{d}" for d in INCLUDES), "-o", str(output), *map(str, sources), *extra]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0, f"{' '.join(cmd)}\n{result.stderr}"
    assert result.stderr == "", result.stderr  # not even a note


# The builds of VARIANTS, shared by every test process: the first to want one builds it under a
# lock, the others wait and take it; a stamp of the sources and flags tells whether a build is
# current.
SHARED = ROOT / "build" / "c-tests" / "variants"


def _sources_stamp(name: str) -> str:
    digest = hashlib.sha256(repr({**VARIANTS, **OPTION_VARIANTS}[name]).encode())
    inputs = [*GEN.iterdir(), *CLI.iterdir(), *JSON_RUNTIME.iterdir(), RTDE_STREAM, RTDE_STREAM.with_suffix(".h"),
              ROOT / "tests" / "c" / "driver.c", Path(state_members.__file__)]
    inputs += [UTF8, UTF8.with_suffix(".h"), UTF8.with_name("macros.h")]
    for path in sorted(p for p in inputs if p.is_file()):
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


def build_variant(name: str) -> Build:
    cc, flags = {**VARIANTS, **OPTION_VARIANTS}[name]
    if shutil.which(cc) is None:
        pytest.fail(f"{cc} is not installed (scripts/setup.sh installs it)")
    folder = SHARED / name
    cli, driver = folder / "urwire-decode", folder / "driver"
    built = Build(name, cli, driver)
    folder.mkdir(parents=True, exist_ok=True)
    with open(SHARED / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        stamp, want = folder / "stamp", _sources_stamp(name)
        if not (stamp.is_file() and stamp.read_text() == want and cli.is_file() and driver.is_file()):
            stamp.unlink(missing_ok=True)
            # The library once as objects, linked into the CLI and into the test driver.
            objects = []
            for source in [*CLI_LIBRARY, GEN / "urwire.c"]:
                objects.append(built.object(source))
                compile_c(cc, flags + ["-c"], [source], objects[-1])
            compile_c(cc, flags, [CLI / "main.c", *objects], cli, ["-lm"])
            # The driver is test code: strict too, except that it uses malloc and stdio freely.
            compile_c(cc, flags + [f"-I{state_members.write(GEN / 'urwire.h', folder)}"],
                      [ROOT / "tests" / "c" / "driver.c", *objects], driver, ["-lm"])
            stamp.write_text(want)
    return built


def build_decode_driver(name: str = "asan-gcc") -> Path:
    """tests/c/decode_driver.c (urwire-decode's main run again for each request, in one process:
    the differential fuzzer's peer), linked from a variant's objects and main.c renamed, as
    mk/cell_fuzz.mk builds it; rebuilt by each test process that asks, under the variant's lock."""
    build = get_build(name)
    cc, flags = VARIANTS[name]
    out = OUT / name / "decode_driver"
    with open(SHARED / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        main = OUT / name / "urwire_decode_main.o"
        compile_c(cc, flags + ["-c", "-Dmain=urwire_decode_main"], [CLI / "main.c"], main)
        objects = [build.object(source) for source in [*CLI_LIBRARY, GEN / "urwire.c"]]
        compile_c(cc, flags, [ROOT / "tests" / "c" / "decode_driver.c", main, *objects], out, ["-lm"])
    return out


_BUILDS: dict[str, Build] = {}


def get_build(name: str) -> Build:
    if name not in _BUILDS:
        _BUILDS[name] = build_variant(name)
    return _BUILDS[name]


def run_cli(b: Build, data: bytes, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(b.cli), *args, "-"], input=data, capture_output=True)


def parse_lines(out: bytes) -> list:
    return [json.loads(line) for line in out.decode("utf-8").splitlines()]


def python_lines(data: bytes, version: str | None) -> tuple[list[str], int]:
    """The lines the Python reference decoder prints for a stream, and its exit code."""
    import urwire
    from urwire.canonical import has_error

    records = list(urwire.decode_stream(data, version_hint=version))
    return [urwire.to_json_line(r) for r in records], 1 if any(has_error(r) for r in records) else 0


def python_records(data: bytes, version: str | None) -> tuple[list, int]:
    """The same, parsed."""
    lines, code = python_lines(data, version)
    return [json.loads(line) for line in lines], code


class CommandPeer:
    """One test-driver process that answers input after input (`driver batch`), so that many
    streams cost one process, not one each. By default it answers for urwire-decode (the
    command's own record loop); `mode` picks another answer: ("chunks", "K") prints the records
    fed K bytes at a time, ("roundtrip",) checks that every part encodes back (tests/c/driver.c).
    Whatever the driver writes to stderr (a sanitizer's report) fails `close`."""

    def __init__(self, driver: Path, *mode: str):
        self.stderr = tempfile.TemporaryFile()
        self.proc = subprocess.Popen([str(driver), "batch", *mode], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=self.stderr)

    def decode(self, data: bytes, hint: str = "") -> tuple[list[str], int]:
        """The lines the driver prints for a stream and its exit status ("" hint: none given)."""
        text = hint.encode("utf-8", "surrogateescape")
        self.proc.stdin.write(len(text).to_bytes(4, "big") + text + len(data).to_bytes(4, "big") + data)
        self.proc.stdin.flush()
        lines = []
        while True:
            line = self.proc.stdout.readline()
            assert line, f"the driver stopped (exit {self.proc.wait()}): {self.errors()}"
            if line.startswith(b"="):
                return lines, int(line[1:])
            lines.append(line.decode("utf-8")[:-1])   # "\n" only: a text may hold U+2028

    def errors(self) -> str:
        self.stderr.seek(0)
        return self.stderr.read().decode("utf-8", "replace")[-3000:]

    def close(self) -> None:
        self.proc.stdin.close()
        code = self.proc.wait()
        assert code == 0 and self.errors() == "", f"the driver exited {code}: {self.errors()}"
        self.stderr.close()

    def __enter__(self) -> "CommandPeer":
        return self

    def __exit__(self, *exc) -> None:
        if exc[0] is None:
            self.close()
        else:
            self.proc.kill()
            self.proc.wait()


def python_answer(data: bytes, hint: str = "") -> tuple[list[str], int]:
    """What the Python command prints for the same stream and hint, and its exit status."""
    import urwire

    try:
        version = urwire.parse_version(hint) if hint else None
    except ValueError:
        return [], 2
    return python_lines(data, version)
