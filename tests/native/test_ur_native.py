"""The native dissector of the primary/secondary interface (generated/epan/packet-ur.c, protocol
`ur`) against its Lua twin (generated/lua/urwire.lua): each loaded alone in real tshark, they
must register the same fields and show the same layers (-T json), Info column and expert infos
on every capture the Lua dissector is tested with. The captures are batched: many TCP sessions
per capture, so that a few tshark runs cover every vector."""
from __future__ import annotations

import functools
import os
import subprocess

from tests.native import harness

LUA = functools.partial(harness.run_lua, lua=[harness.lua_plugin("ur")])


def _fields(result) -> list[list[str]]:
    """The `ur` protocol line and field lines of `tshark -G fields`, split into columns."""
    err = result.stderr.decode(errors="replace")
    assert result.returncode == 0 and "Lua: Error" not in err, err[:3000]
    rows = [line.split("\t") for line in result.stdout.decode().splitlines()]
    return [r for r in rows if (r[0] == "P" and r[2:3] == ["ur"]) or (r[0] == "F" and r[4:5] == ["ur"])]


def test_both_register_the_same_fields_in_the_same_order():
    native = _fields(harness.native_tshark(["-G", "fields"]))
    lua = _fields(_lua_fields())
    assert len(native) > 300
    # Kind, name, abbreviation, type, protocol, base and bitmask, line for line.
    assert [r[:7] for r in native] == [r[:7] for r in lua]
    # Descriptions too, where Lua has one: Wireshark 4.0 drops the description of a Lua string field.
    differ = [(n[2], n[7], l[7]) for n, l in zip(native, lua) if len(l) > 7 and l[7] and n[7:8] != l[7:8]]
    assert not differ, differ[:5]


def _lua_fields() -> subprocess.CompletedProcess:
    """tshark -G fields with the Lua dissector alone (-G must come first, so not through run_lua)."""
    environment = {**os.environ, "HOME": str(harness._empty_home())}
    environment.pop("XDG_CONFIG_HOME", None)
    return subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{harness.lua_plugin('ur')}"],
                          capture_output=True, env=environment, timeout=120)
