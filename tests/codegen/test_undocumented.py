"""Types no UR document lays out: the spec names them, the IR marks them (undocumented, and
inferred where the fields are read from real bytes), and every target shows the marks; a message
of one layout (types 5, 22, 23, 24) has no subtype byte."""
from __future__ import annotations

import textwrap

import pytest

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.errors import SpecError
from codegen.kinds.packages.naming import layout_label
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import c, lua, python

SPEC_TEXT = DEFAULT_SPEC.read_text(encoding="utf-8")
PROTOCOL = compile_text(SPEC_TEXT)
PLAN = plan(PROTOCOL)
LAYOUTS = {lay.name: lay for lay in PROTOCOL.all_layouts()}


@pytest.mark.parametrize("name, marks", [
    ("payload_info", ["undocumented", "inferred"]),
    ("robot_message_12", ["undocumented"]),
    ("modbus_info", ["undocumented"]),
    ("hmc", ["undocumented"]),
    ("safety_setup_broadcast", ["undocumented"]),
    ("safety_compliance_tolerances", ["undocumented", "inferred"]),
    ("joint_data", []),
    ("version", []),
])
def test_the_marks_come_from_the_code_and_the_layout(name, marks):
    assert LAYOUTS[name].marks == marks


def test_labels_carry_the_marks():
    assert layout_label(LAYOUTS["payload_info"]) == "Payload info (undocumented, inferred)"
    assert layout_label(LAYOUTS["hmc"]) == "HMC (undocumented)"   # the spec's label: not "Hmc"
    assert layout_label(LAYOUTS["joint_data"]) == "Joint data"


def test_the_four_body_messages_have_no_subtype_byte():
    bodies = {m.message.name: m for m in PLAN.messages if m.is_dispatch and not m.message.has_subtype}
    assert sorted((m.message.code.value, name) for name, m in bodies.items()) == [
        (5, "modbus_info"), (22, "hmc"), (23, "safety_setup_broadcast"), (24, "safety_compliance_tolerances")]
    for mp in bodies.values():
        assert mp.header == [] and mp.subtype_offset is None
        assert mp.body_offset == PROTOCOL.header_size
        assert list(mp.variants) == [mp.message.code.value]   # its one layout's code is its type
    tolerances = bodies["safety_compliance_tolerances"].variants[24][0]
    assert tolerances.sizes == {22 * 8}


def test_only_message_type_255_stays_unlaid():
    assert [v.name for v in PROTOCOL.unlaid_message_codes] == ["DISCONNECT"]


def test_every_target_shows_the_marked_labels():
    py = python.render(PLAN, ["test"])["python/urwire/generated/messages.py"]
    assert 'LABEL: ClassVar[str] = "Safety compliance tolerances (undocumented, inferred)"' in py
    assert 'LABEL: ClassVar[str] = "Robot message 12 (undocumented)"' in py
    text = lua.render(PLAN, ["test"])["lua/urwire.lua"]
    assert '"ur.payload_info", "Payload info (undocumented, inferred)"' in text
    assert '"ur.modbus_info", "Modbus info (undocumented)"' in text
    header = c.render(PLAN, ["test"])["c/urwire.h"]
    assert "urwire_safety_compliance_tolerances_message safety_compliance_tolerances;" in header
    assert "URWIRE_KIND_MODBUS_INFO," in header


def test_a_body_message_is_a_layout_under_messages():
    spec = SPEC_TEXT.replace("""  hmc:
    code: HMC_MESSAGE
    label: HMC
""", """  hmc:
    code: HMC_MESSAGE
    label: HMC
    subtype: {name: x, label: "X", type: uint8, enum: message_type}
""")
    with pytest.raises(SpecError) as err:
        compile_text(spec)
    assert "messages.hmc" in str(err.value)


def test_a_body_message_is_named_once():
    spec = SPEC_TEXT.replace("      robot_message_12:\n", "      hmc:\n")
    with pytest.raises(SpecError) as err:
        compile_text(spec)
    assert "layout name 'hmc' is used more than once" in str(err.value)
