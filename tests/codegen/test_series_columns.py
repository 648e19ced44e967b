"""Tables with a column per series (RTDE's variables, the dashboard's commands): PolyScope X (10.x)
reads the e-Series column only as far as the spec says it follows it (`polyscope_x_follows:`); a
newer row states its own `polyscope_x:` or is refused at its YAML path (codegen/series.py). The
generator decides each row's PolyScope X version once and every target reads it from its tables."""
from __future__ import annotations

import importlib.util
import re
import sys

import pytest
import yaml

from codegen import series
from codegen.compile import DEFAULT_SPEC, SPEC_DIR, compile_text, kind_of
from codegen.errors import SpecError
from codegen.load import load_text

RTDE = SPEC_DIR / "rtde.yaml"
DASHBOARD = SPEC_DIR / "ur_dashboard.yaml"


def spec_with(path, edit) -> str:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    edit(data)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def problems_of(text: str) -> list[str]:
    with pytest.raises(SpecError) as info:
        compile_text(text, "bad.yaml")
    return [str(p) for p in info.value.problems]


def new_variable(since: dict):
    def edit(data):
        data["variables"].append({"name": "tcp_speed_scaling", "type": "DOUBLE", "direction": "output",
                                  "label": "TCP speed scaling", "since": since})
    return edit


def new_command(since: dict):
    def edit(data):
        data["commands"].append({"name": "get_speed_scaling", "text": "getSpeedScaling", "since": since,
                                 "doc": "A made-up command of 5.27.",
                                 "replies": [{"name": "scaling", "pattern": "Speed scaling: <scaling>"}]})
    return edit


def rendered(text: str, target: str) -> dict:
    """The files one target makes of a spec."""
    return kind_of(load_text(text)).render(compile_text(text), ["test build"], [target])


def generated_module(text: str, tmp_path, name: str):
    """The Python module the spec makes, imported beside the real ones (its imports are relative)."""
    (source,) = rendered(text, "python").values()
    path = tmp_path / f"{name}.py"
    path.write_text(source, encoding="utf-8")
    spec = importlib.util.spec_from_file_location(f"urwire.generated.{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        del sys.modules[spec.name]
    return module


RTDE_ROWS = len(yaml.safe_load(RTDE.read_text(encoding="utf-8"))["variables"])
DASHBOARD_ROWS = len(yaml.safe_load(DASHBOARD.read_text(encoding="utf-8"))["commands"])


# ---- refusals, each at its YAML path ----

@pytest.mark.parametrize("path, edit, at", [
    (RTDE, new_variable({"cb3": "none", "eseries": "5.27"}), f"variables[{RTDE_ROWS}].since"),
    (DASHBOARD, new_command({"e_series": "5.27"}), f"commands[{DASHBOARD_ROWS}].since"),
])
def test_a_row_newer_than_polyscope_x_follows_must_state_its_polyscope_x(path, edit, at):
    (problem,) = problems_of(spec_with(path, edit))
    assert problem.startswith(at + " (line"), problem
    assert "e-Series 5.27 is newer than the last e-Series version PolyScope X is known to follow" in problem
    assert "state `polyscope_x:`" in problem


@pytest.mark.parametrize("path, edit, at", [
    (RTDE, new_variable({"cb3": "none", "eseries": "5.27", "polyscope_x": "5.28"}),
     f"variables[{RTDE_ROWS}].since.polyscope_x"),
    (DASHBOARD, new_command({"e_series": "5.27", "polyscope_x": "9.9"}),
     f"commands[{DASHBOARD_ROWS}].since.polyscope_x"),
])
def test_a_polyscope_x_version_is_a_10x_version(path, edit, at):
    (problem,) = problems_of(spec_with(path, edit))
    assert problem.startswith(at + " (line") and "is not a PolyScope X version (10.0 or later)" in problem, problem


def test_without_polyscope_x_follows_every_e_series_row_states_it():
    text = spec_with(DASHBOARD, lambda data: data["protocol"].pop("polyscope_x_follows"))
    problems = problems_of(text)
    assert len(problems) == sum(1 for c in yaml.safe_load(text)["commands"] if "e_series" in c.get("since", {}))
    assert all("no `polyscope_x_follows:`" in p for p in problems), problems


# ---- what a row made for 5.27 only is offered on ----

def test_an_rtde_variable_of_5_27_alone_is_not_offered_on_10x(tmp_path):
    text = spec_with(RTDE, new_variable({"cb3": "none", "eseries": "5.27", "polyscope_x": "none"}))
    module = generated_module(text, tmp_path, "rtde_made_up")
    (row,) = [v for v in module.VARIABLES if v.name == "tcp_speed_scaling"]
    assert [row.available_in(v) for v in ((5, 26), (5, 27), (5, 99), (10, 0), (10, 13))] == \
        [False, True, True, False, False]
    # The C table carries the same column, decided by the generator: the row's first versions are
    # indices in rtde__variable_words, whose lines name their words.
    source = rendered(text, "c")["c/rtde.c"]
    (since,) = re.findall(r"\{\d+, \d+, RTDE_VT_DOUBLE, true, 0, \{(\d+), (\d+), (\d+)\}\},  /\* tcp_speed_scaling \*/",
                          source)
    words = source.split("rtde__variable_words[] = {", 1)[1].split("};", 1)[0]
    words = re.findall(r"^    \d+,  /\* (.*) \*/$", words, re.M)
    assert [words[int(i)] for i in since] == ["none", "5.27", "none"] and '"TCP speed scaling\\0"' in source


def test_an_rtde_variable_may_come_with_a_later_10x(tmp_path):
    text = spec_with(RTDE, new_variable({"cb3": "none", "eseries": "5.27", "polyscope_x": "10.13"}))
    (row,) = [v for v in generated_module(text, tmp_path, "rtde_later").VARIABLES if v.name == "tcp_speed_scaling"]
    assert [row.available_in(v) for v in ((5, 27), (10, 12), (10, 13), (11, 0))] == [True, False, True, True]


def test_a_dashboard_command_of_5_27_alone_is_not_offered_on_10x(tmp_path):
    from urwire import text_lines

    text = spec_with(DASHBOARD, new_command({"e_series": "5.27", "polyscope_x": "none"}))
    module = generated_module(text, tmp_path, "ur_dashboard_made_up")
    command = module.GET_SPEED_SCALING
    assert [command.available(v) for v in ((3, 15, 0), (5, 26, 0), (5, 27, 0), (10, 0, 0), (10, 13, 0))] == \
        [False, False, True, False, False]
    # As a decoder reads a conversation: the version hint decides.
    for version, available in (("5.27", True), ("10.13", False)):
        conversation = text_lines.LinesConversation(module, version_hint=version)
        (record,) = conversation.feed(b"getSpeedScaling\n", False)
        assert (record.command_name, record.available) == ("get_speed_scaling", available)
    # C, the epan dissector and Lua read the same column: 5.27 in the e-Series', none in PolyScope X's.
    c_source = rendered(text, "c")["c/ur_dashboard.c"]
    assert re.search(r'\{"get_speed_scaling", "getSpeedScaling", false, 0u, 5027000u, 0u,', c_source)
    lua_source = rendered(text, "lua")["lua/ur_dashboard.lua"]
    assert re.search(r"since_cb = nil,\s+since_e_series = 5027000,\s+since_polyscope_x = nil,", lua_source)


# ---- today's rows: on 10.x exactly as before ----

def test_every_row_of_today_is_on_10x_as_on_the_last_e_series():
    """Before its own column, 10.x read the e-Series one: every row kept that reading."""
    from urwire.generated import rtde, ur_dashboard

    for version in ((10, 0, 0), (10, 13, 0)):
        assert [v.available_in(version) for v in rtde.VARIABLES] == [v.available_in((5, 99, 0)) for v in rtde.VARIABLES]
        assert [c.available(version) for c in ur_dashboard.COMMANDS] == \
            [c.available((5, 99, 0)) for c in ur_dashboard.COMMANDS]
    assert sum(v.available_in((10, 13)) is True for v in rtde.VARIABLES) > 500
    assert not ur_dashboard.SET_USER_ROLE.available((10, 13, 0))   # CB-series alone, as before


def test_polyscope_x_follows_is_the_newest_e_series_version_of_each_table():
    for path, key, column in ((RTDE, "variables", "eseries"), (DASHBOARD, "commands", "e_series")):
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
        newest = max((tuple(map(int, r["since"][column].split("."))) for r in data[key]
                      if r.get("since", {}).get(column, "unknown") != "unknown"))
        assert tuple(map(int, data["protocol"]["polyscope_x_follows"].split("."))) == newest, path.name


def test_the_series_starts_are_the_primary_specs():
    generations = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))["protocol"]["generations"]
    starts = {g["name"]: g["versions"]["from"] for g in generations}
    assert (starts["e-Series"], starts["PolyScope X"]) == \
        tuple(".".join(map(str, v[:2])) for v in (series.E_SERIES_FROM, series.POLYSCOPE_X_FROM))
