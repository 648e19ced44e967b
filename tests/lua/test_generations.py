"""The dissector across controller generations, in real tshark, on a variant of the spec that
uses what older generations need (docs/contract.md#choosing-a-layout):

- a field gated by version (additional_info.gated_flag from 5.12; singularity_info.late_flag
  from 5.25.1, a bugfix release);
- a type code with two layouts in disjoint version ranges (package 5: a 29-byte early_info up
  to 1.8, kinematics_info from 3.0), with an enum member of its own for each;
- a name repeated with two wire types (masterboard_data.digital_input_bits: int16 up to 1.8,
  int32 from 3.0): one Wireshark field;
- an enum whose codes change meaning (joint_mode 240: EMERGENCY_STOPPED up to 5.0);
- a Version message with a bugfix number from 3.3 on, where 3.2 and older have an svn revision.

Each test builds the bytes of a stream, runs tshark with the variant's generated plugin, and
reads the tree.
"""
from __future__ import annotations

from pathlib import Path

import struct
import subprocess
import xml.etree.ElementTree as ET

import pytest
import yaml

from codegen.compile import compile_text

# The generator's features on a small frozen spec, not on whatever the real spec holds today.
BASE_SPEC = Path(__file__).resolve().parents[1] / "fixtures" / "ur_primary_5_9_only.yaml"
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import lua as lua_target
from tests.lua.harness import parse_json, run_tshark, ur_items_by_stream, write_sessions


def edit(data: dict) -> None:
    enums, state = data["enums"], data["messages"]["robot_state"]["packages"]
    for v in enums["package_type"]["values"]:
        if v["name"] == "KINEMATICS_INFO":
            v["versions"] = {"from": "3.0"}
    enums["package_type"]["values"].append({"name": "EARLY_INFO", "value": 5, "versions": {"until": "1.8"}})
    for v in enums["joint_mode"]["values"]:
        if v["name"] == "READY_FOR_POWER_OFF":
            v["versions"] = {"from": "5.1"}
    enums["joint_mode"]["values"].append({"name": "EMERGENCY_STOPPED", "value": 240, "versions": {"until": "5.0"}})

    state["additional_info"]["fields"].append({"name": "gated_flag", "label": "Gated flag", "type": "uint16", "versions": {"from": "5.12"}})
    state["singularity_info"]["fields"].append({"name": "late_flag", "label": "Late flag", "type": "uint8", "versions": {"from": "5.25.1"}})
    state["kinematics_info"]["versions"] = {"from": "3.0"}
    state["early_info"] = {
        "code": "EARLY_INFO", "doc": "A package type 5 of early controllers (a test layout).",
        "versions": {"until": "1.8"},
        "fields": [{"name": "a", "label": "A", "type": "float64"}, {"name": "b", "label": "B", "type": "float64"}, {"name": "c", "label": "C", "type": "float64"},
                   {"name": "d", "label": "D", "type": "uint32"}, {"name": "e", "label": "E", "type": "uint8"}],
    }
    mb = state["masterboard_data"]["fields"]
    bits = mb[0]
    assert bits["name"] == "digital_input_bits"
    # Both entries name the same bits (16, which an int16 holds).
    mb[0] = dict(bits, bits=bits["bits"][:16], versions={"from": "3.0"})
    mb.insert(0, dict(mb[0], type="int16", versions={"until": "1.8"}))

    version = data["messages"]["robot_message"]["subtypes"]["version"]
    version["sets_version"]["bugfix"] = "bugfix_version"
    fields = version["fields"]
    at = next(i for i, f in enumerate(fields) if f["name"] == "bugfix_version")
    fields[at] = dict(fields[at], versions={"from": "3.3"})
    fields.insert(at, {"name": "svn_revision", "label": "Svn revision", "type": "int32", "versions": {"until": "3.2"}})


@pytest.fixture(scope="module")
def variant(tmp_path_factory):
    """The variant's protocol, its plan and its generated plugin."""
    data = yaml.safe_load(BASE_SPEC.read_text(encoding="utf-8"))
    edit(data)
    protocol = compile_text(yaml.safe_dump(data, sort_keys=False))
    protocol_plan = plan(protocol)
    path = tmp_path_factory.mktemp("variant") / "urwire.lua"
    path.write_text(lua_target.render(protocol_plan, ["test build"])[lua_target.OUT])
    return protocol, protocol_plan, path


# ---- bytes ----

def package(code: int, body: bytes) -> bytes:
    return struct.pack(">iB", 5 + len(body), code) + body


def robot_state(*packages: bytes) -> bytes:
    body = b"".join(packages)
    return struct.pack(">iB", 5 + len(body), 16) + body


def version_message(major: int, minor: int, after_minor: int, build: int = 100) -> bytes:
    """A Version message; `after_minor` is the bugfix number (or, up to 3.2, the svn revision)."""
    body = struct.pack(">QbB", 0, -2, 3) + struct.pack(">b", 9) + b"URControl" \
        + struct.pack(">BBii", major, minor, after_minor, build) + b"01-01-2024"
    return struct.pack(">iB", 5 + len(body), 20) + body


def additional_info(gated: bool) -> bytes:
    return package(8, bytes([1, 0, 1, 0]) + (struct.pack(">H", 0xBEEF) if gated else b""))


def singularity_info(late: bool) -> bytes:
    return package(13, bytes([2, 3]) + (b"\x09" if late else b""))


def early_info() -> bytes:
    return package(5, struct.pack(">dddIB", 1.5, 2.5, 3.5, 7, 9))


def joint_data(mode: int) -> bytes:
    joint = struct.pack(">dddffffB", 0.5, 0.5, 0.0, 0.1, 48.0, 30.0, 0.0, mode)
    return package(1, joint * 6)


def masterboard(offset_of_safety_mode: int, inputs: bytes, safety_mode: int = 1) -> bytes:
    """A masterboard package without euromap: `inputs` (2 or 4 bytes), the rest zero but for
    safety_mode."""
    body = bytearray(inputs + bytes(66))
    body[offset_of_safety_mode] = safety_mode
    return package(3, bytes(body))


def safety_mode_offset(protocol_plan, inputs_size: int) -> int:
    """Where safety_mode sits in the masterboard form whose digital inputs take `inputs_size`
    bytes: after the same fixed fields in both forms."""
    (form,) = [v for v in protocol_plan.message("robot_state").variants[3] if v.sizes and 68 + inputs_size - 2 in v.sizes]
    at = 0
    for f in form.layout.struct.fields:
        if f.name == "safety_mode":
            return at
        if f.name != "digital_input_bits" or f.scalar.size == inputs_size:
            at += f.fixed_size
    raise AssertionError("no safety_mode")


# ---- tshark ----

def frames(plugin, pcap, *opts: str) -> dict:
    return ur_items_by_stream(parse_json(run_tshark(pcap, "-2", "-T", "json", "--no-duplicate-keys", *opts,
                                                    plugin=plugin)))


def experts(obj: dict) -> list[str]:
    found = obj.get("_ws.expert", [])
    return [e["_ws.expert.message"] for e in (found if isinstance(found, list) else [found])]


def field_list(plugin) -> list[list[str]]:
    """tshark -G fields with the plugin: one row per registered field."""
    out = subprocess.run(["tshark", "-G", "fields", "-X", f"lua_script:{plugin}"], capture_output=True, text=True,
                         check=True, timeout=120).stdout
    return [row.split("\t") for row in out.splitlines() if row.startswith("F\t")]


def shown(plugin, pcap, *opts: str) -> list[str]:
    """Every tree item's text (PDML showname), in order."""
    root = ET.fromstring(run_tshark(pcap, "-2", "-T", "pdml", *opts, plugin=plugin))
    return [f.get("showname") or "" for f in root.iter("field")]


# ---- tests ----

def test_the_versions_form_and_the_form_chosen_by_length(variant, tmp_path):
    """Announced 5.12: the 6-byte additional_info is its form. Announced 5.9: the 4-byte one
    is; a 6-byte one fits only 5.12's, which is used with a note."""
    _, _, plugin = variant
    pcap = write_sessions(tmp_path / "forms.pcap", [
        [version_message(5, 12, 0), robot_state(additional_info(True))],
        [version_message(5, 9, 0), robot_state(additional_info(False)), robot_state(additional_info(True))],
    ])
    streams = frames(plugin, pcap)
    new = streams[0][1]
    assert new["ur.software_version"] == "5.12"
    info = new["ur.additional_info"]
    assert info["ur.additional_info.gated_flag"] == str(0xBEEF) and not experts(info)
    old, by_length = streams[1][1], streams[1][2]
    assert "ur.additional_info.gated_flag" not in old["ur.additional_info"]
    assert not experts(old["ur.additional_info"])
    info = by_length["ur.additional_info"]
    assert info["ur.additional_info.gated_flag"] == str(0xBEEF)
    assert experts(info) == ["laid out as software 5.12 and later (chosen by length 11)"]
    assert by_length["ur.software_version"] == "5.9", "a form chosen by length does not change an announced version"


def test_layout_sizes_tell_the_version_of_a_stream_that_did_not(variant, tmp_path):
    """No Version message, no preference: a 29-byte package 5 is only the early layout (up to
    1.8), so the stream is taken as 1.8 from there on: the masterboard's two-byte inputs, the
    early joint-mode names, in this message and the next; the same with one pass and two."""
    _, protocol_plan, plugin = variant
    mb_18 = masterboard(safety_mode_offset(protocol_plan, 2), struct.pack(">H", 0x0102))
    first = robot_state(early_info(), joint_data(240), mb_18)
    second = robot_state(joint_data(240))
    pcap = write_sessions(tmp_path / "implied.pcap", [[first, second]])
    for opts in ((), ("-2",)):
        items = ur_items_by_stream(parse_json(run_tshark(pcap, *opts, "-T", "json", "--no-duplicate-keys",
                                                         plugin=plugin)))[0]
        one, two = items
        assert one["ur.software_version"] == "up to 1.8 (from layout sizes)"
        assert one["ur.version_assumed"] == "1"
        assert experts(one) == ["no Version message seen on this stream: software up to 1.8, as the layout sizes show"]
        early = one["ur.early_info"]
        assert experts(early) == ["laid out as software up to 1.8 (chosen by length 34)"]
        assert early["ur.early_info.d"] == "7" and early["ur.package.type"] == "5"
        mb = one["ur.masterboard_data"]
        assert mb["ur.masterboard_data.digital_input_bits"] == str(0x0102) and not experts(mb)
        assert mb["ur.masterboard_data.safety_mode"] == "1"
        assert two["ur.software_version"] == "up to 1.8 (from layout sizes)", "later messages keep it"
    info = run_tshark(pcap, "-2", "-Y", "ur", "-T", "fields", "-e", "_ws.col.Info", plugin=plugin).split("\n")
    assert info[:2] == ["Robot state: NORMAL", "Robot state"], "the summary of the masterboard's 1.8 form"
    texts = shown(plugin, pcap)
    assert "Joint mode: EMERGENCY_STOPPED (240)" in texts
    assert "Software version: up to 1.8 (from layout sizes)" in texts   # generated: [..] in the text view
    assert "Type: EARLY_INFO (5)" in texts


def test_the_version_message_bugfix_and_svn_revision(variant, tmp_path):
    """5.25.1 announces its bugfix number: singularity_info's late flag (from 5.25.1) is its
    form. A 3.2 Version message carries an svn revision at that place, not a bugfix."""
    _, _, plugin = variant
    pcap = write_sessions(tmp_path / "bugfix.pcap", [
        [version_message(5, 25, 1), robot_state(singularity_info(True))],
        [version_message(5, 25, 0), robot_state(singularity_info(True))],
        [version_message(3, 2, 12345), robot_state(additional_info(False))],
    ])
    streams = frames(plugin, pcap)
    version, state = streams[0]
    assert version["ur.version"]["ur.version.bugfix_version"] == "1"
    assert state["ur.software_version"] == "5.25.1"
    assert state["ur.singularity_info"]["ur.singularity_info.late_flag"] == "9"
    assert not experts(state["ur.singularity_info"])
    assert streams[1][1]["ur.software_version"] == "5.25"
    assert experts(streams[1][1]["ur.singularity_info"]) == ["laid out as software 5.25.1 and later (chosen by length 8)"]
    version, state = streams[2]
    assert version["ur.version"]["ur.version.svn_revision"] == "12345"
    assert "ur.version.bugfix_version" not in version["ur.version"]
    assert state["ur.software_version"] == "3.2"
    info = run_tshark(pcap, "-2", "-T", "fields", "-e", "_ws.col.Info", plugin=plugin)
    assert "Version: URControl 5.25.1.100" in info
    assert "Version: URControl 3.2.100" in info


def test_the_preference_takes_a_bugfix_release(variant, tmp_path):
    _, _, plugin = variant
    pcap = write_sessions(tmp_path / "pref.pcap", [[robot_state(singularity_info(True), additional_info(True))]])
    (state,) = frames(plugin, pcap, "-o", "ur.version:5.25.1")[0]
    assert state["ur.software_version"] == "5.25.1" and state["ur.version_assumed"] == "1"
    assert experts(state) == ["no Version message seen on this stream: assuming software 5.25.1 (preference ur.version)"]
    for name in ("singularity_info", "additional_info"):
        assert not experts(state[f"ur.{name}"]), name
    (state,) = frames(plugin, pcap, "-o", "ur.version:5.25")[0]
    assert state["ur.software_version"] == "5.25"
    assert experts(state["ur.singularity_info"]) == ["laid out as software 5.25.1 and later (chosen by length 8)"]
    assert not experts(state["ur.additional_info"])
    # No preference: the three-byte singularity_info tells the version.
    (state,) = frames(plugin, pcap)[0]
    assert state["ur.software_version"] == "5.25.1 and later (from layout sizes)"
    assert not experts(state["ur.additional_info"])
    pcap = write_sessions(tmp_path / "default.pcap", [[robot_state(additional_info(False))]])
    (state,) = frames(plugin, pcap)[0]
    assert state["ur.software_version"] == "5.9", "nothing the sizes tell: the default"
    assert experts(state) == ["no Version message seen on this stream: assuming software 5.9 (the default; "
                              "preference ur.version)"]


def test_enum_names_follow_the_version(variant, tmp_path):
    """joint_mode 240 is EMERGENCY_STOPPED up to 5.0 and READY_FOR_POWER_OFF from 5.1; the field
    keeps the newest names, so filters by name follow today's firmware."""
    _, _, plugin = variant
    pcap = write_sessions(tmp_path / "names.pcap", [
        [version_message(5, 0, 3), robot_state(joint_data(240))],
        [version_message(5, 9, 0), robot_state(joint_data(240))],
    ])
    texts = shown(plugin, pcap)
    assert texts.count("Joint mode: EMERGENCY_STOPPED (240)") == 6
    assert texts.count("Joint mode: READY_FOR_POWER_OFF (240)") == 6
    hits = run_tshark(pcap, "-Y", 'ur.joint_data.joint_mode == "READY_FOR_POWER_OFF"', "-T", "fields",
                      "-e", "tcp.stream", plugin=plugin).split()
    assert hits == ["0", "1"], "the filter matches the code, whatever a version calls it"


def test_a_repeated_name_is_one_field_of_the_widest_type(variant, tmp_path):
    """digital_input_bits is int16 up to 1.8 and int32 from 3.0: one ur.masterboard_data field
    (FT_INT32); the two-byte form shows its value and its bits."""
    _, protocol_plan, plugin = variant
    rows = [r for r in field_list(plugin) if r[2] == "ur.masterboard_data.digital_input_bits"]
    assert len(rows) == 1 and rows[0][3] == "FT_INT32", rows
    old = masterboard(safety_mode_offset(protocol_plan, 2), struct.pack(">h", -32767))
    new = masterboard(safety_mode_offset(protocol_plan, 4), struct.pack(">i", 0x10002))
    pcap = write_sessions(tmp_path / "bits.pcap", [[version_message(1, 8, 0), robot_state(old)],
                                                   [version_message(3, 3, 0), robot_state(new)]])
    values = run_tshark(pcap, "-2", "-Y", "ur.masterboard_data", "-T", "fields", "-e",
                        "ur.masterboard_data.digital_input_bits", "-e", "ur.masterboard_data.digital_input_bits.standard_0",
                        "-e", "ur.masterboard_data.safety_mode", plugin=plugin).split("\n")
    assert values[:2] == ["-32767\t1\t1", "65538\t0\t1"]
    assert run_tshark(pcap, "-Y", "ur.masterboard_data.digital_input_bits < 0", "-T", "fields", "-e", "tcp.stream",
                      plugin=plugin).split() == ["0"]


def test_a_code_with_two_layouts(variant, tmp_path):
    """Package 5 is early_info up to 1.8 and kinematics_info from 3.0: each stream reads its own,
    each layout's fields registered once."""
    _, protocol_plan, plugin = variant
    forms = protocol_plan.message("robot_state").variants[5]
    assert sorted(v.layout.name for v in forms) == ["early_info", "kinematics_info"]
    kinematics = next(v for v in forms if v.layout.name == "kinematics_info")
    body = bytes(sorted(kinematics.sizes)[0])
    pcap = write_sessions(tmp_path / "two.pcap", [
        [version_message(1, 8, 0), robot_state(early_info())],
        [version_message(5, 9, 0), robot_state(package(5, body))],
    ])
    streams = frames(plugin, pcap)
    early, later = streams[0][1], streams[1][1]
    assert "ur.early_info" in early and not experts(early["ur.early_info"])
    assert early["ur.early_info"]["ur.early_info.a"] == "1.5"
    assert "ur.kinematics_info" in later and not experts(later["ur.kinematics_info"])
    texts = shown(plugin, pcap)
    assert "Type: EARLY_INFO (5)" in texts and "Type: KINEMATICS_INFO (5)" in texts
    abbrs = [r[2] for r in field_list(plugin)]
    assert abbrs.count("ur.early_info.a") == 1 and abbrs.count("ur.kinematics_info.checksum") == 1
