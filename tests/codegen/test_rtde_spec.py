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
