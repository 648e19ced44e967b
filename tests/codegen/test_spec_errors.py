"""A broken spec fails with the YAML path (and line) of what is wrong, and every problem at once."""
from __future__ import annotations

import copy

import pytest
import yaml

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.errors import SpecError

SPEC_TEXT = DEFAULT_SPEC.read_text(encoding="utf-8")
SPEC_DATA = yaml.safe_load(SPEC_TEXT)   # read once: each test edits a copy


def spec_with(edit) -> str:
    data = copy.deepcopy(SPEC_DATA)
    edit(data)
    return yaml.safe_dump(data, sort_keys=False)


def problems_of(text: str) -> list[str]:
    with pytest.raises(SpecError) as info:
        compile_text(text, "bad.yaml")
    return [str(p) for p in info.value.problems]


def robot_mode_fields(d):
    return d["messages"]["robot_state"]["packages"]["robot_mode_data"]["fields"]


def test_the_real_spec_compiles():
    protocol = compile_text(SPEC_TEXT)
    # Robot state, robot message, program state and the four body messages (types 5, 22, 23, 24).
    assert len(protocol.messages) == 7


def test_yaml_syntax_error_names_the_line():
    (problem,) = problems_of("spec_format: 1\nprotocol: [unclosed\n")
    assert "line" in problem


@pytest.mark.parametrize("edit, path, words", [
    (lambda d: robot_mode_fields(d)[8].update(type="int9"),
     "messages.robot_state.packages.robot_mode_data.fields[8].type", "is not one of"),
    (lambda d: d["protocol"].pop("default_version"), "protocol", "'default_version' is a required property"),
    (lambda d: d["enums"]["control_mode"]["values"][0].update(name="no controller"),
     "enums.control_mode.values[0].name", "does not match"),
    (lambda d: d["protocol"].update(documented_versions=["5"]), "protocol.documented_versions[0]", "does not match"),
    (lambda d: robot_mode_fields(d)[0].update(colour="red"),
     "messages.robot_state.packages.robot_mode_data.fields[0]", "Additional properties"),
    (lambda d: robot_mode_fields(d)[1].pop("label"),
     "messages.robot_state.packages.robot_mode_data.fields[1]", "'label' is a required property"),
    (lambda d: robot_mode_fields(d)[1].update(label="is_real_robot_connected"),
     "messages.robot_state.packages.robot_mode_data.fields[1].label", "does not match"),
    (lambda d: robot_mode_fields(d)[10].update(unit="furlong"),
     "messages.robot_state.packages.robot_mode_data.fields[10].unit", "is not one of"),
    (lambda d: d["framing"]["message_header"]["length"].pop("label"),
     "framing.message_header.length", "'label' is a required property"),
])
def test_schema_errors_name_the_yaml_path(edit, path, words):
    problems = problems_of(spec_with(edit))
    assert any(p.startswith(path) and words in p for p in problems), problems


@pytest.mark.parametrize("edit, path, words", [
    (lambda d: robot_mode_fields(d)[8].update(enum="robot_moods"),
     "messages.robot_state.packages.robot_mode_data.fields[8].enum", "unknown enum 'robot_moods'"),
    (lambda d: d["messages"]["robot_state"]["packages"]["joint_data"].update(code="JOINT_DATUM"),
     "messages.robot_state.packages.joint_data.code", "not a member of enum 'package_type'"),
    (lambda d: robot_mode_fields(d)[1].update(name="timestamp"),
     "messages.robot_state.packages.robot_mode_data.fields[1].name", "duplicate field name"),
    (lambda d: d["enums"]["control_mode"]["values"].append({"name": "TOO_BIG", "value": 300}),
     "enums.control_mode.values[4].value", "does not fit in uint8"),
    (lambda d: d["enums"]["control_mode"]["values"].append({"name": "POSITION", "value": 9}),
     "enums.control_mode.values[4].name", "duplicate enum member"),
    (lambda d: d["enums"]["value_type"]["tables"][1]["versions"].update({"from": "3.0"}),
     "enums.value_type.tables[1].versions", "overlaps"),
    (lambda d: d["enums"]["control_mode"]["values"][0].update(versions={"from": "5.1", "until": "4.0"}),
     "enums.control_mode.values[0].versions", "starts after it ends"),
    (lambda d: d["messages"]["robot_message"]["subtypes"]["text"]["fields"].append({"name": "more", "label": "More", "type": "int32"}),
     "messages.robot_message.subtypes.text.fields[1]", "runs to the end"),
    (lambda d: d["messages"]["robot_state"]["packages"]["masterboard_data"]["fields"][17].update(present_if="nothing"),
     "messages.robot_state.packages.masterboard_data.fields[17].present_if", "must name an earlier"),
    (lambda d: d["messages"]["robot_message"]["subtypes"]["safety_mode"]["fields"][4].update(switch="later"),
     "messages.robot_message.subtypes.safety_mode.fields[4].switch", "must name an earlier integer field"),
    (lambda d: d["value_layouts"].pop("MATRIX"), "enums.value_type", "MATRIX has no entry in value_layouts"),
    (lambda d: d["messages"]["robot_message"]["subtypes"]["key"].update(summary="{title}: {colour}"),
     "messages.robot_message.subtypes.key.summary", "'colour' is not a scalar or string field"),
    (lambda d: d["messages"]["robot_message"]["subtypes"]["key"].update(summary="{title}!"),
     "messages.robot_message.subtypes.key.summary", "end with a field"),
    (lambda d: robot_mode_fields(d)[8].update(enum="joint_mode"),
     "messages.robot_state.packages.robot_mode_data.fields[8].enum", "do not fit the field's int8"),
    (lambda d: robot_mode_fields(d)[1].update(unit="V"),
     "messages.robot_state.packages.robot_mode_data.fields[1].unit", "a unit needs a number"),
    (lambda d: robot_mode_fields(d)[8].update(unit="rad"),
     "messages.robot_state.packages.robot_mode_data.fields[8].unit", "a unit needs a number"),
    (lambda d: d["messages"]["robot_state"]["packages"]["masterboard_data"]["fields"][1].update(label="Inputs"),
     "messages.robot_state.packages.masterboard_data.fields[1].label", "another label or unit"),
])
def test_semantic_errors_name_the_yaml_path(edit, path, words):
    problems = problems_of(spec_with(edit))
    assert any(p.startswith(path) and words in p for p in problems), problems


def repeated_probe(older: str, newer: str):
    """An edit: robot mode data gains a field `probe`, of type `older` up to 3.4 and `newer` after."""
    def edit(d):
        robot_mode_fields(d).extend([
            {"name": "probe", "label": "Probe", "type": older, "versions": {"until": "3.4"}},
            {"name": "probe", "label": "Probe", "type": newer, "versions": {"from": "3.5", "through": "PolyScope X"}},
        ])
    return edit


def test_a_repeated_name_may_not_change_its_signedness():
    """uint16 then int32: int32 holds every uint16, but one C member cannot be both; the one rule
    (resolve.same_name) rejects it before any target sees it, at the newer entry's type."""
    problems = problems_of(spec_with(repeated_probe("uint16", "int32")))
    assert any(p.startswith("messages.robot_state.packages.robot_mode_data.fields[15].type")
               and "uint16 and int32" in p for p in problems), problems


def test_a_repeated_name_may_widen_and_every_target_renders_it():
    from codegen.kinds.packages import KIND

    protocol = compile_text(spec_with(repeated_probe("uint16", "uint32")))
    outputs = KIND.render(protocol, ["probe.yaml"])
    # One C member of the widest type, the narrower entry read into it.
    assert "    uint32_t probe;" in outputs["c/urwire.h"]
    assert "out->probe = (uint32_t)urwire__u16(p + 41);" in outputs["c/urwire.c"]
    # One Wireshark field of the widest type; the narrower read adds its value explicitly.
    lua = outputs["lua/urwire.lua"]
    assert '["robot_mode_data.probe"] = ProtoField.uint32("ur.robot_mode_data.probe"' in lua
    assert '{ k = "scalar", f = F["robot_mode_data.probe"], n = 2, path = "probe", signed = false, value = true }' in lua
    # One record attribute.
    assert outputs["python/urwire/generated/messages.py"].count("    probe: Optional[int] = field(") == 1


def test_every_problem_is_reported_at_once():
    def two_mistakes(d):
        robot_mode_fields(d)[8].update(enum="robot_moods")
        d["messages"]["robot_state"]["packages"]["joint_data"].update(code="JOINT_DATUM")
    assert len(problems_of(spec_with(two_mistakes))) == 2


def test_problems_carry_the_line_of_the_node():
    text = spec_with(lambda d: robot_mode_fields(d)[8].update(enum="robot_moods"))
    with pytest.raises(SpecError) as info:
        compile_text(text, "bad.yaml")
    (problem,) = info.value.problems
    line = text.splitlines()[problem.line - 1]
    assert "robot_moods" in line
