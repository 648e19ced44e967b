"""Interpreter mode (30020) and the Robotiq gripper's socket (63352) in their Lua dissectors under
real tshark: every golden vector, whole and in one-byte segments, shows the records Python writes."""
from __future__ import annotations

import json

import pytest

from tests.interface_vectors import bytewise, conversation_cases
from tests.lua.test_dashboard import ROOT, _items, _lists, lua_expectation, tcp_segments, to_record, tshark_text
from tests.tools import capture

PORTS = {"ur_interpreter": 30020, "robotiq_gripper": 63352}
CASES = [(name, case) for name in PORTS for case in conversation_cases(name)]


@pytest.mark.parametrize("name,case", CASES, ids=[f"{n}/{c.name}" for n, c in CASES])
def test_golden_vectors_whole_and_in_one_byte_segments(tmp_path, name, case):
    plugin = ROOT / "generated" / "lua" / f"{name}.lua"
    version = ("-o", f"{name}.version:{case.version}") if case.version else ()
    for segments in (case.segments, bytewise(case.segments)):
        pcap = capture.write(tmp_path / f"{name}.pcap",
                             capture.session_frames(tcp_segments(segments), port=PORTS[name]))
        shown = []
        for frame in json.loads(tshark_text(pcap, "-2", "-T", "json", *version, plugin=plugin) or "[]",
                                object_pairs_hook=_lists):
            layer = frame["_source"]["layers"].get(name)
            if layer is not None:
                shown += [to_record(item, f"{name}.") for item in _items(layer)]
        assert shown == lua_expectation(case.expect)
