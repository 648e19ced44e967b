"""The Lua target renders the dissector model (dissector.py), and the template refuses what it
cannot render: an unknown descriptor kind or field shape is an error at generation time, not a broken
dissector. Constants reach the runtime through the generated `spec` table."""
from __future__ import annotations

from pathlib import Path

import copy
import dataclasses
import re
from typing import ClassVar

import jinja2
import pytest
import yaml

from codegen.compile import compile_text

# The generator's features on a small frozen spec, not on whatever the real spec holds today.
BASE_SPEC = Path(__file__).resolve().parents[1] / "fixtures" / "ur_primary_5_9_only.yaml"
from codegen.emit import TEMPLATES
from codegen.errors import SpecError
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import dissector, lua


@pytest.fixture(scope="module")
def protocol():
    return compile_text(BASE_SPEC.read_text(encoding="utf-8"))


def test_an_unknown_descriptor_kind_is_an_error(protocol, monkeypatch):
    real = dissector._Builder.descriptor

    @dataclasses.dataclass
    class Tlv(dissector.String):
        kind: ClassVar[str] = "tlv"

    def descriptor(self, owner, f, doc, path, keep, show):
        d = real(self, owner, f, doc, path, keep, show)
        return Tlv(d.path, d.show, d.field) if path == "tool_temperature" else d

    monkeypatch.setattr(dissector._Builder, "descriptor", descriptor)
    with pytest.raises(jinja2.UndefinedError, match="tlv"):
        lua.render(plan(protocol), ["test"])


def test_an_unknown_field_shape_is_an_error(protocol, monkeypatch):
    real = dissector._Builder.add_field

    def add_field(self, pf, *where):
        if pf.key == "robot_mode_data.timestamp":
            pf = dataclasses.replace(pf, shape="timestamp")
        return real(self, pf, *where)

    monkeypatch.setattr(dissector._Builder, "add_field", add_field)
    with pytest.raises(jinja2.UndefinedError, match="timestamp"):
        lua.render(plan(protocol), ["test"])


def test_every_runtime_file_is_joined_in_a_known_order(monkeypatch):
    monkeypatch.setattr(lua, "RUNTIME", lua.RUNTIME[:-1])
    with pytest.raises(ValueError, match="joining order"):
        lua.runtime()


def test_constants_come_from_the_spec(protocol):
    p = copy.deepcopy(protocol)
    p.default_version = (5, 12, 0)
    p.ports = [40000, 40001]
    p.max_message_length = 4096
    p.max_value_depth = 3
    text = lua.render(plan(p), ["test"])[lua.OUT]
    spec_table = text[text.index("local spec = {"):text.index("local rt = {}")]
    for expected in ('default_version = "5.12"', 'default_ports = "40000,40001"', "max_message_length = 4096",
                     "max_value_depth = 3", "header_size = 5", "package_header_size = 5"):
        assert expected in spec_table, expected


def test_the_template_is_mostly_data():
    template = (TEMPLATES / "lua" / "packages" / "urwire.lua.j2").read_text(encoding="utf-8")
    assert len(template.splitlines()) < 600
    for statement in ("function", "while ", "local function"):
        assert statement not in template.replace("(function(...)", ""), statement


# ---- several generations: versions as numbers, forms, repeated names, names by version ----

def variant(edit):
    data = yaml.safe_load(BASE_SPEC.read_text(encoding="utf-8"))
    edit(data)
    return plan(compile_text(yaml.safe_dump(data, sort_keys=False)))


def render_text(protocol_plan) -> str:
    return lua.render(protocol_plan, ["test"])[lua.OUT]


def entries(text: str) -> str:
    """The rendered Lua with its layout folded away: a long string's \\z continuations joined and
    every run of line breaks and indentation one space, so a check reads entries, not lines."""
    return re.sub(r"\s+", " ", re.sub(r"\\z\s*", "", text))


def test_versions_reach_the_runtime_as_numbers():
    """(major * 1000 + minor) * 1000 + bugfix: a bound written 5.8 takes in every 5.8.x."""
    def edit(data):
        data["messages"]["robot_state"]["packages"]["additional_info"]["fields"].append(
            {"name": "gated", "label": "Gated", "type": "uint8", "versions": {"from": "5.25.1", "until": "6.2"}})

    text = entries(render_text(variant(edit)))
    assert '{ k = "cond", present_if = nil, low = 5025001, high = 6002999, fields = {' in text
    assert "{ low = 3003000, high = 5008999, min_size = 1, kinds = {" in text   # value types of 3.3 to 5.8
    # The forms tables print versions as versions: the runtime parses them once, at load.
    assert ('{ of = PART.additional_info, sizes = { [5] = true }, min = 5, rep = "5.25.1", '
            'versions = "5.25.1 to 6.2" }') in text
    starts = text[text.index("segment_starts = {"):]
    starts = starts[:starts.index("}")]
    assert '"5.25.1"' in starts and '"6.3"' in starts     # a form from 5.25.1, the next from 6.3 on


def test_a_repeated_name_is_one_protofield_of_its_widest_type():
    def edit(data):
        fields = data["messages"]["robot_state"]["packages"]["tool_data"]["fields"]
        fields[0] = dict(fields[0], versions={"from": "3.0"}, type="int32")
        fields.insert(0, dict(fields[0], type="int8", versions={"until": "1.8"}))

    text = entries(render_text(variant(edit)))
    assert text.count('ProtoField.int32("ur.tool_data.analog_input_range0"') == 1
    assert 'ProtoField.int8("ur.tool_data.analog_input_range0"' not in text
    narrow = '{ k = "scalar", f = F["tool_data.analog_input_range0"], n = 1, path = "analog_input_range0", signed = true, value = true }'
    wide = '{ k = "scalar", f = F["tool_data.analog_input_range0"], n = 4, path = "analog_input_range0", signed = true }'
    assert narrow in text and wide in text


def test_entries_no_one_field_holds_are_a_problem():
    """int32 then uint32: no one Wireshark field holds both; the spec is refused before any
    target renders it (resolve.same_name)."""
    def edit(data):
        fields = data["messages"]["robot_state"]["packages"]["tool_data"]["fields"]
        fields[0] = dict(fields[0], versions={"from": "3.0"}, type="uint32")
        fields.insert(0, dict(fields[0], type="int32", versions={"until": "1.8"}))

    with pytest.raises(SpecError) as caught:
        render_text(variant(edit))
    (problem,) = caught.value.problems
    assert problem.path == "messages.robot_state.packages.tool_data.fields[1].type"
    assert "analog_input_range0" in problem.message and "int32 and uint32" in problem.message


def test_a_versioned_enum_has_its_names_by_version():
    text = render_text(plan(compile_text(BASE_SPEC.read_text(encoding="utf-8"))))
    assert "NAMES.JOINT_MODE = { newest = VS.JOINT_MODE," in text
    assert "{ low = nil, high = 5000999, names = VS.JOINT_MODE_UpTo5_0 },   -- up to 5.0" in text
    assert 'tables = NAMES.JOINT_MODE, label = "Joint mode"' in text
    assert 'ProtoField.uint8("ur.joint_data.joint_mode", "Joint mode", base.DEC, VS.JOINT_MODE,' in text


def test_the_version_reader_reads_the_bugfix_in_its_versions():
    def edit(data):
        version = data["messages"]["robot_message"]["subtypes"]["version"]
        version["sets_version"]["bugfix"] = "bugfix_version"
        fields = version["fields"]
        fields[3] = dict(fields[3], versions={"from": "3.3"})
        fields.insert(3, {"name": "svn_revision", "label": "Svn revision", "type": "int32", "versions": {"until": "3.2"}})

    text = render_text(variant(edit))
    assert "bugfix = { n = 4, signed = true, low = 3003000, high = nil }," in text
    assert "bugfix = {" not in render_text(plan(compile_text(BASE_SPEC.read_text(encoding="utf-8"))))


def test_a_summary_the_info_column_cannot_read_is_a_problem():
    """The Info column reads summaries from the raw bytes: it steps over fixed fields, texts and
    version-gated parts, not over a switch; and it shows integers and texts."""
    def edit(data):
        safety = data["messages"]["robot_message"]["subtypes"]["safety_mode"]
        safety["fields"].append({"name": "after", "label": "After", "type": "uint8"})
        safety["summary"] = "{safety_mode_type} {after}"
        data["messages"]["robot_state"]["packages"]["robot_mode_data"]["summary"] = "{robot_mode} {speed_scaling}"

    with pytest.raises(SpecError) as caught:
        render_text(variant(edit))
    found = {(p.path, p.message) for p in caught.value.problems}
    assert ("messages.robot_message.subtypes.safety_mode",
            "the summary's field 'after' comes after a field the Info column cannot step over") in found
    assert ("messages.robot_state.packages.robot_mode_data",
            "the summary cannot show 'speed_scaling', a float field") in found


def test_a_filter_name_with_two_types_is_a_problem():
    """A field named like a role of the typed values beside it (`type`, a text of the values)
    would give one filter name two types."""
    def edit(data):
        update = data["messages"]["program_state"]["subtypes"]["global_variables_update"]
        update["fields"].insert(1, {"name": "type", "label": "Type", "type": "uint8"})

    with pytest.raises(SpecError) as caught:
        render_text(variant(edit))
    assert any("ur.global_variables_update.type would be both" in p.message for p in caught.value.problems)


def test_labels_units_and_descriptions_reach_the_protofields(protocol):
    text = entries(render_text(plan(protocol)))
    assert ('ProtoField.double("ur.joint_data.q_actual", "Actual joint position", '
            '"Actual joint position (rad). In rad.")') in text   # the fixture's doc, then the unit
    assert 'ProtoField.uint8("ur.tool_data.tool_output_voltage", "Tool output voltage", base.UNIT_STRING, { " V" },' in text
    assert 'f = F["joint_data.q_actual"], n = 8, path = "q_actual", signed = false, unit = " rad" }' in text
