"""The generated dissector parses with every Lua that Wireshark embeds (5.2 to 5.4)."""
import shutil
import subprocess

import pytest

from tests.lua.harness import PLUGIN


@pytest.mark.parametrize("luac", ["luac5.2", "luac5.3", "luac5.4"])
def test_parses(luac):
    assert shutil.which(luac), f"{luac} is not installed"
    res = subprocess.run([luac, "-p", str(PLUGIN)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


def test_no_operators_of_one_lua_only():
    text = PLUGIN.read_text(encoding="utf-8")
    code = "\n".join(line.split("--")[0] for line in text.splitlines())
    for op in ("//", "<<", ">>", "goto ", "bit32."):
        assert op not in code, f"{op!r} is not in every Lua that Wireshark embeds"
