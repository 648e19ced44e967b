"""The one reader of a version preference's text (runtime/epan/common/dotted_version.c), which every
native dissector joins, compiled alone against Wireshark's headers and checked by
dotted_version_unit.c: the Lua pattern's grammar when the text must be whole, the primary
interface's (text may follow) when not."""
from __future__ import annotations

import subprocess

import pytest

from tests.native.harness import ROOT

FOLDER = ROOT / "runtime" / "epan" / "common"


@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_reader_alone(tmp_path, cc):
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "wireshark"], capture_output=True, text=True,
                           check=True)
    binary, source = tmp_path / "dotted_version_unit", ROOT / "tests" / "native" / "dotted_version_unit.c"
    build = subprocess.run([cc, "-std=gnu11", "-Wall", "-Wextra", "-Werror", "-fsanitize=address,undefined",
                            "-fno-sanitize-recover=all", f"-I{FOLDER}", str(source), *flags.stdout.split(),
                            "-o", str(binary)], capture_output=True, text=True)
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(binary)], capture_output=True, text=True, env={"ASAN_OPTIONS": "detect_leaks=0"})
    assert run.stdout == "ok\n" and run.returncode == 0, run.stdout + run.stderr
