"""The C runtimes of the other kinds (runtime/c/lines/, runtime/c/int32_records/) on their own:
each file compiles alone under the strict flags, the lines matcher (which the C library and the
Wireshark dissector both join) passes lines_match_unit.c, and the scaled numbers of the int32
records are written exactly as Python's repr() writes raw / 10**decimals."""
from __future__ import annotations

import random
import subprocess

import pytest

from tests.c.harness_c import OUT, ROOT, SANITIZE, STRICT

RUNTIME = ROOT / "runtime" / "c"
FILES = sorted(p for folder in ("lines", "int32_records") for p in (RUNTIME / folder).iterdir())


@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("path", FILES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_each_file_compiles_on_its_own(cc, path):
    header = ["-x", "c"] if path.suffix == ".h" else []
    out = OUT / "kind-runtime" / f"{path.parent.name}-{path.name}-{cc}.o"
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, "-O2", "-c", *header, f"-I{path.parent}", str(path), "-o", str(out)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", result.stderr


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_lines_matcher_alone(cc):
    exe = OUT / "kind-runtime" / f"lines_match_unit-{cc}"
    exe.parent.mkdir(parents=True, exist_ok=True)
    build = subprocess.run([cc, *STRICT, "-O1", "-g", *SANITIZE, f"-I{RUNTIME / 'lines'}", "-o", str(exe),
                            str(ROOT / "tests" / "c" / "lines_match_unit.c")], capture_output=True, text=True)
    assert build.returncode == 0 and build.stderr == "", build.stderr
    run = subprocess.run([str(exe)], capture_output=True, text=True)
    assert run.stdout == "ok\n" and run.returncode == 0, run.stdout + run.stderr


def test_scaled_numbers_are_written_as_python_writes_them():
    exe = OUT / "kind-runtime" / "scaled_unit"
    exe.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run(["gcc", *STRICT, "-O1", "-g", *SANITIZE, "-o", str(exe), str(ROOT / "tests" / "c" / "scaled_unit.c")],
                   check=True, capture_output=True)
    rng = random.Random(1000000)
    pairs = [(raw, d) for d in (1, 2, 3, 6) for raw in
             [0, 1, -1, 9, 10, 99, 100, 101, 1000, 999999, 1000000, 1500000, 2147483647, -2147483648, 12000000]]
    pairs += [(rng.randrange(-2**31, 2**31), rng.choice([1, 2, 3, 4, 5, 6])) for _ in range(3000)]
    pairs += [(rng.randrange(-200, 200), 6) for _ in range(300)]
    result = subprocess.run([str(exe)], input="".join(f"{r} {d}\n" for r, d in pairs), capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    expected = [repr(r / 10 ** d) for r, d in pairs]
    wrong = [(p, got, want) for p, got, want in zip(pairs, result.stdout.splitlines(), expected) if got != want]
    assert not wrong and len(result.stdout.splitlines()) == len(pairs), wrong[:5]
