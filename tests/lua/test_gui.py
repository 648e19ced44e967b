"""The dissector in the real Wireshark GUI (wireshark-qt under xvfb-run): it loads, reads the
bundled capture, and a display filter on its fields leaves packets in the list, with no Lua error
and no error dialog. Each run is bounded (a minute at most; about ten seconds when it works)."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from tests.lua.harness import PLUGIN, ROOT, run_tshark
from tests.tools.gui import SCREEN

SAMPLE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
FILTER = 'ur.robot_mode_data.robot_mode == "RUNNING" && ur.joint_data.q_actual > 1.5'


def open_in_gui(capture, display_filter: str, plugin=PLUGIN, timeout: int = 60) -> dict:
    missing = [tool for tool in ("wireshark", "xvfb-run", "xdotool") if not shutil.which(tool)]
    if missing:
        pytest.fail(f"{', '.join(missing)} missing: scripts/setup.sh installs them")
    res = subprocess.run(["xvfb-run", "-a", "-s", SCREEN, sys.executable, "-m", "tests.tools.gui", "smoke",
                          str(capture), display_filter, "--plugin", str(plugin), "--timeout", str(timeout)],
                         cwd=ROOT, capture_output=True, text=True, timeout=timeout + 60)
    assert res.returncode == 0, res.stderr[-2000:]
    return json.loads(res.stdout.splitlines()[-1])


def test_the_gui_shows_the_filtered_packets_without_a_lua_error():
    shown = open_in_gui(SAMPLE, FILTER)
    counts = shown["counts"]
    assert counts is not None, f"the GUI read no packet: {shown}"
    expected = len(run_tshark(SAMPLE, "-Y", FILTER, "-T", "fields", "-e", "frame.number").split())
    assert expected > 0
    assert counts["frames"] == len(run_tshark(SAMPLE, "-T", "fields", "-e", "frame.number").split())
    assert counts["shown"] == expected, "the packet list holds what the filter matches in tshark"
    assert counts["faults"] == 0, "no Lua error, internal error or malformed packet"
    assert shown["windows"] == [SAMPLE.name], "one main window and no error dialog"
    assert shown["lua_lines"] == []


def test_a_plugin_that_fails_to_load_fails_the_check(tmp_path):
    broken = tmp_path / "broken.lua"
    broken.write_text(PLUGIN.read_text(encoding="utf-8").replace("local ur = Proto(", "local ur = = Proto(", 1),
                      encoding="utf-8")
    shown = open_in_gui(SAMPLE, "ur", plugin=broken, timeout=10)
    assert shown["counts"] is None or shown["counts"]["shown"] == 0
    assert shown["windows"] != [SAMPLE.name], "Wireshark shows the Lua error in a dialog"
