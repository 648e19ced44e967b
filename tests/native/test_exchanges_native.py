"""Request/response tracking in the native plugin (generated/epan/packet-ur-dashboard.c and
packet-rtde.c): the links the protocol's rule gives, each time the frames' difference, on the same
captures as the Lua dissectors (tests/lua/test_exchanges.py, whose checks run here on the plugin),
and the same `-T json` layers, Info column and expert infos as the Lua twins. Also the runtime that
keeps the links, compiled alone: runtime/epan/common/exchange.c, which every dissector that links
replies joins, and runtime/epan/typed_messages/rtde_exchanges.c, RTDE's pairs."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tests.lua.test_exchanges import CELL, PORTS, check, dashboard_capture, linked, rtde_capture, shown
from tests.native import harness
from tests.native.lua_twin import as_lua_writes
from tests.native.test_lines_native import lua_shown, native_run

ROOT = Path(__file__).resolve().parents[2]
RUNTIME = ROOT / "runtime" / "epan"


def native(capture_: Path, *args: str) -> str:
    return harness.checked(harness.run_native(capture_, *args))


def test_the_cell_samples_replies_link_with_their_requests():
    for protocol, at_least in (("ur_dashboard", 2), ("rtde", 6)):
        requests, replies = linked(check(native, CELL, protocol))
        assert requests == replies >= at_least, protocol


def test_segmented_and_interleaved_conversations(tmp_path):
    assert linked(check(native, dashboard_capture(tmp_path), "ur_dashboard")) == (8, 8)


def test_rtde_pairs_apart_past_max_pending_and_from_mid_session(tmp_path):
    assert linked(check(native, rtde_capture(tmp_path), "rtde")) == (15, 15)


def test_one_pass_shows_replies_links_but_not_yet_requests(tmp_path):
    frames = shown(native, dashboard_capture(tmp_path), "ur_dashboard")
    assert not any(f.response_in for f in frames) and any(f.response_to for f in frames)


def same_in_both(pcap: Path, protocol: str, args: tuple, variant: str) -> list:
    """The -T json layers, Info column and expert infos of the native dissector and the Lua one
    alike, a native subtree's text keyed as Lua keys it (lua_twin.as_lua_writes)."""
    native = harness.shown(native_run(variant), pcap, [protocol], *args)
    lua = lua_shown(pcap, [protocol], *args)
    layers = [as_lua_writes(layer) for layer in native.layers]
    assert layers == lua.layers and native.info == lua.info and native.experts == lua.experts
    return layers


# The plain build, and the one built with ASan and UBSan (a `deep` test: tests/native/conftest.py).
@pytest.mark.parametrize("variant", ["gcc", "asan"])
@pytest.mark.parametrize("protocol", ["ur_dashboard", "rtde"])
def test_native_and_lua_show_the_same(tmp_path, protocol, variant):
    made = dashboard_capture(tmp_path) if protocol == "ur_dashboard" else rtde_capture(tmp_path)
    for pcap, args in ((made, ()), (CELL, ("-Y", f"tcp.port == {PORTS[protocol]}"))):
        layers = same_in_both(pcap, protocol, args, variant)
        assert any("response_in" in str(layer) for layer in layers), pcap


@pytest.mark.parametrize("source", [RUNTIME / "common" / "exchange.c", RUNTIME / "typed_messages" / "rtde_exchanges.c"])
def test_the_runtime_compiles_alone(source):
    flags = subprocess.run(["pkg-config", "--cflags", "wireshark"], capture_output=True, text=True, check=True)
    result = subprocess.run(["gcc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function",
                             "-fsyntax-only", *flags.stdout.split(), str(source)],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
