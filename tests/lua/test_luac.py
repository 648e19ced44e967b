"""Every generated dissector (generated/lua/*.lua: one per interface) parses with every Lua that
Wireshark embeds (5.2 to 5.4), uses no operator of one Lua only, and assigns no global."""
import shutil
import subprocess

import pytest

from tests.lua.harness import PLUGIN

PLUGINS = sorted(PLUGIN.parent.glob("*.lua"))


def test_every_interface_has_its_dissector():
    assert PLUGIN in PLUGINS and len(PLUGINS) >= 2


@pytest.mark.parametrize("plugin", PLUGINS, ids=lambda p: p.name)
@pytest.mark.parametrize("luac", ["luac5.2", "luac5.3", "luac5.4"])
def test_parses(luac, plugin):
    assert shutil.which(luac), f"{luac} is not installed"
    res = subprocess.run([luac, "-p", str(plugin)], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr


@pytest.mark.parametrize("plugin", PLUGINS, ids=lambda p: p.name)
def test_no_operators_of_one_lua_only(plugin):
    text = plugin.read_text(encoding="utf-8")
    code = "\n".join(line.split("--")[0] for line in text.splitlines())
    for op in ("//", "<<", ">>", "goto ", "bit32."):
        assert op not in code, f"{op!r} is not in every Lua that Wireshark embeds"


@pytest.mark.parametrize("plugin", [p for p in PLUGINS if p != PLUGIN], ids=lambda p: p.name)
def test_assigns_no_global(plugin):
    listing = subprocess.run(["luac5.2", "-l", "-p", str(plugin)], capture_output=True, text=True,
                             check=True).stdout
    leaks = [line for line in listing.splitlines() if "SETTABUP" in line and "_ENV" in line]
    assert not leaks, leaks[:5]
