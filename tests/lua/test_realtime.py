"""The real-time dissector (generated/lua/ur_realtime.lua) in real tshark: the golden vectors in
several segmentations give the values Python gives, every field filters as ur_realtime.<field>,
a size no layout has is an expert, the client's URScript is not read as packets, and hostile
bytes raise no Lua error."""
from __future__ import annotations

import json
import random
import struct

import pytest

from tests.lua.harness import F64_TOL, ROOT, run_tshark
from tests.tools import capture
from tests.tools.capture import Segment
from tests.vectors import interface_cases, mismatches

PLUGIN = ROOT / "generated" / "lua" / "ur_realtime.lua"
CASES = interface_cases("ur_realtime")
PORT = 30003


def _values(node, out: dict) -> None:
    """Every ur_realtime.<field> under a packet's tree, in order (arrays sit in text subtrees)."""
    if isinstance(node, list):
        for item in node:
            _values(item, out)
        return
    if not isinstance(node, dict):
        return
    for key, value in node.items():
        if key.startswith("ur_realtime.") and (key.endswith("_tree") or key.count(".") > 1):
            continue                    # the flags of a double's bits: not a field of the record
        if key.startswith("ur_realtime."):
            out[key.split(".", 1)[1]] = value
        else:
            _values(value, out)


def _record(tree: dict) -> dict:
    """A packet's subtree as the canonical record it shows (values parsed back from tshark's text)."""
    fields: dict = {}
    _values(tree, fields)
    size = int(fields.pop("message_size"))
    if "raw" in fields:
        return {"type": "unknown", "message_size": size, "raw": fields["raw"].replace(":", "")}
    record = {"type": fields.pop("layout"), "message_size": size}
    for name, value in fields.items():
        record[name] = [float(v) for v in value] if isinstance(value, list) else float(value)
    return record


def dissect(pcap, *args) -> list[dict]:
    out = run_tshark(pcap, "-2", "-T", "json", "--no-duplicate-keys", "-Y", "ur_realtime", *args, plugin=PLUGIN)
    records = []
    for packet in json.loads(out or "[]"):
        layer = packet["_source"]["layers"].get("ur_realtime", [])
        for tree in layer if isinstance(layer, list) else [layer]:
            if "ur_realtime.urscript" not in tree:      # the client's text, not a packet
                records.append(_record(tree))
    return records


def pcap_of(tmp_path, data: bytes, cut: str, name: str = "rt.pcap"):
    pieces = {"whole": [data], "bytewise": capture.bytewise([data]) if len(data) < 3000 else [data],
              "random": capture.random_cuts([data], seed=len(data), max_len=700)}[cut]
    return capture.write(tmp_path / name, capture.robot_session(pieces, port=PORT))


def expected(case) -> list[dict]:
    """What the tree holds: the records but the stream fault (a cut tail waits for more bytes),
    an unknown packet without its error text (an expert says it)."""
    out = []
    for r in case.expect:
        if r["type"] == "error":
            continue
        out.append({k: v for k, v in r.items() if k != "error"})
    return out


@pytest.mark.parametrize("cut", ["whole", "random", "bytewise"])
@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_vector(case, cut, tmp_path):
    args = ["-o", f"ur_realtime.version:{case.version}"] if case.version else []
    got = dissect(pcap_of(tmp_path, case.data, cut), *args)
    assert mismatches(expected(case), got, partial=False, tolerance=F64_TOL) == []


def test_every_field_filters_and_an_unknown_size_is_an_expert(tmp_path):
    case = next(c for c in CASES if c.name.endswith("unknown_size_and_cut_tail"))
    pcap = pcap_of(tmp_path, case.data, "random")
    q = run_tshark(pcap, "-2", "-T", "fields", "-e", "ur_realtime.layout", "-Y", "ur_realtime.q_actual > 1.2",
                   plugin=PLUGIN)
    assert q.split() == ["rt_1_8", "rt_3_10"]          # q_actual[2] = 1.251953125 in both
    experts = run_tshark(pcap, "-2", "-q", "-z", "expert", plugin=PLUGIN)
    assert "Packet size 28 matches no layout" in experts
    modes = run_tshark(pcap, "-2", "-T", "fields", "-e", "ur_realtime.robot_mode", "-Y", "ur_realtime.robot_mode",
                       plugin=PLUGIN)
    assert modes.split() == ["0", "7"]


def test_the_tree_reads_in_words_with_units_and_names(tmp_path):
    case = next(c for c in CASES if c.name.endswith("cb3_3_2"))
    text = run_tshark(pcap_of(tmp_path, case.data, "whole"), "-2", "-V", "-Y", "ur_realtime", plugin=PLUGIN)
    assert "Actual joint position (rad)\n        Base: 0.501953125 rad" in text   # joints named
    assert "Motor temperature (°C)\n        Base: 30.5 °C" in text
    assert "Robot mode: 7 (RUNNING)" in text and "Program state: 2 (PLAYING)" in text


def test_the_client_sends_urscript_not_packets(tmp_path):
    case = CASES[0]
    frames = capture.session_frames([Segment(False, b"movej([0,0,0,0,0,0])\n"),
                                     Segment(True, case.data)], port=PORT)
    pcap = capture.write(tmp_path / "both.pcap", frames)
    assert len(dissect(pcap)) == len(expected(case))
    assert "movej" in run_tshark(pcap, "-2", "-T", "fields", "-e", "ur_realtime.urscript", plugin=PLUGIN)


def test_hostile_bytes_raise_no_lua_error(tmp_path):
    rng = random.Random(3)
    base = b"".join(c.data for c in CASES)
    streams = [struct.pack(">i", -1) + bytes(30), struct.pack(">i", 1 << 30) + bytes(30), b"\x00\x00",
               bytes(rng.getrandbits(8) for _ in range(5000))]
    for _ in range(5):
        mutated = bytearray(base)
        for _ in range(20):
            mutated[rng.randrange(len(mutated))] = rng.getrandbits(8)
        streams.append(bytes(mutated))
    frames = []
    for i, data in enumerate(streams):
        frames += capture.robot_session(capture.random_cuts([data], seed=i), port=PORT, client_port=40000 + i)
    run_tshark(capture.write(tmp_path / "hostile.pcap", frames), "-2", "-V", plugin=PLUGIN)


def test_installed_beside_the_primary_dissector_each_loads_on_its_own(tmp_path):
    """make install-dissector copies every generated dissector; in the plugins folder each loads
    beside the other, the real-time one taking 30003 and the primary one 30001."""
    import os
    import shutil
    import subprocess

    env = dict(os.environ, HOME=str(tmp_path))
    make = shutil.which("make")
    subprocess.run([make, "-C", str(ROOT), "install-dissector", "NATIVE=no"], env=env, check=True, capture_output=True)
    folder = tmp_path / ".local" / "lib" / "wireshark" / "plugins"
    assert (folder / "ur_realtime.lua").read_text() == PLUGIN.read_text() and (folder / "urwire.lua").exists()
    plugins = subprocess.run(["tshark", "-G", "plugins"], env=env, capture_output=True, text=True).stdout
    assert "ur_realtime.lua" in plugins and "urwire.lua" in plugins
    case = next(c for c in CASES if c.name.endswith("cb2_1_8"))
    pcap = pcap_of(tmp_path, case.data, "whole")
    res = subprocess.run(["tshark", "-r", str(pcap), "-2", "-T", "fields", "-e", "ur_realtime.layout"], env=env,
                         capture_output=True, text=True)
    assert "Lua: Error" not in res.stderr and res.stdout.split() == ["rt_1_8"]
    subprocess.run([make, "-C", str(ROOT), "uninstall-dissector"], env=env, check=True, capture_output=True)
    assert not (folder / "ur_realtime.lua").exists()


def test_without_a_tree_the_info_column_still_reads_the_layout_and_robot_mode(tmp_path):
    case = next(c for c in CASES if c.name.endswith("unknown_size_and_cut_tail"))
    whole = run_tshark(pcap_of(tmp_path, case.data, "whole"), "-2", plugin=PLUGIN)
    assert "rt_1_8, RUNNING (+2)" in whole                   # three packets in one segment
    one_by_one = capture.session_frames([Segment(True, p) for p in (case.data[:812], case.data[812:1928],
                                                                      case.data[1928:1956])], port=PORT)
    summary = run_tshark(capture.write(tmp_path / "each.pcap", one_by_one), "-2", plugin=PLUGIN)
    assert "rt_1_8, RUNNING" in summary and "rt_3_10, RUNNING" in summary and "Unknown size 28" in summary
    stats = run_tshark(pcap_of(tmp_path, case.data, "random"), "-q", "-z", "io,stat,0", plugin=PLUGIN)
    assert "Frames" in stats


def test_the_version_preference_chooses_among_forms_of_one_size(tmp_path):
    """A 1108-byte packet is CB3 3.5-3.9 or e-Series 5.0-5.3 (spec framing.same_size): joint mode
    248 is PART_D_CALIBRATION_ERROR in CB3's table only; without a version the newest is taken."""
    n = (1108 - 4) // 8
    doubles = [0.0] * n
    doubles[95:101] = [248.0] * 6           # joint_modes, after 95 doubles (RealTime 5.9 columns 96-101)
    pcap = pcap_of(tmp_path, struct.pack(f">i{n}d", 1108, *doubles), "whole")
    cb3 = run_tshark(pcap, "-2", "-V", "-o", "ur_realtime.version:3.6", plugin=PLUGIN)
    newest = run_tshark(pcap, "-2", "-V", plugin=PLUGIN)
    assert "Base: 248 (PART_D_CALIBRATION_ERROR)" in cb3
    assert "Base: 248\n" in newest and "PART_D_CALIBRATION_ERROR" not in newest
