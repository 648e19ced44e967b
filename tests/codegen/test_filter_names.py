"""The Wireshark filter names of the primary interface obey rules of the spec, not of one target:
one type per filter name, and none of the dissector's own names (ur.raw, ur.malformed, ...). They
are checked when the spec is resolved, so every target reports them at the spec's YAML path, even
one that writes no dissector (`python -m codegen --target c`)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.errors import SpecError
from codegen.kinds.packages.dissector import EXPERTS, OWN_FIELDS

ROOT = Path(__file__).resolve().parents[2]
UPDATE = "messages.program_state.subtypes.global_variables_update"


def spec_with(edit) -> str:
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    edit(data)
    return yaml.safe_dump(data, sort_keys=False)


def typed_value_role(data) -> None:
    """A field `type` beside the typed values, whose value type names are the text ur.<layout>.type."""
    update = data["messages"]["program_state"]["subtypes"]["global_variables_update"]
    update["fields"].insert(1, {"name": "type", "label": "Type", "type": "uint8"})


def package_named(name: str):
    def edit(data) -> None:
        packages = data["messages"]["robot_state"]["packages"]
        data["messages"]["robot_state"]["packages"] = {name if key == "payload_info" else key: layout
                                                       for key, layout in packages.items()}
    return edit


def problems_of(text: str) -> list[str]:
    with pytest.raises(SpecError) as caught:
        compile_text(text, "bad.yaml")
    return [str(p) for p in caught.value.problems]


@pytest.mark.parametrize("target", ["c", "python"])
def test_a_filter_name_with_two_types_fails_a_target_that_writes_no_dissector(tmp_path, target):
    spec = tmp_path / "bad.yaml"
    spec.write_text(spec_with(typed_value_role), encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "codegen", "--spec", str(spec), "--target", target,
                             "--out", str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 2, result.stderr
    assert f"{UPDATE}.fields[2] (line " in result.stderr
    assert "ur.global_variables_update.type would be both an integer and a text field" in result.stderr
    assert "Traceback" not in result.stderr and not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["raw", "malformed"])
def test_a_layout_may_not_take_the_dissectors_own_name(name):
    (problem,) = problems_of(spec_with(package_named(name)))
    assert problem.startswith(f"messages.robot_state.packages.{name} (line ")
    assert f"ur.{name} is the dissector's own name" in problem


def test_the_own_names_are_those_the_lua_dissector_declares():
    """runtime/lua/packages/declare.lua declares the Lua dissector's own fields and expert infos by hand; the
    rule above guards the same names."""
    declared = (ROOT / "runtime" / "lua" / "packages" / "declare.lua").read_text(encoding="utf-8")
    for name in [f.filter for f in OWN_FIELDS] + [e.filter for e in EXPERTS]:
        assert f'"{name}"' in declared, name
