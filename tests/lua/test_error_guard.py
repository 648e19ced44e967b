"""The RTDE and real-time dissectors run behind the error guard every urwire Lua dissector has
(runtime/lua/common/guard.lua): a Lua error while dissecting shows as the expert
<protocol>.internal_error, "<protocol>: <the error>", on the packet, and never as a Lua error.
A copy of each plugin throws where a packet holds the bytes DAMAGED, and the cell capture with
those bytes written over one packet of the protocol trips it (tests/lua/test_differential.py does
the same for the primary dissector)."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from tests.lua.harness import ROOT

CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"
MARK = b"DAMAGED"
# protocol: the port whose robot-side packets are damaged
PORTS = {"rtde": 30004, "ur_realtime": 30003}
ANCHOR = "local function dissect(tvb, pinfo, tree)\n"


def throwing_copy(protocol: str, folder: Path) -> Path:
    """The generated plugin, throwing on a packet that holds MARK."""
    text = (ROOT / "generated" / "lua" / f"{protocol}.lua").read_text(encoding="utf-8")
    assert text.count(ANCHOR) == 1, f"{protocol}.lua: no single dissect() to break"
    throw = f'    if string.find(tvb:raw(), "{MARK.decode()}", 1, true) then error("bytes it cannot read") end\n'
    path = folder / f"{protocol}.lua"
    path.write_text(text.replace(ANCHOR, ANCHOR + throw), encoding="utf-8")
    return path


def damaged_capture(protocol: str, folder: Path) -> Path:
    """The cell capture with MARK written over the last bytes of the robot's first packet of the protocol
    longer than 16 bytes."""
    payload = subprocess.run(["tshark", "-r", str(CELL), "-Y", f"tcp.srcport == {PORTS[protocol]} && tcp.len > 16",
                              "-T", "fields", "-e", "tcp.payload"],
                             capture_output=True, text=True, check=True).stdout.split()[0]
    data, raw = CELL.read_bytes(), bytes.fromhex(payload.replace(":", ""))
    assert data.count(raw) == 1 and len(raw) > len(MARK)
    path = folder / f"damaged_{protocol}.pcapng"
    path.write_bytes(data.replace(raw, raw[:-len(MARK)] + MARK))
    return path


def tshark(pcap: Path, plugin: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["tshark", "-r", str(pcap), "-X", f"lua_script:{plugin}", *args],
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("protocol", sorted(PORTS))
def test_a_lua_error_shows_as_the_protocols_expert(protocol, tmp_path):
    plugin = throwing_copy(protocol, tmp_path)
    shown = tshark(damaged_capture(protocol, tmp_path), plugin, "-V")
    assert shown.returncode == 0, shown.stderr
    assert "Lua: Error" not in shown.stderr + shown.stdout and "Lua Error" not in shown.stdout
    assert f"(Error/Malformed): {protocol}: " in shown.stdout and "bytes it cannot read" in shown.stdout
    experts = tshark(damaged_capture(protocol, tmp_path), plugin, "-Y", f"{protocol}.internal_error",
                     "-T", "fields", "-e", "frame.number").stdout.split()
    assert len(experts) == 1, experts
    # The same copy on the capture as recorded: nothing to catch.
    assert f"{protocol}.internal_error" not in tshark(CELL, plugin, "-T", "json").stdout
