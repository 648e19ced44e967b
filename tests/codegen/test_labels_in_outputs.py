"""The spec's labels and units reach what people read in every target: the C header's member
comments and the protocol reference (the Lua and Python targets are tested with their output)."""
from __future__ import annotations

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages.reference import protocol_markdown
from codegen.kinds.packages import c

PLAN = plan(compile_text(DEFAULT_SPEC.read_text(encoding="utf-8")))


def test_c_members_say_their_label_and_unit():
    header = c.render(PLAN, ["test"])["c/urwire.h"]
    assert "double q_actual;  /* Actual joint position (rad). Measured angle of the joint. */" in header
    assert "float t_motor;  /* Motor temperature (°C). Temperature of the joint. */" in header
    assert "uint8_t is_real_robot_connected;" in header and "/* Real robot connected." in header


def test_the_reference_lists_each_field_with_its_label_and_unit():
    text = protocol_markdown(PLAN, "spec/ur_primary.yaml")
    assert "| `joints[].q_actual` | Actual joint position | rad | Measured angle of the joint. |" in text
    assert "| `tool_output_voltage` | Tool output voltage | V |" in text
    assert "| `is_real_robot_connected` | Real robot connected |  |" in text
