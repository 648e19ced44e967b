"""The dissectors' hand-written runtime (runtime/lua/common, shared by every kind, and
runtime/lua/<kind>), file by file: each parses with every Lua that Wireshark embeds, assigns no
global, and passes its own small tests (tests/lua/runtime/test_*.lua) under plain lua5.2, lua5.3
and lua5.4, with stub Wireshark objects (tests/lua/runtime/stubs.lua). No tshark here: these run
in seconds."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from tests.lua.harness import PLUGIN, ROOT

RUNTIME = ROOT / "runtime" / "lua"
TESTS = Path(__file__).resolve().parent / "runtime"
LUAS = ["5.2", "5.3", "5.4"]
# Every runtime file, as the tests load it: "common/guard.lua", "packages/walk.lua"...
FILES = sorted(p.relative_to(RUNTIME).as_posix() for p in RUNTIME.glob("*/*.lua"))
KINDS = ("packages", "typed_messages", "sized_packets", "lines", "int32_records")
SCRIPTS = sorted(p.name for p in TESTS.glob("test_*.lua"))


def test_the_runtime_and_its_tests_are_there():
    assert len(FILES) >= 8 and SCRIPTS
    folders = sorted({name.split("/")[0] for name in FILES})
    assert folders == sorted(("common",) + KINDS), f"runtime/lua holds a folder per kind and common/: {folders}"
    assert not list(RUNTIME.glob("*.lua")), "every runtime file sits in its kind's folder or in common/"
    loaded = "".join(p.read_text(encoding="utf-8") for p in TESTS.glob("*.lua"))
    untested = [name for name in FILES if f'"{name}"' not in loaded]
    assert not untested, f"runtime files no test loads: {untested}"


@pytest.mark.parametrize("lua", LUAS)
@pytest.mark.parametrize("name", FILES)
def test_each_runtime_file_parses_alone(name, lua):
    luac = f"luac{lua}"
    assert shutil.which(luac), f"{luac} is not installed"
    res = subprocess.run([luac, "-p", str(RUNTIME / name)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


@pytest.mark.parametrize("name", FILES)
def test_each_runtime_file_assigns_no_global(name):
    listing = subprocess.run(["luac5.2", "-l", "-p", str(RUNTIME / name)], capture_output=True, text=True,
                             check=True).stdout
    leaks = [line for line in listing.splitlines() if "SETTABUP" in line and "_ENV" in line]
    assert not leaks, leaks[:5]


@pytest.mark.parametrize("name", FILES)
def test_each_runtime_file_takes_spec_and_rt(name):
    """The joined file calls every runtime chunk with (spec, rt); constants come from spec."""
    text = (RUNTIME / name).read_text(encoding="utf-8")
    assert re.search(r"^local spec, rt = \.\.\.$", text, re.M), name
    code = "\n".join(line.split("--")[0] for line in text.splitlines())
    for literal in ("5009", "\"5.9\"", "30001", "HEADER = 5"):
        assert literal not in code, f"{name}: {literal} belongs in the spec, not the runtime"
    for op in ("//", "<<", ">>", "goto ", "bit32."):
        assert op not in code, f"{name}: {op!r} is not in every Lua that Wireshark embeds"


@pytest.mark.parametrize("lua", LUAS)
@pytest.mark.parametrize("script", SCRIPTS)
def test_runtime_unit(script, lua):
    exe = f"lua{lua}"
    assert shutil.which(exe), f"{exe} is not installed"
    env = dict(os.environ, URWIRE_RUNTIME=str(RUNTIME), URWIRE_PLUGIN=str(PLUGIN))
    res = subprocess.run([exe, script], cwd=TESTS, env=env, capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stdout.strip() == "ok", res.stdout + res.stderr
