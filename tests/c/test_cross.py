"""Other CPUs (mk/cross.mk, docs/c.md#other-cpus): every interface's generated C cross-compiled
with -Werror for Cortex-M0+, M4F, M7 and RV32IMC; and the golden vectors of every interface run
under QEMU on a big-endian s390x, on 32-bit ARM and on a Cortex-M4F board, each output compared
byte for byte with the x86 build's.

The compilers, flags and QEMU command lines are mk/cross.mk's (`make cross-table`). Outside CI a
missing toolchain skips, saying which; in CI (CI=true) it fails. `make test` compiles one object
per interface and CPU at -Os and runs every vector on each CPU built at -Os (QEMU takes under a
second for all of them; the builds take the time); `make test-deep` compiles the whole matrix
(`make cross`), runs the vectors again built at -O2, and 530 sessions no vector holds (fuzz
corpora, their mutants, random robot states) at -Os and -O2.
"""
from __future__ import annotations

import os
import random
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.c.harness_c import CLI, CLI_LIBRARY, GEN, INCLUDES, ROOT, STRICT, build_decode_driver
from tests.interface_vectors import conversation_cases
from tests.rtde_vectors import rtde_cases
from tests.vectors import all_cases, interface_cases

DECODE_DRIVER = ROOT / "tests" / "c" / "decode_driver.c"
# The conversation interfaces: their robot's stream, and --to-robot the client's.
CONVERSATIONS = ("ur_dashboard", "ur_interpreter", "robotiq_gripper", "ur_reverse", "ur_trajectory",
                 "ur_script_sender", "ur_script_command")


def _table() -> tuple[dict[str, tuple[str, list[str]]], dict[str, "Run"], list[str]]:
    out = subprocess.run(["make", "--no-print-directory", "-s", "cross-table"], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout
    cpus, runs, common = {}, {}, []
    for line in out.splitlines():
        kind, name, rest = line.split(" ", 2)
        if kind == "cpu":
            cc, *flags = rest.split()
            cpus[name] = (cc, flags)
        elif kind == "run":
            build, defines, sources, qemu = (part.split() for part in rest.split("|"))
            runs[name] = Run(name, build[0], build[1:], defines, [ROOT / s for s in sources], qemu)
        else:
            common = [name, *rest.split()]
    return cpus, runs, common


@dataclass(frozen=True)
class Run:
    name: str
    cc: str
    flags: list[str]
    defines: list[str]    # what the x86 build it is compared with takes too
    sources: list[Path]   # the harness's own start code, if the target needs one
    qemu: list[str]       # the command line the program follows


CPUS, RUNS, COMMON = _table()


def need(*programs: str) -> None:
    missing = [p for p in programs if shutil.which(p) is None]
    if not missing:
        return
    message = f"{', '.join(missing)} not installed (scripts/setup.sh installs it)"
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


# ---- cross builds ----

# One ARM and the RISC-V CPU in make test; the other two Cortex-Ms (the same compiler) in test-deep.
@pytest.mark.parametrize("cpu", [cpu if cpu in ("cortex-m4f", "rv32imc") else pytest.param(cpu, marks=pytest.mark.deep)
                                 for cpu in sorted(CPUS)])
def test_every_interface_compiles_clean_at_os(cpu, tmp_path):
    """`make cross` at -Os for one CPU: an object per interface, not one warning (-Werror)."""
    need(CPUS[cpu][0])
    result = subprocess.run(["make", "--no-print-directory", "-s", "cross", f"CROSS_CPUS={cpu}", "CROSS_LEVELS=-Os",
                             f"CROSS_OUT={tmp_path}"], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr[-3000:]
    objects = sorted(p.stem for p in (tmp_path / cpu / "Os").glob("*.o"))
    assert objects == sorted(p.stem for p in GEN.glob("*.c"))


def test_the_project_warnings_are_the_cross_builds_warnings():
    assert COMMON[:len(STRICT)] == STRICT
    assert {"-ffunction-sections", "-fdata-sections"} <= set(COMMON)


# ---- the golden vectors on other CPUs ----

@dataclass(frozen=True)
class Request:
    name: str
    args: list[str]    # urwire-decode's command line after its name


def _files(folder: Path, name: str, robot: bytes, client: bytes | None) -> list[str]:
    """The streams of one vector as files; the command line's FILE [--to-robot FILE2]."""
    stem = folder / name.replace("/", "~")
    stem.with_suffix(".robot").write_bytes(robot)
    if client is None:
        return [str(stem.with_suffix(".robot"))]
    stem.with_suffix(".client").write_bytes(client)
    return [str(stem.with_suffix(".robot")), "--to-robot", str(stem.with_suffix(".client"))]


def _hint(version: str | None) -> list[str]:
    return ["--version-hint", version] if version else []


def vector_requests(folder: Path) -> list[Request]:
    """Every golden vector (and the primary interface's conformance cases) as urwire-decode
    command lines, their streams written under folder."""
    folder.mkdir(parents=True, exist_ok=True)
    groups: list[list[Request]] = [
        [Request(c.name, _hint(c.version) + _files(folder, c.name, c.data, None)) for c in all_cases()],
        [Request(c.name, ["--protocol", "ur_realtime", *_hint(c.version), *_files(folder, c.name, c.data, None)])
         for c in interface_cases("ur_realtime")],
        [Request(f"rtde/{c.name}", ["--protocol", "rtde", *_files(folder, f"rtde/{c.name}", c.robot_bytes,
                                                                   c.client_bytes)]) for c in rtde_cases()],
    ]
    for interface in CONVERSATIONS:
        group = []
        for c in conversation_cases(interface):
            robot = b"".join(s.data for s in c.segments if s.from_robot)
            client = b"".join(s.data for s in c.segments if not s.from_robot)
            name = f"{interface}/{c.name}"
            group.append(Request(name, ["--protocol", interface, *_hint(c.version),
                                        *_files(folder, name, robot, client)]))
        groups.append(group)
    return [r for group in groups for r in group]


def hostile_requests(folder: Path) -> list[Request]:
    """Sessions no vector holds, for `make test-deep`: each interface's kept differential-fuzz
    corpus and as many seeded mutants of it (tests/fuzz/diff_sessions.py), and random robot
    states of every software version of the primary interface (tests/tools/valid.py), whole and
    cut short."""
    from tests.fuzz.diff_sessions import INTERFACES, Mutator, kept, load
    from tests.fuzz.fuzz_diff import command_args
    from tests.tools import valid

    folder.mkdir(parents=True, exist_ok=True)
    requests = []
    for interface in INTERFACES:
        rng = random.Random(interface)
        pool = [load(interface, raw) for raw in kept(interface)]
        mutate = Mutator(interface, rng)
        for i, session in enumerate(pool + [mutate(rng.choice(pool), pool) for _ in pool]):
            stem = folder / f"{interface}~{i}"
            robot, client = stem.with_suffix(".robot"), stem.with_suffix(".client")
            robot.write_bytes(session.stream(True))
            client.write_bytes(session.stream(False))
            requests.append(Request(f"hostile/{interface}/{i}", command_args(interface, session, robot, client)))
    rng = random.Random("ur")
    for version in valid.versions():
        data = valid.session(rng, version, 20)
        for cut in (len(data), rng.randrange(len(data))):
            name = f"hostile/ur/{'.'.join(map(str, version))}/{cut}"
            requests.append(Request(name, _files(folder, name, data[:cut], None)))
    return requests


def batch(requests: list[Request]) -> bytes:
    """tests/c/decode_driver.c's input: each request's argument count, then each argument."""
    out = bytearray()
    for r in requests:
        out += len(r.args).to_bytes(4, "big")
        for arg in r.args:
            out += len(arg.encode()).to_bytes(4, "big") + arg.encode()
    return bytes(out)


def answers(output: bytes, requests: list[Request]) -> dict[str, bytes]:
    """The driver's output cut into each request's lines and "=CODE" line."""
    lines, out, start = output.split(b"\n")[:-1], {}, 0
    for i, line in enumerate(lines):
        if line.startswith(b"=") and len(out) < len(requests):
            out[requests[len(out)].name] = b"\n".join(lines[start:i + 1]) + b"\n"
            start = i + 1
    return out


def build_runner(run: Run, level: str, folder: Path) -> Path:
    """decode_driver.c with urwire-decode's main (renamed) and everything it links, for the run's
    target, statically."""
    need(run.cc, *run.qemu[:1])
    folder.mkdir(parents=True, exist_ok=True)
    includes = [f"-I{d}" for d in INCLUDES]
    flags = [*STRICT, level, *run.flags, *run.defines, *includes]
    main = folder / "urwire_decode_main.o"
    steps = [[run.cc, *flags, "-Dmain=urwire_decode_main", "-c", str(CLI / "main.c"), "-o", str(main)],
             [run.cc, *flags, "-o", str(folder / "decode_driver"), str(DECODE_DRIVER), str(main),
              *map(str, [*CLI_LIBRARY, GEN / "urwire.c", *run.sources]), "-lm"]]
    for cmd in steps:
        result = subprocess.run(cmd, capture_output=True, text=True)
        assert result.returncode == 0 and result.stderr == "", f"{' '.join(cmd)}\n{result.stderr[-3000:]}"
    return folder / "decode_driver"


def run_batch(command: list[str], requests: list[Request], timeout: int) -> dict[str, bytes]:
    result = subprocess.run(command, input=batch(requests), capture_output=True, timeout=timeout)
    assert result.returncode == 0 and result.stderr == b"", result.stderr.decode(errors="replace")[-3000:]
    out = answers(result.stdout, requests)
    assert len(out) == len(requests), f"{len(out)} of {len(requests)} answered"
    return out


@pytest.fixture(scope="module")
def vectors(tmp_path_factory) -> Path:
    """The folder the vectors' streams are written to."""
    return tmp_path_factory.mktemp("vectors")


_X86: dict[tuple, dict[str, bytes]] = {}


def x86_answers(run: Run, requests: list[Request], folder: Path) -> dict[str, bytes]:
    """The answers of the x86 build (gcc -O2, with the run's defines) to these requests."""
    key = (tuple(run.defines), tuple(r.name for r in requests))
    if key not in _X86:
        # With no defines, the gcc build of the other C tests, its objects shared with them.
        program = (build_runner(Run("x86", "gcc", [], run.defines, [], []), "-O2", folder / "x86") if run.defines
                   else build_decode_driver("gcc"))
        _X86[key] = run_batch([str(program)], requests, 300)
        refused = [name for name, text in _X86[key].items() if not text.endswith((b"=0\n", b"=1\n"))]
        assert not refused, f"urwire-decode refused these command lines: {refused}"
    return _X86[key]


def compare(run: Run, level: str, requests: list[Request], folder: Path) -> None:
    program = build_runner(run, level, folder)
    expected = x86_answers(run, requests, folder)
    got = run_batch([*run.qemu, str(program)], requests, 600)
    differ = [r.name for r in requests if got[r.name] != expected[r.name]]
    assert not differ, (f"{run.name} {level}: {len(differ)} of {len(requests)} differ from x86, first "
                        f"{differ[0]}:\n{got[differ[0]].decode(errors='replace')[:2000]}\nx86:\n"
                        f"{expected[differ[0]].decode(errors='replace')[:2000]}")


@pytest.mark.parametrize("run", sorted(RUNS))
def test_every_vector_gives_x86s_bytes_at_os(run, vectors, tmp_path):
    """Each run takes a second or less under QEMU: its build is most of the test's time."""
    compare(RUNS[run], "-Os", vector_requests(vectors), tmp_path)


def test_the_cortex_m_board_traps_an_unaligned_load(tmp_path):
    """The Cortex-M run would stop at any unaligned access, as a Cortex-M0+ does (its start code
    sets CCR.UNALIGN_TRP): here one ends the run with an error."""
    run = RUNS["mps2-an386"]
    need(run.cc, run.qemu[0])
    source = tmp_path / "unaligned.c"
    # The offset is read at run time, or the compiler, seeing the misalignment, loads bytes.
    source.write_text("#include <stdint.h>\nstatic uint32_t words[2];\nstatic volatile int one = 1;\n"
                      "int main(void)\n{\n"
                      "    const uint32_t *p = (const uint32_t *)(void *)((unsigned char *)words + one);\n"
                      "    return (int)*p;\n}\n")
    program = tmp_path / "unaligned"
    subprocess.run([run.cc, *STRICT, "-O2", *run.flags, "-o", str(program), str(source), *map(str, run.sources)],
                   check=True, capture_output=True)
    result = subprocess.run([*run.qemu, str(program)], capture_output=True, timeout=60)
    assert result.returncode != 0 and b"fault" in result.stderr, (result.returncode, result.stderr)


@pytest.mark.deep
@pytest.mark.parametrize("level", ["-Os", "-O2"])
@pytest.mark.parametrize("run", sorted(RUNS))
def test_hostile_sessions_give_x86s_bytes(run, level, vectors, tmp_path):
    """The vectors again at -O2, and sessions no vector holds at both levels."""
    requests = hostile_requests(vectors / "hostile")
    compare(RUNS[run], level, requests + (vector_requests(vectors) if level == "-O2" else []), tmp_path)
