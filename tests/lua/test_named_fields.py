"""tshark -T fields builds only the values its command line names (runtime/lua/common/wanted.lua), in
the RTDE and the real-time dissectors as in the primary one (tests/lua/test_behaviour.py): the values
printed are those of the whole tree, and a value no argument names is not built (a postdissector
reading it with Field.new sees none)."""
from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from tests.lua.harness import ROOT, _checked

CELL = ROOT / "dissector" / "samples" / "cell_session.pcapng"
LUA = ROOT / "generated" / "lua"

# protocol: (a value to print, a filter on another, a value of the same packets that neither names)
CASES = {
    "rtde": ("rtde.actual_q", "rtde.robot_mode == 7", "rtde.timestamp"),
    "ur_realtime": ("ur_realtime.q_actual", "ur_realtime.robot_mode == 7", "ur_realtime.qd_actual"),
}

# A postdissector that writes to stderr how many items of FIELD each frame has.
PROBE = """local field = Field.new("FIELD")
local probe = Proto("urwire_probe", "urwire probe")
function probe.dissector(tvb, pinfo, tree)
    local n = select("#", field())
    if n > 0 then io.stderr:write("probe " .. pinfo.number .. " " .. n .. "\\n") end
end
register_postdissector(probe)
"""


def tshark(protocol: str, *args: str, probe: Path | None = None) -> subprocess.CompletedProcess:
    scripts = [f"lua_script:{LUA / (protocol + '.lua')}"] + ([f"lua_script:{probe}"] if probe else [])
    cmd = ["tshark", "-r", str(CELL), *(a for s in scripts for a in ("-X", s)), *args]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    _checked(res)
    return res


def whole_tree(protocol: str, field: str, *args: str) -> list[str]:
    """Each frame's values of field as -T fields prints them, from -T json (which builds every field)."""
    frames = json.loads(tshark(protocol, *args, "-T", "json", "-e", field).stdout)
    return [",".join(frame["_source"]["layers"].get(field, [])) for frame in frames]


@pytest.mark.parametrize("protocol", sorted(CASES))
def test_one_value_prints_as_in_the_whole_tree(protocol):
    field, condition, _ = CASES[protocol]
    for args in ((), ("-Y", condition)):
        named = tshark(protocol, *args, "-T", "fields", "-e", field).stdout.splitlines()
        assert any(named), (protocol, args)
        assert named == whole_tree(protocol, field, *args), (protocol, args)


@pytest.mark.parametrize("protocol", sorted(CASES))
def test_a_value_no_argument_names_is_not_built(protocol, tmp_path):
    field, _, other = CASES[protocol]
    probe = tmp_path / "probe.lua"
    probe.write_text(PROBE.replace("FIELD", other), encoding="utf-8")
    seen = tshark(protocol, "-T", "fields", "-e", field, probe=probe).stderr
    assert "probe " not in seen
    seen = tshark(protocol, "-T", "fields", "-e", field, "-e", other, probe=probe).stderr
    assert "probe " in seen
    assert "probe " in tshark(protocol, "-V", probe=probe).stderr
