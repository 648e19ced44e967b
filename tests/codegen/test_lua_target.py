"""The Lua target's builder hands the template data, and the template refuses what it cannot
render: an unknown descriptor kind or field shape is an error at generation time, not a broken
dissector. Constants reach the runtime through the generated `spec` table."""
from __future__ import annotations

import copy
import dataclasses

import jinja2
import pytest

from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.plan import plan
from codegen.targets import lua
from codegen.view import Step


@pytest.fixture(scope="module")
def protocol():
    return compile_text(DEFAULT_SPEC.read_text(encoding="utf-8"))


def test_an_unknown_descriptor_kind_is_an_error(protocol, monkeypatch):
    real = lua._Builder.descriptor

    def descriptor(self, owner, f, doc, path, keep, show):
        step = real(self, owner, f, doc, path, keep, show)
        return Step("tlv", step.data) if path == "tool_temperature" else step

    monkeypatch.setattr(lua._Builder, "descriptor", descriptor)
    with pytest.raises(jinja2.UndefinedError, match="tlv"):
        lua.render(plan(protocol), ["test"])


def test_an_unknown_field_shape_is_an_error(protocol, monkeypatch):
    real = lua._Builder.add_field

    def add_field(self, pf, *where):
        if pf.key == "robot_mode_data.timestamp":
            pf = dataclasses.replace(pf, shape="timestamp")
        return real(self, pf, *where)

    monkeypatch.setattr(lua._Builder, "add_field", add_field)
    with pytest.raises(jinja2.UndefinedError, match="timestamp"):
        lua.render(plan(protocol), ["test"])


def test_every_runtime_file_is_joined_in_a_known_order(monkeypatch):
    monkeypatch.setattr(lua, "RUNTIME", lua.RUNTIME[:-1])
    with pytest.raises(ValueError, match="joining order"):
        lua.runtime()


def test_constants_come_from_the_spec(protocol):
    p = copy.deepcopy(protocol)
    p.default_version = (5, 12, 0)
    p.ports = [40000, 40001]
    p.max_message_length = 4096
    p.max_value_depth = 3
    text = lua.render(plan(p), ["test"])[lua.OUT]
    spec_table = text[text.index("local spec = {"):text.index("local rt = {}")]
    for expected in ('default_version = "5.12"', 'default_ports = "40000,40001"', "max_message_length = 4096",
                     "max_value_depth = 3", "header_size = 5", "package_header_size = 5"):
        assert expected in spec_table, expected


def test_the_template_is_mostly_data():
    template = (lua.TEMPLATES / "lua" / "urwire.lua.j2").read_text(encoding="utf-8")
    assert len(template.splitlines()) < 600
    for statement in ("function", "while ", "local function"):
        assert statement not in template.replace("(function(...)", ""), statement
