"""The kind `int32_records` (spec/ur_reverse.yaml, ur_trajectory.yaml, ur_script_command.yaml):
layouts along the driver-release axis, and spec errors at their YAML paths and lines."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from codegen.compile import SPEC_DIR, compile_text
from codegen.errors import SpecError
from codegen.kinds.int32_records.plan import plan

ROOT = Path(__file__).resolve().parents[2]
TRAJECTORY = (SPEC_DIR / "ur_trajectory.yaml").read_text(encoding="utf-8")
REVERSE = (SPEC_DIR / "ur_reverse.yaml").read_text(encoding="utf-8")


def problems(text: str) -> list:
    with pytest.raises(SpecError) as caught:
        compile_text(text, "probe.yaml")
    return caught.value.problems


def test_the_trajectory_point_has_a_layout_per_release_range():
    (point, result) = plan(compile_text(TRAJECTORY)).records
    assert [(lay.describe(), lay.size) for lay in point.layouts] == [
        ("up to 1.3.1", 9), ("1.3.2 to 2.9", 21), ("2.10 and later", 21)]
    scales = [{s.field.name: s.scale for s in lay.slots}["duration"] for lay in point.layouts]
    assert scales == [1000, 1000, 1000000]
    assert [f.name for f in point.fields if not f.always] == ["velocities", "accelerations"]
    assert [lay.size for lay in result.layouts] == [1]


def test_one_name_sent_twice_in_one_release_is_named_at_its_path():
    text = TRAJECTORY.replace('versions: {from: "2.10.0"}', 'versions: {from: "2.9.0"}', 1)
    (problem,) = problems(text)
    assert problem.path.startswith("records[0].fields[") and problem.path.endswith(".versions")
    assert "duration is sent twice" in problem.message


def test_a_field_that_changes_its_kind_and_an_unknown_enum_are_both_reported():
    text = REVERSE.replace("      - name: read_timeout\n",
                           "      - name: keepalive\n        scale: 1000\n        scale_name: MULT_TIME\n").replace(
        "        enum: control_mode\n", "        enum: no_such_enum\n")
    found = {p.path: p.message for p in problems(text)}
    assert "changes its kind" in found["records[0].fields[1]"]
    assert "unknown enum 'no_such_enum'" in found["records[0].fields[3].enum"]


def test_a_scale_needs_its_constant_name():
    text = REVERSE.replace("        scale_name: MULT_JOINTSTATE\n", "")
    (problem,) = problems(text)
    assert problem.path == "records[0].fields[2]" and "scale_name" in problem.message


def test_a_name_both_records_send_keeps_one_kind():
    """Each field is one filter ur_trajectory.<name> over both records: the result record's
    motion_type taken as a plain int32 while the point's carries an enum would be two kinds."""
    text = TRAJECTORY.replace("      - name: result\n        enum: result_code\n",
                              "      - name: motion_type\n")
    (problem,) = problems(text)
    assert problem.path == "records[1].fields[0]"
    assert "ur_trajectory.motion_type is a field of trajectory_point too, of another kind" in problem.message


def test_a_field_named_like_a_scaled_fields_raw_int32_is_refused_by_target_c(tmp_path):
    """ur_reverse.target is scaled, so ur_reverse.target_raw is its raw int32 in both dissectors;
    the C target renders no dissector and still refuses the spec, at the field's YAML path."""
    bad = tmp_path / "ur_reverse.yaml"
    bad.write_text(REVERSE.replace("      - name: control_mode\n", "      - name: target_raw\n"), encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "codegen", "--spec", str(bad), "--target", "c",
                             "--out", str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode != 0
    assert "records[0].fields[3].name" in result.stderr, result.stderr
    assert "ur_reverse.target_raw is the raw int32 of the scaled field target" in result.stderr
