"""Targets report what they cannot render like spec errors, and templates refuse unknown steps."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import jinja2
import pytest
import yaml

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.emit import environment
from codegen.errors import SpecError
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import python as python_target
from codegen.view import Step

ROOT = Path(__file__).resolve().parents[2]


def spec_with(edit) -> str:
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    edit(data)
    return yaml.safe_dump(data, sort_keys=False)


def test_a_field_named_like_a_decoder_local_is_a_problem_with_its_path():
    def edit(data):
        data["messages"]["robot_state"]["packages"]["tool_data"]["fields"][0]["name"] = "buf"

    with pytest.raises(SpecError) as caught:
        python_target.render(plan(compile_text(spec_with(edit))), ["test"])
    (problem,) = caught.value.problems
    assert problem.path == "messages.robot_state.packages.tool_data.fields[0]"
    assert problem.line is not None and "buf" in problem.message


def test_the_command_prints_a_target_problem_and_exits_2(tmp_path):
    spec = tmp_path / "spec.yaml"
    spec.write_text(spec_with(lambda d: d["messages"]["robot_state"]["packages"]["tool_data"]["fields"][0]
                              .update(name="pos")))
    result = subprocess.run([sys.executable, "-m", "codegen", "--spec", str(spec), "--out", str(tmp_path / "out")],
                            cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 2
    assert "tool_data.fields[0] (line" in result.stderr and "Traceback" not in result.stderr


def test_two_layouts_that_set_the_version_are_a_planning_problem():
    def edit(data):
        data["messages"]["robot_message"]["subtypes"]["text"]["sets_version"] = {"major": "a", "minor": "b"}
        data["messages"]["robot_message"]["subtypes"]["text"]["fields"] = [
            {"name": "a", "label": "A", "type": "uint8"}, {"name": "b", "label": "B", "type": "uint8"}]
        data["messages"]["robot_message"]["subtypes"]["text"]["summary"] = "{a}"

    with pytest.raises(SpecError) as caught:
        plan(compile_text(spec_with(edit)))
    assert "exactly one layout must set the version" in str(caught.value)


@pytest.mark.parametrize("target, template, macro", [
    ("python", "packages/steps.py.j2", "decode"),
    ("python", "packages/steps.py.j2", "encode"),
])
def test_an_unknown_step_kind_fails_at_generation_time(target, template, macro):
    module = environment(target).get_template(template).module
    with pytest.raises(jinja2.UndefinedError):
        getattr(module, macro)([Step("no_such_kind", {})], "")


def test_a_c_keyword_as_a_field_name_is_a_c_target_problem():
    from codegen.kinds.packages import c as c_target

    def edit(data):
        data["messages"]["robot_state"]["packages"]["tool_data"]["fields"][1]["name"] = "switch"

    with pytest.raises(SpecError) as caught:
        c_target.render(plan(compile_text(spec_with(edit))), ["test"])
    (problem,) = caught.value.problems
    assert problem.path == "messages.robot_state.packages.tool_data.fields[1]" and "C keyword" in problem.message
