"""Static analysis of the C (mk/static.mk, `make static-c`): over every interface's generated C, the
C runtime on its own and tools/urwire-decode, cppcheck finds nothing (seconds: here) and clang-tidy
with .clang-tidy finds nothing (1.5 to 6 minutes on a shared 2-core machine: `make test-deep`).
Each tool is also shown a file with a bug, through the same target, to prove a finding fails it, and
no C file of the tree is left out. Outside CI a missing tool skips; in CI (CI=true) it fails."""
from __future__ import annotations

import os
import shutil
import subprocess

import pytest

from tests.c.harness_c import OUT, ROOT


def require(tool: str) -> None:
    if shutil.which(tool) is None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"{tool} is not installed (scripts/setup.sh installs it)")
        pytest.skip(f"{tool} is not installed")


def make(target: str, *overrides: str) -> tuple[int, str]:
    """The target's exit status and what the tools said, less clang-tidy's count of the warnings
    it left unshown (system headers)."""
    result = subprocess.run(["make", "-s", "--no-print-directory", target, *overrides], cwd=ROOT,
                            capture_output=True, text=True)
    lines = (result.stdout + result.stderr).splitlines()
    return result.returncode, "\n".join(line for line in lines if line.strip() and
                                        not line.endswith("warnings generated.") and not line.startswith("make: ***"))


def bad_file() -> str:
    """A file under the tree (so that clang-tidy finds .clang-tidy) that writes past an array."""
    path = OUT / "static" / "bad.c"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("int bad(int k)\n{\n    int a[2] = {0, 0};\n    a[2] = k;\n    return a[0] / (k - k);\n}\n")
    return str(path.relative_to(ROOT))


def test_every_c_file_is_analysed():
    """Each C file of the generated parsers, the runtime and the command is read by the tools on
    its own, or, for a runtime fragment with no includes of its own, inside a generated file
    that joins it."""
    status, said = make("static-c-files")
    assert status == 0, said
    read = set(said.splitlines())
    joined = "".join(path.read_text() for path in sorted((ROOT / "generated" / "c").glob("*.c")))
    files = [*(ROOT / "generated" / "c").glob("*.c"), *(ROOT / "runtime" / "c").rglob("*.c"),
             *(ROOT / "tools" / "urwire-decode").glob("*.c")]
    unread = [name for name in sorted(str(path.relative_to(ROOT)) for path in files) if name not in read and
              ("#include" in (ROOT / name).read_text() or f"/* ---- {name} ---- */" not in joined)]
    assert unread == []


def test_cppcheck_finds_nothing():
    require("cppcheck")
    status, said = make("static-c-cppcheck")
    assert status == 0 and said == "", said


@pytest.mark.deep
def test_clang_tidy_finds_nothing():
    require("clang-tidy")
    status, said = make("static-c-tidy")
    assert status == 0 and said == "", said


@pytest.mark.parametrize("tool, target, finding", [("cppcheck", "static-c-cppcheck", "arrayIndexOutOfBounds"),
                                                   ("clang-tidy", "static-c-tidy", "clang-analyzer-core.DivideZero")])
def test_a_finding_fails_the_target(tool, target, finding):
    require(tool)
    status, said = make(target, "STATIC_C_GROUPS=bad", f"STATIC_C_bad={bad_file()}")
    assert status != 0 and finding in said, said
