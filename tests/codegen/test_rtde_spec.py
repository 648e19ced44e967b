"""spec/rtde.yaml and the typed-messages kind: the spec resolves to one layout per type code,
direction and protocol version, its recipes name real setup messages, the variable table is whole;
and a broken spec is reported at its YAML path and line."""
from __future__ import annotations

import pytest
import yaml

from codegen.compile import SPEC_DIR, compile_text
from codegen.errors import SpecError
from codegen.kinds.typed_messages import model

SPEC = SPEC_DIR / "rtde.yaml"
TEXT = SPEC.read_text(encoding="utf-8")


def interface() -> model.Interface:
    return compile_text(TEXT, str(SPEC))


def problems_of(edit) -> list:
    data = yaml.safe_load(TEXT)
    edit(data)
    with pytest.raises(SpecError) as caught:
        compile_text(yaml.safe_dump(data, sort_keys=False, allow_unicode=True), "bad.yaml")
    return caught.value.problems


def test_every_code_direction_and_protocol_has_one_layout():
    rtde = interface()
    seen = {}
    for m in rtde.messages:
        for p in m.protocols:
            key = (m.letter, m.from_robot, p)
            assert key not in seen, (m.name, seen.get(key))
            seen[key] = m.name
    # Every documented code in both directions and both protocols (the guide's eight types).
    for letter in "VvMOISPU":
        for from_robot in (False, True):
            for p in (1, 2):
                assert (letter, from_robot, p) in seen, (letter, from_robot, p)


def test_protocol_1_and_2_differ_where_the_guide_says():
    rtde = interface()
    by = {(m.letter, m.from_robot, p): m for m in rtde.messages for p in m.protocols}
    assert [f.name for f in by["O", False, 2].fields] == ["output_frequency", "variables"]
    assert [f.name for f in by["O", False, 1].fields] == ["variables"]
    assert [f.name for f in by["O", True, 2].fields] == ["recipe_id", "types"]
    assert [f.name for f in by["O", True, 1].fields] == ["types"]
    assert [f.name for f in by["U", True, 2].fields] == ["recipe_id", "values"]
    assert [f.name for f in by["U", True, 1].fields] == ["values"]
    assert [f.name for f in by["M", True, 1].fields] == ["level", "message"]
    assert [f.name for f in by["M", True, 2].fields] == ["message", "source", "level"]


def test_recipes_are_made_by_setup_exchanges_of_each_direction():
    rtde = interface()
    outputs = rtde.recipe_kind_of_data(from_robot=True)
    inputs = rtde.recipe_kind_of_data(from_robot=False)
    assert outputs.name == "outputs" and {m.name for m in outputs.requests} == {"setup_outputs", "setup_outputs_v1"}
    assert inputs.name == "inputs" and [m.name for m in inputs.replies] == ["setup_inputs_reply"]
    assert [r.word for r in rtde.refusals] == ["NOT_FOUND", "IN_USE"]


def test_the_variable_table():
    rtde = interface()
    by = {(v.name, v.direction): v for v in rtde.variables}
    q = by["actual_q", "output"]
    assert (q.value_type.name, q.unit, q.label) == ("VECTOR6D", "rad", "Actual joint positions")
    assert q.since_text("cb3") == "3.3" and q.since_text("eseries") == "5.0"
    assert by["speed_slider_fraction", "input"].value_type.name == "DOUBLE"
    # Registers expand to one variable each, with the upper ranges from 3.9 / 5.3.
    assert by["input_int_register_23", "input"].since_text("cb3") == "3.4"
    assert by["input_int_register_24", "input"].since_text("eseries") == "5.3"
    assert sum(1 for n, d in by if n.startswith("output_double_register_")) == 48
    assert by["tool_output_mode", "output"].since_text("cb3") == "none"
    # Input registers are read back as outputs too.
    assert ("input_bit_register_64", "output") in by and ("input_bit_register_64", "input") in by
    assert len(by) == len(rtde.variables)



def test_every_first_version_names_its_source():
    """A row with a `since` (a later first version, "none" or "unknown") says where that comes from in
    its field_note: the guide's column, ur_rtde's gates or the commit that added it, or what is known."""
    rows = yaml.safe_load(TEXT)["variables"]
    unsourced = [(r["name"], r["direction"]) for r in rows if "since" in r and not r.get("field_note", "").strip()]
    assert unsourced == []


# First versions as the cited sources give them, written out here by hand from those sources (the
# guide's column in URCL's 2024 copy, ur_rtde 1.6.5's gates, URCL's commit messages).
SOURCED_FIRST_VERSIONS = {
    "payload": ("3.11", "5.5.1"),
    "payload_cog": ("3.11", "5.5.1"),
    "payload_inertia": ("3.15", "5.11"),
    "tcp_offset": ("3.12", "5.5.1"),
    "ft_raw_wrench": ("none", "5.9"),
    "collision_detection_ratio": ("none", "5.15"),
    "time_scale_source": ("none", "5.17"),
    "actual_current_as_torque": ("none", "5.23"),
    "actual_robot_energy_consumed": ("none", "5.23"),
    "target_gravity": ("none", "5.26"),
    "target_base_acceleration": ("none", "5.26"),
    "control_step": ("none", "5.26"),
    "target_base_wrench": ("none", "5.26"),
    "safety_status": ("3.10", "5.4"),
    "elbow_position": ("3.5", "5.0"),
    "output_int_register_23": ("3.4", "5.0"),
    "output_int_register_24": ("3.9", "5.3"),
    "output_bit_register_64": ("3.9", "5.3"),
}
# Rows no source read settles: they stay "unknown" rather than a guess.
STILL_UNKNOWN = ["tool_digital_output_mask", "tool_digital_output", "actual_current_window",
                 "actual_TCP_acceleration", "target_TCP_acceleration", "actual_configurable_digital_input_bits",
                 "actual_configurable_digital_output_bits", "target_execution_time", "joint_position_deviation_ratio",
                 "wrench_calc_from_currents", "script_control_line", "actual_robot_braking_energy_dissipated",
                 "encoder0_raw", "encoder1_raw"]


def test_first_versions_are_the_sources_and_unknown_only_where_none_settles():
    rtde = interface()
    by_name = {v.name: v for v in rtde.variables}
    for name, (cb3, eseries) in SOURCED_FIRST_VERSIONS.items():
        v = by_name[name]
        assert (v.since_text("cb3"), v.since_text("eseries")) == (cb3, eseries), name
    for name in STILL_UNKNOWN:
        v = by_name[name]
        assert (v.since_text("cb3"), v.since_text("eseries")) == ("unknown", "unknown"), name
    unknown = {v.name for v in rtde.variables if "unknown" in (v.since_text("cb3"), v.since_text("eseries"))}
    assert unknown == set(STILL_UNKNOWN)

def test_a_duplicate_layout_is_named_at_its_path_and_line():
    def edit(d):
        d["messages"][1]["from_robot"] = False          # the V reply now clashes with the V request
    problems = problems_of(edit)
    assert any(p.path == "messages[1]" and "already 'request_protocol_version'" in p.message and p.line
               for p in problems), problems


def test_a_recipe_naming_an_unknown_message_is_reported():
    def edit(d):
        d["recipes"]["kinds"][0]["requests"].append("setup_everything")
    problems = problems_of(edit)
    assert any(p.path == "recipes.kinds[0].requests[2]" and "setup_everything" in p.message for p in problems)


def test_a_variable_of_an_unknown_type_and_a_bad_pattern_are_reported_together():
    def edit(d):
        d["variables"][0]["type"] = "VECTOR9D"
        d["variables"][1]["name"] = "speed_{n}"
    problems = problems_of(edit)
    assert {p.path for p in problems} >= {"variables[0].type", "variables[1]"}


def test_a_field_after_one_that_runs_to_the_end_is_refused():
    def edit(d):
        d["messages"][0]["fields"] = [{"name": "names", "type": "names", "label": "Names"},
                                      {"name": "after", "type": "uint8", "label": "After"}]
    problems = problems_of(edit)
    assert any(p.path == "messages[0].fields[1]" and "runs to the end" in p.message for p in problems)
