"""What a Wireshark user relies on: ports and "Decode As", the version preference and its
note, the same tree with one pass and two, the Info column, experts, no leaked globals, and
installation into the personal plugins folder."""
from __future__ import annotations

import json
import os
import shutil
import struct
import subprocess

from tests.lua.harness import (PLUGIN, ROOT, _experts, parse_json, run_tshark, to_records, tshark_json,
                               ur_items_by_stream, write_sessions)
from tests.tools import capture
from tests.tools.capture import Segment

import urwire  # noqa: E402

SAMPLE = ROOT / "dissector" / "samples" / "primary_session.pcapng"


def text_message(text: bytes, ts: int = 1) -> bytes:
    body = struct.pack(">QbB", ts, -2, 0) + text
    return struct.pack(">iB", 5 + len(body), 20) + body


def update_5_0_bool() -> bytes:
    """A global-variables update whose first value is 0x0c: BOOL in 3.3-5.8, POSE from 5.9."""
    body = struct.pack(">QBH", 7, 1, 0) + b"\x0c\x01\x0a"
    return struct.pack(">iB", 5 + len(body), 25) + body


def test_no_global_is_assigned():
    listing = subprocess.run(["luac5.2", "-l", "-p", str(PLUGIN)], capture_output=True, text=True, check=True).stdout
    leaks = [line for line in listing.splitlines() if "SETTABUP" in line and "_ENV" in line]
    assert not leaks, leaks[:5]


def test_ports_preference_and_decode_as(tmp_path):
    frames = capture.session_frames([Segment(True, text_message(b"hello"))], port=40000)
    pcap = capture.write(tmp_path / "p40000.pcap", frames)
    assert not run_tshark(pcap, "-Y", "ur.text").strip()
    assert "hello" in run_tshark(pcap, "-o", "ur.ports:40000", "-Y", "ur.text", "-T", "fields", "-e", "ur.text.text")
    assert "hello" in run_tshark(pcap, "-d", "tcp.port==40000,ur", "-Y", "ur.text", "-T", "fields", "-e", "ur.text.text")


def test_the_four_ports_are_taken_from_mrcpv2(tmp_path):
    for port in (30001, 30002, 30011, 30012):
        frames = capture.session_frames([Segment(True, text_message(b"x"))], port=port)
        out = run_tshark(capture.write(tmp_path / f"{port}.pcap", frames), "-T", "fields", "-e", "_ws.col.Protocol")
        assert "UR" in out.split() and "MRCPv2" not in out


def test_version_assumed_then_preference(tmp_path):
    pcap = write_sessions(tmp_path / "noversion.pcap", [[update_5_0_bool()]])
    frames = tshark_json(pcap)
    (u,) = ur_items_by_stream(frames)[0]
    obj = u["ur.global_variables_update"]
    assert obj["ur.software_version"] == "5.9" and obj["ur.version_assumed"] == "1"
    experts = obj["_ws.expert"] if isinstance(obj["_ws.expert"], list) else [obj["_ws.expert"]]
    assert any("assuming software 5.9" in e["_ws.expert.message"] for e in experts)
    assert to_records(u)[0]["error"].startswith("variables[0] at offset 17: needs 24 bytes")   # POSE in 5.9
    (u,) = ur_items_by_stream(tshark_json(pcap, "-o", "ur.version:5.0"))[0]
    assert to_records(u)[0]["variables"] == [{"type": "BOOL", "value": True}]


def test_version_message_wins_over_the_preference(tmp_path):
    version = bytes.fromhex("0000002d140000000000000000fe0309555243" "6f6e74726f6c05000000000200000064"
                            "30312d30312d32303138")
    pcap = write_sessions(tmp_path / "v.pcap", [[version, update_5_0_bool()]])
    items = ur_items_by_stream(tshark_json(pcap, "-o", "ur.version:5.9"))[0]
    rec = to_records(items[1])[0]
    assert rec["variables"] == [{"type": "BOOL", "value": True}]
    assert "ur.version_assumed" not in items[1]["ur.global_variables_update"]


def test_a_version_bugfix_out_of_range_is_flagged_and_the_stream_read_as_major_minor(tmp_path):
    """bugfix -1: a warning on its bytes, and 5.0 for the messages after it, as in Python and C."""
    version = bytes.fromhex("0000002d140000000000000000fe0309555243" "6f6e74726f6c0500ffffffff00000064"
                            "30312d30312d32303138")
    pcap = write_sessions(tmp_path / "v.pcap", [[version, update_5_0_bool()]])
    items = ur_items_by_stream(tshark_json(pcap))[0]
    text = "bugfix version -1 is out of range (0 to 999); the stream is read as 5.0"
    (warning,) = _experts(items[0]["ur.version"][text])   # an item of its own, on the bugfix bytes
    assert warning["_ws.expert.message"] == text and "ur.version_out_of_range" in warning
    assert warning["_ws.expert.severity"] == str(0x00600000)   # PI_WARN
    assert to_records(items[0])[0]["bugfix_version"] == -1
    update = items[1]["ur.global_variables_update"]
    assert update["ur.software_version"] == "5.0" and "ur.version_assumed" not in update
    assert to_records(items[1])[0]["variables"] == [{"type": "BOOL", "value": True}]
    fields = run_tshark(pcap, "-Y", "ur.version_out_of_range", "-T", "fields", "-e", "ur.version.bugfix_version")
    assert fields.split() == ["-1"]


def test_a_robot_state_that_cannot_be_framed_teaches_the_stream_no_version(tmp_path):
    """Its CB2-sized robot mode data is read as CB2, but a package longer than the message makes
    the robot state malformed: the next message is read in the version the stream had, as the
    Python and C decoders read it. A robot state framed whole does teach its version."""
    cb2_mode = struct.pack(">iB", 29, 0) + bytes(24)      # robot_mode_data: 29 bytes only on CB2
    too_long = struct.pack(">iB", 1000, 1) + bytes(3)     # joint_data past the end of the message
    for packages, error in ((cb2_mode + too_long, "needs 24 bytes, 2 left"),   # POSE in 5.9
                            (cb2_mode, "needs 4 bytes, 2 left")):              # NUM up to 3.2
        state = struct.pack(">iB", 5 + len(packages), 16) + packages
        pcap = write_sessions(tmp_path / f"cb2_{len(packages)}.pcap", [[state, update_5_0_bool()]])
        items = ur_items_by_stream(tshark_json(pcap))[0]
        python = [urwire.to_dict(r) for r in urwire.decode_stream(state + update_5_0_bool())]
        assert to_records(items[1])[0]["error"] == python[1]["error"] == "variables[0] at offset 17: " + error


def test_one_pass_and_two_passes_give_the_same_records(tmp_path):
    junk = bytes(range(1, 40))
    msgs = [junk, text_message(b"a" * 50), b"\x00\x00\x00\x03\x10", text_message(b"b"), update_5_0_bool()]
    data = b"".join(msgs)
    pcap = write_sessions(tmp_path / "mixed.pcap", [capture.random_cuts([data], seed=s, max_len=9) for s in range(5)]
                          + [capture.bytewise([data])], handshake=False)
    for path in (pcap, SAMPLE):
        one = parse_json(run_tshark(path, "-T", "json"))
        two = parse_json(run_tshark(path, "-2", "-T", "json"))
        records = lambda frames: {s: [r for u in items for r in to_records(u)]  # noqa: E731
                                  for s, items in ur_items_by_stream(frames).items()}
        assert records(one) == records(two)
        # Values, errors and experts agree; with one pass only, TCP may hand the bytes carried
        # while resynchronising over twice, which shows as one more "skipped bytes" item.


def test_info_column_summarises():
    info = run_tshark(SAMPLE, "-T", "fields", "-e", "_ws.col.Info")
    for expected in ("Version: URControl 5.11.8.110254", "Robot state: IDLE, NORMAL", "Robot state: RUNNING, NORMAL",
                     "Robot state: RUNNING, PROTECTIVE_STOP", "Key: PROGRAM_XXX_STARTED: urwire_demo",
                     "Popup: Operator: Check the gripper", "Safety mode: PROTECTIVE_STOP",
                     "Runtime exception: line 3:1: compile_error_name_not_found:txtms", "Text: cycle done",
                     "URScript: def urwire_demo():", "Global variables update"):
        assert expected in info, expected


def test_bad_lengths_are_experts_and_resynchronise(tmp_path):
    data = b"\x00\x00\x00\x02\x14" + b"\xee" * 7 + text_message(b"after") + b"\x7f\xff\xff\xff\x10" + text_message(b"end")
    pcap = write_sessions(tmp_path / "bad.pcap", [capture.random_cuts([data], seed=2, max_len=6)])
    experts = run_tshark(pcap, "-q", "-z", "expert,error")
    assert "length 2 is below 5" in experts and "length 2147483647 is above 1048576" in experts
    texts = run_tshark(pcap, "-2", "-T", "fields", "-e", "ur.text.text")
    assert texts.split() == ["after", "end"]


def test_install_and_uninstall(tmp_path):
    env = dict(os.environ, HOME=str(tmp_path))
    make = shutil.which("make")
    subprocess.run([make, "-C", str(ROOT), "install-dissector", "NATIVE=no"], env=env, check=True, capture_output=True)
    installed = tmp_path / ".local" / "lib" / "wireshark" / "plugins" / "urwire.lua"
    assert installed.read_text() == PLUGIN.read_text()
    prefs = subprocess.run(["tshark", "-G", "currentprefs"], env=env, capture_output=True, text=True).stdout
    assert "ur.ports" in prefs and "ur.version" in prefs
    plugins = subprocess.run(["tshark", "-G", "plugins"], env=env, capture_output=True, text=True).stdout
    assert "urwire.lua" in plugins
    subprocess.run([make, "-C", str(ROOT), "uninstall-dissector"], env=env, check=True, capture_output=True)
    assert not installed.exists()


def test_info_of_a_frame_called_twice_joins_both_calls(tmp_path):
    """A message completed by reassembly, then whole ones from the rest of the segment."""
    a, b, c = text_message(b"first"), text_message(b"second"), text_message(b"third")
    pcap = capture.write(tmp_path / "info.pcap", capture.robot_session([a[:10], a[10:] + b + c[:3], c[3:]]))
    for opts in ((), ("-2",)):
        lines = run_tshark(pcap, *opts, "-Y", "ur", "-T", "fields", "-e", "_ws.col.Info").splitlines()
        assert lines == ["Text: first; Text: second", "Text: third"]


def test_tshark_fields_builds_the_named_packages_as_the_full_tree_does():
    """tshark -T fields builds only the robot-state packages its command line names
    (runtime/lua/packages/wanted.lua): their values are those of the whole tree (ur.named_fields_only off),
    and a filter on another package selects the same frames."""
    full = ("-o", "ur.named_fields_only:FALSE")
    for args in (("-e", "ur.joint_data.q_actual", "-e", "ur.masterboard_data.robot_voltage_48v"),
                 ("-Y", 'ur.robot_mode_data.robot_mode == "RUNNING"', "-e", "frame.number", "-e", "ur.tool_data.tool_mode"),
                 ("-e", "ur.type", "-e", "ur.key.title")):
        named = run_tshark(SAMPLE, "-T", "fields", *args)
        assert named.strip() and named == run_tshark(SAMPLE, *full, "-T", "fields", *args), args
    assert any(v.strip(",") for v in run_tshark(SAMPLE, "-T", "fields", "-e", "ur.joint_data.q_actual").split())
