"""tshark with every dissector of generated/lua/ loaded reads the bundled capture of a whole cell
(dissector/samples/cell_session.pcapng) with no expert error, each interface under its own
protocol; the RTDE setup's NOT_FOUND and IN_USE are the warnings they should be."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "cell_session.pcapng"
PLUGINS = sorted((ROOT / "generated" / "lua").glob("*.lua"))
PROTOCOLS = {"ur", "ur_realtime", "rtde", "ur_dashboard", "ur_reverse", "ur_script_sender", "ur_trajectory",
             "ur_script_command"}
PI_ERROR, PI_WARN = 0x00800000, 0x00600000

pytestmark = pytest.mark.skipif(shutil.which("tshark") is None, reason="tshark is not installed")


def frames() -> list[tuple[set, list, list]]:
    """(protocols, expert severities, expert messages) of each frame."""
    args = ["tshark", "-r", str(SAMPLE)]
    for plugin in PLUGINS:
        args += ["-X", f"lua_script:{plugin}"]
    args += ["-T", "fields", "-E", "occurrence=a", "-E", "aggregator=|", "-e", "frame.protocols",
             "-e", "_ws.expert.severity", "-e", "_ws.expert.message"]
    res = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    out = []
    for line in res.stdout.splitlines():
        protocols, severities, messages = (line.split("\t") + ["", ""])[:3]
        out.append((set(protocols.split(":")), [int(s) for s in severities.split("|") if s],
                    [m for m in messages.split("|") if m]))
    return out


def test_every_interface_is_dissected_with_no_expert_error():
    seen = frames()
    assert set().union(*(p for p, _, _ in seen)) >= PROTOCOLS
    errors = [(m, s) for _, s, m in seen if any(x >= PI_ERROR for x in s)]
    assert not errors
    warnings = {m for _, s, ms in seen for m, x in zip(ms, s) if x == PI_WARN}
    assert {"not_a_variable: NOT_FOUND", "input_int_register_24: IN_USE"} <= warnings


def test_each_interface_names_itself_in_the_protocol_column():
    """A frame of each interface's port says which interface it is, in words (the frames that
    carry only a TCP acknowledgement say TCP)."""
    args = ["tshark", "-r", str(SAMPLE)]
    for plugin in PLUGINS:
        args += ["-X", f"lua_script:{plugin}"]
    args += ["-Y", "tcp.len > 0", "-T", "fields", "-e", "tcp.srcport", "-e", "tcp.dstport", "-e", "_ws.col.Protocol"]
    res = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    want = {30001: "UR", 30002: "UR", 30003: "UR real-time", 30004: "RTDE", 29999: "UR dashboard",
            50001: "UR reverse", 50002: "UR script sender", 50003: "UR trajectory", 50004: "UR script command",
            30020: "UR interpreter", 63352: "Robotiq gripper"}
    columns: dict[int, set] = {}
    for line in res.stdout.splitlines():
        source, destination, column = line.split("\t")
        port = int(source) if int(source) in want else int(destination)
        columns.setdefault(port, set()).add(column)
    assert {port: columns[port] for port in columns} == {port: {want[port]} for port in columns}
    assert len(columns) >= 10
