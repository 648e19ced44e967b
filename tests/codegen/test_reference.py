"""The spec diff and the protocol reference read the same plan the decoders use."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import yaml

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages.reference import diff, forms_at, protocol_markdown

ROOT = Path(__file__).resolve().parents[2]


def planned_with(edit):
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    edit(data)
    return plan(compile_text(yaml.safe_dump(data, sort_keys=False)))


def gate_two_fields(data):
    fields = data["messages"]["robot_state"]["packages"]["tool_mode_info"]["fields"]
    fields.append({"name": "gated_flag", "label": "Gated flag", "type": "uint16", "versions": {"from": "5.12", "through": "PolyScope X"}})
    fields.append({"name": "old_flag", "label": "Old flag", "type": "uint8", "versions": {"until": "5.11"}})


def test_diff_names_fields_sizes_and_enum_members():
    p = planned_with(gate_two_fields)
    lines = diff(p, (5, 11, 0), (5, 25, 1))
    assert "~ robot_state 12: tool_mode_info" in lines
    assert "  size 9 -> 10" in lines
    assert "  - old_flag: uint8" in lines and "  + gated_flag: uint16" in lines
    assert diff(p, (5, 12, 0), (5, 20, 3)) == []
    enum_lines = diff(p, (5, 0, 0), (5, 1, 0))
    assert enum_lines == ["~ enum joint_mode", "  240: (none) -> READY_FOR_POWER_OFF"]
    cb2 = diff(p, (1, 8, 0), (3, 0, 0))
    assert "~ robot_state 0: robot_mode_data" in cb2 and "  size 29 -> 38" in cb2 and "  + control_mode: uint8 (control_mode)" in cb2


def test_forms_at_a_version_follow_the_until_bound_to_every_bugfix():
    p = planned_with(gate_two_fields)
    assert [n for n, _ in forms_at(p, (5, 11, 4))[("robot_state", 12)].fields][-1] == "old_flag"
    assert [n for n, _ in forms_at(p, (5, 12, 0))[("robot_state", 12)].fields][-1] == "gated_flag"


def test_the_reference_lists_each_form_with_its_versions_and_size():
    text = protocol_markdown(planned_with(gate_two_fields), "spec/ur_primary.yaml")
    assert "| up to 5.11 | 9 |" in text and "| 5.12 and later | 10 |" in text
    assert "| 3.10 to 3.15 or 5.4 and later | 75, or 91 with euromap67_interface_installed |" in text


def test_the_command_and_the_committed_reference():
    result = subprocess.run([sys.executable, "-m", "codegen", "diff", "5.0", "5.9"], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode == 0 and "READY_FOR_POWER_OFF" in result.stdout
    bad = subprocess.run([sys.executable, "-m", "codegen", "diff", "5.x", "5.9"], cwd=ROOT,
                         capture_output=True, text=True)
    assert bad.returncode == 2
    check = subprocess.run([sys.executable, "-m", "codegen", "reference", "--check"], cwd=ROOT,
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
