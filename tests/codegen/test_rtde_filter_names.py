"""RTDE's filter names: every message field and variable is the Wireshark field rtde.<name> in
both dissectors, so the kind's resolver refuses a name with two types, one of the dissectors' own,
or one that differs from another only in case, at the spec's YAML path, for every target (here
`python -m codegen --target c`, which renders no dissector)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from codegen.compile import SPEC_DIR, compile_text
from codegen.errors import SpecError
from codegen.kinds.typed_messages import model
from codegen.kinds.typed_messages.dissector import dissector
from codegen.kinds.typed_messages.plan import plan

ROOT = Path(__file__).resolve().parents[2]
SPEC = SPEC_DIR / "rtde.yaml"
TEXT = SPEC.read_text(encoding="utf-8")


def edited(edit) -> str:
    data = yaml.safe_load(TEXT)
    edit(data)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def variable_named(name: str, index: int = 0):
    def edit(data):
        data["variables"][index]["name"] = name
        data["variables"][index].pop("indices", None)
    return edit


def problems(text: str) -> list[str]:
    with pytest.raises(SpecError) as caught:
        compile_text(text, "bad.yaml")
    return [str(p) for p in caught.value.problems]


def test_a_variable_named_like_the_dissectors_own_field_is_refused_at_its_path():
    found = problems(edited(variable_named("unknown_variable")))
    assert any(p.startswith("variables[0]") and "rtde.unknown_variable is the dissector's own field" in p
               for p in found), found


def test_a_value_field_name_is_the_dissectors_own():
    found = problems(edited(variable_named("value_float64")))
    assert any("rtde.value_float64 is the dissector's own field" in p for p in found), found


def test_a_name_with_two_types_is_refused():
    """recipe_id is a uint8 in every message; a double variable of that name would be a second type."""
    data = yaml.safe_load(TEXT)
    double = next(i for i, v in enumerate(data["variables"]) if v["type"] == "DOUBLE" and "indices" not in v)
    found = problems(edited(variable_named("recipe_id", double)))
    assert any(p.startswith(f"variables[{double}]") and "rtde.recipe_id would be both a uint8 and a float64 field"
               in p for p in found), found


def test_names_that_differ_only_in_case_are_refused():
    data = yaml.safe_load(TEXT)
    first = data["variables"][0]["name"]
    found = problems(edited(variable_named(first.upper(), 1)))
    assert any("differ only in case" in p and p.startswith("variables[1]") for p in found), found


def test_target_c_reports_the_rule(tmp_path):
    """The C target renders no dissector, yet the spec is refused, at its YAML path."""
    bad = tmp_path / "rtde.yaml"
    bad.write_text(edited(variable_named("protocol")), encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "codegen", "--spec", str(bad), "--target", "c",
                             "--out", str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode != 0
    assert "variables[0]" in result.stderr and "rtde.protocol is the dissector's own field" in result.stderr, \
        result.stderr


def test_the_dissectors_own_fields_are_the_ones_resolve_keeps_free():
    d = dissector(plan(compile_text(TEXT, str(SPEC))))
    assert tuple(f.name for f in d.header) == model.OWN_FIELDS
    assert all(f.name.startswith(model.VALUE_FIELD_PREFIX) for f in d.values)
