"""The selection pass (codegen/select.py, kinds/<kind>/select.py; docs/generator.md#subsets): what a
selection keeps of the IR, what it always keeps, and a clear error naming every bad name."""
from __future__ import annotations

import copy
import subprocess
import sys
from pathlib import Path

import pytest

from codegen import ir, select
from codegen.compile import SPEC_DIR, compile_file
from codegen.kinds.packages import model
from codegen.kinds.packages.pin import pin

ROOT = Path(__file__).resolve().parents[2]
PRIMARY = compile_file()
RTDE = compile_file(SPEC_DIR / "rtde.yaml")
WHERE = ir.Where("ur")


def picks(*names: str) -> tuple[select.Pick, ...]:
    return tuple(select.Pick(n, ir.Where("ur")) for n in names)


def primary(*names: str, protocol: model.Protocol = PRIMARY) -> model.Protocol:
    return select.apply("packages", protocol, picks(*names), WHERE)


def problems_of(kind: str, model_, *names: str) -> list[str]:
    with pytest.raises(select.SelectionError) as info:
        select.apply(kind, model_, picks(*names), WHERE)
    return [p.message for p in info.value.problems]


def layouts(p: model.Protocol) -> dict[str, list[str]]:
    return {m.name: [lay.name for lay in (m.packages if isinstance(m, model.PackageListMessage) else m.subtypes)]
            for m in p.messages}


def test_sub_packages_keep_only_those_and_the_version_message():
    p = primary("robot_state.joint_data", "robot_state.tool_data")
    assert layouts(p) == {"robot_state": ["joint_data", "tool_data"], "robot_message": ["version"]}
    # What is left out keeps its code: the framer frames it, decoders keep it raw by its length.
    assert p.messages[0].package_type.names == PRIMARY.messages[0].package_type.names
    assert p.message_type_enum.names == PRIMARY.message_type_enum.names
    # Enums only the dropped layouts used go with them; the kept layouts' stay.
    assert "robot_mode" not in p.enums and "joint_mode" in p.enums and "robot_mode" in PRIMARY.enums
    assert layouts(PRIMARY)["robot_state"][:3] == ["robot_mode_data", "joint_data", "tool_data"]   # untouched


def test_a_message_picks_every_layout_it_has():
    p = primary("robot_state", "robot_message.text")
    assert layouts(p)["robot_state"] == layouts(PRIMARY)["robot_state"]
    assert layouts(p)["robot_message"] == ["version", "text"]


def test_a_code_with_a_layout_per_version_is_picked_whole_unless_pinned():
    (problem,) = problems_of("packages", PRIMARY, "robot_state.kinematics_info")
    assert "type code 5 is also laser_pointer (up to 1.7)" in problem and "robot_state.laser_pointer" in problem
    assert layouts(primary("robot_state.kinematics_info", "robot_state.laser_pointer"))["robot_state"] == \
        ["laser_pointer", "kinematics_info"]
    pinned = primary("robot_state.kinematics_info", protocol=pin(PRIMARY, (5, 11, 0)))
    assert layouts(pinned)["robot_state"] == ["kinematics_info"]


def test_a_robot_state_keeps_a_sub_package():
    (problem,) = problems_of("packages", PRIMARY, "robot_message.text")
    assert "keep at least one robot_state sub-package" in problem


@pytest.mark.parametrize("name, says", [
    ("robot_state.joint_dat", "robot_state has no sub-package 'joint_dat' (did you mean joint_data?)"),
    ("robot_stat", "ur has no message 'robot_stat' (did you mean robot_state"),
    ("robot_message.texts", "robot_message has no subtype 'texts' (did you mean text?)"),
    ("hmc.x", "hmc has no layout 'x'; it has: hmc"),
])
def test_a_bad_name_is_an_error_naming_it(name, says):
    (problem,) = problems_of("packages", PRIMARY, name, "robot_state.joint_data")
    assert problem.startswith(f"{name}: ") and says in problem


def test_rtde_keeps_the_picked_rows_of_its_variable_table():
    r = select.apply("typed_messages", RTDE, picks("actual_q", "input_bit_registers0_to_31"), WHERE)
    assert sorted((v.name, v.direction) for v in r.variables) == \
        [("actual_q", "output"), ("input_bit_registers0_to_31", "input"), ("input_bit_registers0_to_31", "output")]
    assert r.messages == RTDE.messages and len(RTDE.variables) > 500   # every message stays; the spec's IR too
    (problem,) = problems_of("typed_messages", RTDE, "actual_TCP_pos")
    assert "rtde's table has no variable 'actual_TCP_pos' (did you mean actual_TCP_pose" in problem


def test_a_kind_without_a_selection_pass_says_so():
    dashboard = compile_file(SPEC_DIR / "ur_dashboard.yaml")
    (problem,) = problems_of("lines", dashboard, "x")
    assert "kind lines takes no selection (kinds that do: packages, typed_messages)" in problem


def test_the_option_and_a_file_say_the_same():
    option = select.parse(["ur:robot_state.joint_data,robot_state.tool_data", "rtde:actual_q"])
    text = ("# joints, tool, and one RTDE output\n"
            "ur: [robot_state.joint_data, robot_state.tool_data]\nrtde: [actual_q]\n")
    from_file = select.load_selection_text(text, "firmware.yaml")
    for s in (option, from_file):
        assert {k: [p.name for p in v] for k, v in s.picks.items()} == \
            {"ur": ["robot_state.joint_data", "robot_state.tool_data"], "rtde": ["actual_q"]}
    assert from_file.picks["ur"][1].where.line == 2
    assert select.names_of(SPEC_DIR / "ur_primary.yaml", {"protocol": {"name": "ur"}}) == {"ur", "ur_primary"}


def test_a_file_that_breaks_the_schema_is_an_error_at_its_line(tmp_path):
    bad = tmp_path / "firmware.yaml"
    bad.write_text("ur:\n  - robot_state.joint_data\n  - 3x\n")
    with pytest.raises(select.SelectionError) as info:
        select.parse([str(bad)])
    (problem,) = info.value.problems
    assert problem.line == 3 and "'3x' does not match" in problem.message and str(bad) in problem.path


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], cwd=ROOT, capture_output=True, text=True)


def test_codegen_reports_every_bad_name_of_every_interface_and_exits_2(tmp_path):
    result = run("--select", "ur:robot_state.joint_dat,robot_state.tool_data", "--select", "rtde:actual_qq",
                 "--select", "nowhere:x", "--target", "c", "--out", str(tmp_path))
    assert result.returncode == 2 and result.stdout == ""
    lines = result.stderr.splitlines()
    assert lines[0] == "--select: 1 problem(s) in the selection:"          # no such interface: found first
    assert "the cell has no interface 'nowhere'" in lines[1]
    result = run("--select", "ur:robot_state.joint_dat,robot_state.tool_data", "--select", "rtde:actual_qq",
                 "--target", "c", "--out", str(tmp_path))
    assert result.returncode == 2 and "2 problem(s) in the selection" in result.stderr
    assert "'joint_dat'" in result.stderr and "'actual_qq'" in result.stderr
    assert not any(tmp_path.iterdir())                                      # nothing written


def test_codegen_writes_a_selection_outside_generated_only(tmp_path):
    result = run("--select", "ur:robot_state.joint_data", "--target", "python", "--out", str(tmp_path))
    assert result.returncode == 0, result.stderr
    written = sorted(p.name for p in tmp_path.rglob("*.py"))
    assert "messages.py" in written and "rtde.py" not in written          # only the interfaces it names
    messages = (tmp_path / "python" / "urwire" / "generated" / "messages.py").read_text()
    assert "class JointData" in messages and "class ToolData" not in messages
    refused = run("--select", "ur:robot_state.joint_data", "--target", "c")
    assert refused.returncode == 2 and "give --out a folder outside generated/" in refused.stderr


def test_every_target_renders_a_selection():
    from codegen.kinds import KINDS
    p = primary("robot_state.joint_data", "robot_state.tool_data")
    out = KINDS["packages"].render(copy.deepcopy(p), ["banner"])
    assert {"c/urwire.c", "epan/packet-ur.c", "lua/urwire.lua", "python/urwire/generated/messages.py"} <= set(out)
    r = select.apply("typed_messages", RTDE, picks("actual_q"), WHERE)
    out = KINDS["typed_messages"].render(r, ["banner"])
    assert "#define RTDE_VARIABLE_COUNT 1\n" in out["c/rtde.h"]
