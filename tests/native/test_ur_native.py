"""The native dissector of the primary/secondary interface (generated/epan/packet-ur.c, protocol
`ur`) against its Lua twin (generated/lua/urwire.lua): each loaded alone in real tshark, they
must register the same fields and show the same layers (-T json), Info column and expert infos
on every capture the Lua dissector is tested with. The captures are batched: many TCP sessions
per capture, so that a few tshark runs cover every vector."""
from __future__ import annotations

import functools
import json
import os
import subprocess
import tempfile
from pathlib import Path

import pytest

from tests.native import harness
from tests.tools import capture
from tests.vectors import golden_cases

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


# ---- captures: many sessions each, fed to both dissectors ----

def _sessions(streams: list[list[bytes]], pcapng: bool = False, handshake: bool = True,
              retransmit_every: int = 0) -> bytes:
    """One TCP session per stream (a list of robot segment payloads), as tests/lua writes them."""
    frames = []
    for i, segments in enumerate(streams):
        again = range(0, len(segments), retransmit_every) if retransmit_every else ()
        frames += capture.session_frames([capture.Segment(True, s) for s in segments], port=30001,
                                         client_port=20000 + i % 40000, handshake=handshake, retransmit=again)
    with tempfile.TemporaryDirectory() as folder:
        return capture.write(Path(folder) / "sessions.pcap", frames, pcapng=pcapng).read_bytes()


def _first_difference(a, b, path="") -> str:
    """Where two JSON values first differ, for a readable failure."""
    if type(a) is not type(b):
        return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"
    if isinstance(a, dict):
        if list(a) != list(b):
            return f"{path}: keys {list(a)[:20]} != {list(b)[:20]}"
        for k in a:
            if a[k] != b[k]:
                return _first_difference(a[k], b[k], f"{path}.{k}")
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{path}: {len(a)} items != {len(b)} items"
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                return _first_difference(x, y, f"{path}[{i}]")
    return f"{path}: {json.dumps(a)[:300]} != {json.dumps(b)[:300]}"


def assert_same(capture_bytes: bytes, *args: str) -> harness.Shown:
    """Both dissectors show the same layers, Info column and expert infos of the capture."""
    native = harness.shown(harness.run_native, capture_bytes, ["ur"], *args)
    lua = harness.shown(LUA, capture_bytes, ["ur"], *args)
    assert len(native.layers) == len(lua.layers)
    for frame, (n, l) in enumerate(zip(native.layers, lua.layers), start=1):
        assert n == l, f"frame {frame}: native {_first_difference(n, l)}"
    for frame, (n, l) in enumerate(zip(native.info, lua.info), start=1):
        assert n == l, f"frame {frame}: Info column\n native: {n}\n    lua: {l}"
    assert native.info == lua.info
    assert native.experts == lua.experts
    return native


def _split(data: bytes) -> list[bytes]:
    """A stream cut at its declared lengths where they are plausible (else kept whole)."""
    out, pos = [], 0
    while len(data) - pos >= 5:
        n = int.from_bytes(data[pos:pos + 4], "big", signed=True)
        if n < 5 or pos + n > len(data):
            break
        out.append(data[pos:pos + n])
        pos += n
    if pos < len(data):
        out.append(data[pos:])
    return out


GOLDEN = golden_cases()
HINTS = sorted({c.version or "" for c in GOLDEN})


def _golden_capture(hint: str, cut) -> bytes:
    return _sessions([cut(_split(c.data)) for c in GOLDEN if (c.version or "") == hint])


def _prefs(hint: str) -> tuple[str, ...]:
    return ("-o", f"ur.version:{hint}") if hint else ()


@pytest.mark.parametrize("hint", HINTS, ids=lambda h: h or "no hint")
def test_golden_vectors_whole(hint):
    shown = assert_same(_golden_capture(hint, capture.whole), *_prefs(hint))
    assert any(layer for layer in shown.layers)
