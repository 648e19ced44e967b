"""The primary interface's two Wireshark dissectors (generated/lua/urwire.lua and
generated/epan/packet-ur.c) render one model (codegen/kinds/packages/dissector.py): every field
it declares is one ProtoField in Lua and one hf entry in C, with its filter name, label and
description, and a change to the model reaches both."""
from __future__ import annotations

import dataclasses
import re

import pytest

from codegen.compile import compile_file
from codegen.kinds.packages import dissector, epan, lua
from codegen.kinds.packages.plan import plan


@pytest.fixture(scope="module")
def planned():
    return plan(compile_file())


@pytest.fixture(scope="module")
def model(planned):
    return dissector.dissector(planned)


def rendered(planned) -> tuple[str, str]:
    return lua.render(planned, ["test"])[lua.OUT], epan.render(planned, ["test"])[epan.OUT]


def test_every_field_is_one_protofield_and_one_hf_entry(planned, model):
    lua_text, c_text = rendered(planned)
    lua_filters = re.findall(r'ProtoField\.\w+\(\s*"([^"]+)"', lua_text)
    c_filters = re.findall(r'\{ &hf_ur\[UR_HF_\w+\],\s*\{ "(?:[^"\\]|\\.)*", "([^"]+)"', c_text)
    spec = [f.filter for f in model.fields]
    own = [f.filter for f in model.own_fields]
    assert len(set(spec)) == len(spec)
    # The own fields come last in both: Lua's from runtime/lua/packages/declare.lua, joined after the tables.
    assert lua_filters == spec + own
    assert c_filters == spec + own


def test_a_change_to_the_model_reaches_both_dissectors(planned, monkeypatch):
    built = dissector.dissector

    def relabelled(protocol_plan):
        d = built(protocol_plan)
        d.fields = [dataclasses.replace(f, label="Relabelled mode") if f.filter == "ur.robot_mode_data.robot_mode"
                    else f for f in d.fields]
        return d

    monkeypatch.setattr(dissector, "dissector", relabelled)
    monkeypatch.setattr(lua, "dissector", relabelled)
    lua_text, c_text = rendered(planned)
    assert '"ur.robot_mode_data.robot_mode", "Relabelled mode"' in re.sub(r"\s+", " ", lua_text)
    assert '{ "Relabelled mode", "ur.robot_mode_data.robot_mode",' in c_text


def test_value_strings_are_named_in_each_language(model):
    """One enum, spelled by each renderer: no renderer reads another's names."""
    joint_mode = next(e for e in model.enums if e.name == "joint_mode")
    assert lua.value_strings(joint_mode) == "VS.JOINT_MODE"
    assert epan._Builder.vs_name(joint_mode) == "ur_vs_joint_mode"
    if joint_mode.versioned:
        older = joint_mode.tables[0]
        assert lua.value_strings(joint_mode, older) == f"VS.JOINT_MODE_{older.suffix}"
        assert epan._Builder.vs_name(joint_mode, older) == f"ur_vs_joint_mode_{older.suffix.lower()}"
