"""The planning pass: what every target renders, said once per layout."""
from __future__ import annotations

import pytest
import yaml

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_file, compile_text
from codegen.kinds.packages.plan import CondGroup, FixedRun, VarField, plan


@pytest.fixture(scope="module")
def planned():
    """The plan of what software 5.10 sends (codegen.kinds.packages.pin): one form per code, no version gates."""
    from codegen.kinds.packages.pin import pin

    return plan(pin(compile_file(), (5, 10, 0)))


@pytest.fixture(scope="module")
def full():
    return plan(compile_file())


def layout(planned, message, name):
    for choice in planned.message(message).layouts:
        if choice.layout.name == name:
            return choice.plan
    raise KeyError(name)


def test_message_headers_and_body_offsets(planned):
    assert planned.header_size == 5 and planned.package_header_size == 5
    state = planned.message("robot_state")
    assert state.body_offset == 5 and state.header == [] and state.subtype_offset is None
    robot = planned.message("robot_message")
    assert [(s.field.name, s.offset, s.is_subtype) for s in robot.header] == [
        ("timestamp", 5, False), ("source", 13, False), ("robot_message_type", 14, True)]
    assert robot.body_offset == 15 and robot.subtype_offset == 14
    program = planned.message("program_state")
    assert [(s.field.name, s.offset) for s in program.header] == [("timestamp", 5), ("robot_message_type", 13)]
    assert program.body_offset == 14


def test_a_fixed_package_is_one_run_with_member_and_leaf_offsets(planned):
    mode = layout(planned, "robot_state", "robot_mode_data")
    (run,) = mode.steps
    assert isinstance(run, FixedRun) and run.size == mode.fixed_size == 42
    first = {m.field.name: (m.offset, m.first_leaf) for m in run.members}
    assert first["timestamp"] == (0, 0) and first["robot_mode"] == (15, 8) and first["reserved"] == (41, 13)


def test_fixed_count_groups_are_read_inside_the_run(planned):
    (run,) = layout(planned, "robot_state", "joint_data").steps
    (joints,) = run.members
    assert joints.item.fixed and joints.item.leaf_count == 8 and joints.item.layout.fixed_size == 41
    assert joints.leaf_count == 48 and len(run.leaves) == 48
    leaf = run.leaves[9]
    assert (leaf.path, leaf.offset, leaf.scalar.name) == ("joints[1].q_target", 49, "float64")


def test_a_flag_makes_one_condition_group_between_runs(planned):
    steps = layout(planned, "robot_state", "masterboard_data").steps
    assert [s.kind for s in steps] == ["run", "cond", "run"]
    head, cond, tail = steps
    assert cond.condition.flag == "euromap67_interface_installed" and cond.condition.versions.unbounded
    assert [f.name for f in cond.fields] == ["euromap_input_bits", "euromap_output_bits", "euromap_voltage_24v",
                                             "euromap_current"]
    (inner,) = cond.steps
    assert isinstance(inner, FixedRun) and inner.size == 16 and inner.index == 1
    assert head.index == 0 and tail.index == 2


def test_variable_fields_and_groups_repeated_to_the_end(planned):
    steps = layout(planned, "robot_message", "program_threads").steps
    (threads,) = steps
    assert isinstance(threads, VarField) and not threads.item.fixed
    assert [s.kind for s in threads.item.layout.steps] == ["run", "var", "var"]


def test_where_the_version_is_read(planned):
    v = planned.version
    assert (v.message_code, v.subtype_code, v.subtype_offset, v.body_offset) == (20, 3, 14, 15)
    assert (v.major.name, v.minor.name) == ("major_version", "minor_version")
    assert [(s.fixed, s.prefix, s.signed) for s in v.skips] == [(0, 1, True)] and v.tail == 0 and v.rest == 8


def test_version_gated_fields_group_by_their_range():
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    fields = data["messages"]["robot_state"]["packages"]["tool_mode_info"]["fields"]
    fields += [{"name": "a", "label": "A", "type": "uint8", "versions": {"from": "5.12", "through": "PolyScope X"}},
               {"name": "b", "label": "B", "type": "uint8", "versions": {"from": "5.12", "through": "PolyScope X"}},
               {"name": "c", "label": "C", "type": "uint8", "versions": {"from": "5.13", "through": "PolyScope X"}}]
    planned = plan(compile_text(yaml.safe_dump(data, sort_keys=False)))
    steps = layout(planned, "robot_state", "tool_mode_info").steps
    assert [s.kind for s in steps] == ["run", "cond", "cond"]
    assert [f.name for f in steps[1].fields] == ["a", "b"] and steps[1].condition.low == (5, 12, 0)
    assert isinstance(steps[2], CondGroup) and steps[2].condition.versions == ir.VersionRange((5, 13, 0), None)


def test_a_pinned_protocol_has_no_version_branches():
    from codegen.kinds.packages.pin import pin

    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    fields = data["messages"]["robot_state"]["packages"]["tool_mode_info"]["fields"]
    fields += [{"name": "a", "label": "A", "type": "uint8", "versions": {"from": "5.12", "through": "PolyScope X"}},
               {"name": "b", "label": "B", "type": "uint8", "versions": {"until": "5.11"}}]
    protocol = compile_text(yaml.safe_dump(data, sort_keys=False))
    for version, kept, gone in (((5, 11, 0), "b", "a"), ((5, 12, 0), "a", "b")):
        pinned = pin(protocol, version)
        planned = plan(pinned)
        steps = layout(planned, "robot_state", "tool_mode_info").steps
        assert [s.kind for s in steps] == ["run"] and kept in [f.name for f in steps[0].fields]
        assert gone not in [f.name for f in steps[0].fields]
        assert all(len(e.tables) == 1 for e in pinned.enums.values())
        assert not any(lay.struct.needs_version and lay.name != "global_variables_update"
                       for lay in pinned.all_layouts())
    assert len(protocol.enums["value_type"].tables) == 3   # the full protocol is left alone


def test_every_form_of_a_code_with_its_versions_sizes_and_representative(full):
    state = full.message("robot_state")

    def forms(code):
        return [(v.layout.name, v.describe(), sorted(v.sizes), v.rep) for v in state.variants[code]]

    assert [(d, sizes) for _, d, sizes, _ in forms(0)] == [
        ("up to 1.8", [24]), ("3.0 to 3.1", [33]), ("3.2 to 3.4", [41]), ("3.5 and later", [42])]
    assert forms(0)[0][3] == (1, 8, 0) and forms(0)[3][3] == (5, 9, 0)
    masterboard = {d: sizes for _, d, sizes, _ in forms(3)}
    assert masterboard["3.0 to 3.1"] == [67, 83] and masterboard["3.10 to 3.15 or 5.4 and later"] == [70, 86]
    assert masterboard["up to 1.5"] == [56] and masterboard["3.2 to 3.9 or 5.0 to 5.3"] == [69, 85]
    assert [(name, d) for name, d, _, _ in forms(5)] == [("laser_pointer", "up to 1.7"),
                                                        ("kinematics_info", "1.8 and later")]
    assert [(d, sizes, rep) for _, d, sizes, rep in forms(6)] == [
        ("up to 1.8", [464], (1, 8, 0)), ("3.0 to 5.25.0", [440], (5, 9, 0)), ("5.25.1 and later", [444], (5, 25, 1))]



def test_a_pinned_version_message_without_a_bugfix_number_plans():
    """Up to 3.2 the Version message has an svn revision where later ones have the bugfix
    number: pinned there, the version is announced without a bugfix (0)."""
    from codegen.kinds.packages.pin import pin

    protocol = compile_text(DEFAULT_SPEC.read_text(encoding="utf-8"))
    for version, bugfix in (((3, 2, 0), None), ((1, 8, 0), None), ((5, 11, 0), "bugfix_version")):
        planned = plan(pin(protocol, version))
        assert planned.version.layout.sets_version[2] == bugfix
        assert (planned.version.bugfix.name if planned.version.bugfix else None) == bugfix


def test_the_fewest_bytes_of_a_value_is_worked_out_once_and_rendered_by_every_target():
    """What bounds LIST and MATRIX counts: the type byte alone while a table has NONE, else the
    type byte and the smallest data (BOOL's one byte)."""
    from codegen.kinds.packages import c as c_target, lua as lua_target, python as python_target

    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    newest = data["enums"]["value_type"]["tables"][-1]["values"]
    newest[:] = [v for v in newest if v["name"] != "NONE"]
    protocol = compile_text(yaml.safe_dump(data, sort_keys=False))
    assert [protocol.value_min_size(t) for t in protocol.value_type.tables] == [1, 1, 2]
    planned = plan(protocol)
    python = python_target.render(planned, ["test"])["python/urwire/generated/spec.py"]
    c = c_target.render(planned, ["test"])["c/urwire.c"]
    lua = lua_target.render(planned, ["test"])["lua/urwire.lua"]
    assert python.count("}, MAX_VALUE_DEPTH, 1)),") == 2 and python.count("}, MAX_VALUE_DEPTH, 2)),") == 1
    assert c.count("(urwire__values_5_9_on), 2},") == 1 and c.count("), 1},") == 2
    assert lua.count("min_size = 1,") == 2 and lua.count("min_size = 2,") == 1


def test_segments_between_series_are_said_from_the_series_before():
    """A segment that no released series holds reads "after 3.15, before 5.0", never as a version
    no controller has (3.16, 5.100); segments inside a series read from their first version."""
    texts = [s.describe() for s in plan(compile_file(DEFAULT_SPEC)).segments]
    assert "after 1.8, before 3.0" in texts and "after 3.15, before 5.0" in texts
    assert "after 5.99, before 10.0" in texts
    assert not any("5.100" in t or "3.16" in t for t in texts), texts
    assert texts[-1] == "10.0 and later" and "5.25.1 to 5.99" in texts
