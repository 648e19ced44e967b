"""What the RTDE and real-time trees name alike, held to one another: spec/rtde.yaml declares the
codes UR's guide refers to "Remote Control Via TCP/IP" for, and the item names of its vectors, with
the same values as spec/ur_realtime.yaml (and spec/ur_primary.yaml's tool modes); and the rules of
codegen/items.py (a unit of two parts shared by the items, flags of named bits)."""
from __future__ import annotations

import pytest
import yaml

from codegen.compile import SPEC_DIR, compile_file, compile_text
from codegen.errors import SpecError

RTDE = compile_file(SPEC_DIR / "rtde.yaml")
REALTIME = compile_file(SPEC_DIR / "ur_realtime.yaml")
PRIMARY = compile_file(SPEC_DIR / "ur_primary.yaml")
RTDE_TEXT = (SPEC_DIR / "rtde.yaml").read_text(encoding="utf-8")


def _codes(enum, table=None) -> dict[int, str]:
    values = enum.values if table is None else table.values
    return {v.value: v.name for v in values}


def _rtde_enum(name):
    return next(e for e in RTDE.enums if e.name == name)


def _from(enum, first: str):
    return next(t for t in enum.tables if t.versions.describe().startswith(first))


def test_robot_and_safety_modes_and_program_states_are_the_real_time_codes():
    robot = REALTIME.enums["robot_mode"]
    assert _codes(_rtde_enum("robot_mode")) == _codes(robot, _from(robot, "3.0"))
    assert _codes(_rtde_enum("safety_mode")) == _codes(REALTIME.enums["safety_mode"])
    assert _codes(_rtde_enum("runtime_state")) == _codes(REALTIME.enums["program_state"])


def test_joint_modes_join_the_cb3_and_e_series_tables_without_a_clash():
    joint = REALTIME.enums["joint_mode"]
    cb3, eseries = _codes(joint, _from(joint, "3.0")), _codes(joint, _from(joint, "5.0"))
    assert all(eseries[code] == name for code, name in cb3.items() if code in eseries)
    assert _codes(_rtde_enum("joint_mode")) == {**cb3, **eseries}


def test_tool_modes_are_the_primary_codes():
    assert _codes(_rtde_enum("tool_mode")) == _codes(PRIMARY.enums["tool_mode"])


def test_the_vectors_items_are_named_as_the_real_time_names_them():
    rtde = {v.name: v for v in RTDE.variables}
    assert [i.label for i in rtde["actual_q"].items] == [i.label for i in REALTIME.items["q_actual"]] \
        == ["Base", "Shoulder", "Elbow", "Wrist 1", "Wrist 2", "Wrist 3"]
    pose = [(i.label, i.unit) for i in rtde["actual_TCP_pose"].items]
    assert pose == [(i.label, i.unit) for i in REALTIME.items["tool_vector_actual"]]
    assert pose == [("X", "m"), ("Y", "m"), ("Z", "m"), ("RX", "rad"), ("RY", "rad"), ("RZ", "rad")]
    assert [(i.label, i.unit) for i in rtde["actual_TCP_force"].items][2:4] == [("Fz", "N"), ("Tx", "Nm")]
    assert rtde["actual_TCP_pose"].unit == "m, rad"             # the metadata keeps the one unit


def test_status_bits_are_named_flags():
    rtde = {v.name: v for v in RTDE.variables}
    assert [b.label for b in rtde["robot_status_bits"].bits] == [
        "Is power on", "Is program running", "Is teach button pressed", "Is power button pressed"]
    assert rtde["safety_status_bits"].bits[10].mask == 1 << 10
    assert [b.name for b in REALTIME.bits["digital_input_bits"]][16:] == ["tool_0", "tool_1"]


def _problems(edit) -> list[str]:
    data = yaml.safe_load(RTDE_TEXT)
    edit({v["name"]: v for v in data["variables"]}, data)
    with pytest.raises(SpecError) as caught:
        compile_text(yaml.safe_dump(data, sort_keys=False, allow_unicode=True), "bad.yaml")
    return [p.message for p in caught.value.problems]


def test_a_unit_of_two_parts_needs_items_to_share_it():
    def edit(by_name, data):
        del by_name["actual_TCP_pose"]["item_names"]
    assert any("needs item_names" in m for m in _problems(edit))


def test_item_names_must_fit_the_vector():
    def edit(by_name, data):
        by_name["actual_q"]["item_names"] = "xyz"
    assert any("names 3 items, the vector has 6" in m for m in _problems(edit))


def test_bits_need_an_integer():
    def edit(by_name, data):
        by_name["timestamp"]["bits"] = ["a"]
    assert any("bits need one integer" in m for m in _problems(edit))


def test_a_name_in_both_directions_shows_one_way():
    def edit(by_name, data):
        read_back = next(v for v in data["variables"]
                         if v["name"] == "input_bit_registers0_to_31" and v["direction"] == "output")
        read_back["bits"] = ["bit_0"]
    assert any("otherwise than in its other direction" in m for m in _problems(edit))
