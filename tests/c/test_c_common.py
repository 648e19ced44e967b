"""What every kind's C runtime shares (runtime/c/common/: the big-endian loads, the output buffer,
the UTF-8 decoder, the reader of a version's text, the bytes a stream framer holds, the macros that
declare private and inlined functions) on its own: each file compiles alone under the strict flags
with gcc and clang, tests/c/common_unit.c checks it, and every generated C file that joins a file
joins it whole."""
from __future__ import annotations

import subprocess

import pytest

from codegen.emit import runtime_source
from tests.c.harness_c import GEN, OUT, ROOT, SANITIZE, STRICT

COMMON = ROOT / "runtime" / "c" / "common"
FILES = sorted(p.name for p in COMMON.iterdir())


def _build(cc: str, flags: list[str], sources: list, output) -> None:
    output.parent.mkdir(parents=True, exist_ok=True)
    cmd = [cc, *STRICT, *flags, f"-I{COMMON}", "-o", str(output), *map(str, sources)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    assert result.returncode == 0 and result.stderr == "", f"{' '.join(cmd)}\n{result.stderr}"


@pytest.mark.parametrize("cc", ["gcc", "clang"])
@pytest.mark.parametrize("name", FILES)
def test_each_file_compiles_on_its_own(cc, name):
    header = ["-x", "c"] if name.endswith(".h") else []
    _build(cc, ["-O2", "-c", *header], [COMMON / name], OUT / "common" / f"{name}-{cc}.o")


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_common_unit_checks(cc):
    exe = OUT / "common" / f"common-unit-{cc}"
    sources = [ROOT / "tests" / "c" / "common_unit.c"] + [COMMON / name for name in
                                                         ("buffer.c", "held.c", "utf8.c", "version_text.c")]
    _build(cc, ["-O1", "-g", *SANITIZE], sources, exe)
    result = subprocess.run([str(exe)], capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip() == "all common checks passed"


def test_every_generated_c_file_joins_the_loads_whole():
    """One header of big-endian loads: every kind's C joins it (in the .c, or in its header where the
    header's inline readers use them: rtde.h), and no other file defines them."""
    loads = runtime_source("c", "common/loads.h").rstrip("\n")
    for path in sorted(GEN.glob("*.c")):
        text = path.read_text() + path.with_suffix(".h").read_text()
        if "urwire__u32(" in text or "urwire__i32(" in text or "urwire__uint(" in text:
            assert text.count("/* ---- runtime/c/common/loads.h ---- */") == 1 and loads in text, path.name
