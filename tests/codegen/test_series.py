"""A version range states the series it runs through (codegen/series.py): a change opened in one
series reaches the next only where the spec says so, and every refusal names its YAML path."""
from __future__ import annotations

import importlib
import re
import struct
import sys

import pytest
import yaml

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_text
from codegen.errors import SpecError
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages.reference import diff, forms_at

SPEC_TEXT = DEFAULT_SPEC.read_text(encoding="utf-8")
SPEC = yaml.safe_load(SPEC_TEXT)
ADDITIONAL_INFO = "messages.robot_state.packages.additional_info"
NEW_FIELD = f"{ADDITIONAL_INFO}.fields[{len(SPEC['messages']['robot_state']['packages']['additional_info']['fields'])}]"
LAST_SERIES = SPEC["protocol"]["generations"][-1]["name"]


def _newest_e_series_minor() -> int:
    """The newest e-Series minor version any `from:` of the spec names, so that the made-up
    version below stays newer than every real one when a firmware is added."""
    minors = [int(v.split(".")[1]) for v in re.findall(r'from: "(5\.[0-9]+)', SPEC_TEXT)]
    return max(minors)


# A made-up firmware two minor releases past the newest the spec knows, and one between them.
NEW = f"5.{_newest_e_series_minor() + 2}"
BEFORE = f"5.{_newest_e_series_minor() + 1}"
NEW_V = ir.parse_version(NEW)


def with_field(versions: dict) -> str:
    """The real spec with a made-up float64 appended to additional info, as a new firmware would."""
    data = yaml.safe_load(SPEC_TEXT)
    data["messages"]["robot_state"]["packages"]["additional_info"]["fields"].append(
        {"name": "made_up_scaling", "label": "Made-up scaling", "type": "float64", "versions": versions})
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def problems_of(text: str) -> list[str]:
    with pytest.raises(SpecError) as info:
        compile_text(text, "bad.yaml")
    return [str(p) for p in info.value.problems]


def new_field(protocol) -> ir.AnyField:
    (layout,) = [lay for lay in protocol.all_layouts() if lay.name == "additional_info"]
    return layout.struct.field("made_up_scaling")


def additional_info_fields(planned, version: str) -> list[str]:
    form = next(f for f in forms_at(planned, ir.parse_version(version)).values() if f.layout == "additional_info")
    return [name for name, _ in form.fields]


# ---- refusals, each at its YAML path ----

@pytest.mark.parametrize("versions, path, words", [
    # An open range outside the last series: the later series and the two ways to say it.
    ({"from": NEW}, NEW_FIELD + ".versions",
     [f'{{from: "{NEW}"}} has no end', "into PolyScope X", 'through: "e-Series"', 'through: "PolyScope X"']),
    ({"from": "3.5"}, NEW_FIELD + ".versions",
     ["into e-Series and PolyScope X", 'through: "CB3"', 'through: "PolyScope X"']),
    ({"from": NEW, "until": "5.99", "through": "e-Series"}, NEW_FIELD + ".versions",
     ["either `until:`", "or `through:`", "not both"]),
    ({"from": NEW, "through": "e-series"}, NEW_FIELD + ".versions.through",
     ["'e-series' is not a series", "e-Series: 5.0 to 5.99"]),
    ({"from": NEW, "through": "CB3"}, NEW_FIELD + ".versions.through",
     [f"CB3 ends before {NEW} (e-Series) starts"]),
    ({"from": "4.2", "through": "e-Series"}, NEW_FIELD + ".versions.from", ["4.2 lies in no series"]),
    ({"from": "3.5", "until": "3.16"}, NEW_FIELD + ".versions.until", ["3.16 lies in no series"]),
    ({"until": "2.0"}, NEW_FIELD + ".versions.until", ["2.0 lies in no series", "CB2: 1.0 to 1.8"]),
])
def test_a_range_that_is_ambiguous_across_series_is_refused_at_its_path(versions, path, words):
    problems = problems_of(with_field(versions))
    assert any(p.startswith(path + " (line") and all(w in p for w in words) for p in problems), problems


def test_an_open_range_is_refused_in_enums_and_tables_too():
    data = yaml.safe_load(SPEC_TEXT)
    data["enums"]["robot_mode"]["tables"][1]["versions"] = {"from": "3.0"}
    (member,) = [v for v in data["enums"]["package_type"]["values"] if v["name"] == "KINEMATICS_INFO"]
    member["versions"] = {"from": "1.8"}
    problems = problems_of(yaml.safe_dump(data, sort_keys=False, allow_unicode=True))
    assert any(p.startswith("enums.robot_mode.tables[1].versions (line") and 'through: "CB3"' in p for p in problems)
    assert any(p.startswith("enums.package_type.values[6].versions (line") and 'through: "CB2"' in p
               and "into CB3, e-Series and PolyScope X" in p for p in problems), problems


def test_the_real_time_spec_keeps_the_same_rule():
    """spec/ur_realtime.yaml declares the same series: its three ranges that run on into 10.x say so."""
    path = DEFAULT_SPEC.parent / "ur_realtime.yaml"
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    enums = data["enums"]
    assert enums["robot_mode"]["tables"][1]["versions"] == {"from": "3.0", "through": LAST_SERIES}
    assert enums["joint_mode"]["tables"][2]["versions"] == {"from": "5.0", "through": LAST_SERIES}
    assert data["layouts"]["rt_5_10"]["versions"] == [{"from": "5.10", "through": LAST_SERIES}]
    # An open range is refused where it would leak; split at a series' end, the same reach is accepted.
    enums["joint_mode"]["tables"][2]["versions"] = {"from": "5.0"}
    data["layouts"]["rt_5_10"]["versions"] = [{"from": "5.10", "through": "e-Series"}, {"from": "10.0"}]
    problems = problems_of(yaml.safe_dump(data, sort_keys=False, allow_unicode=True))
    assert [p.split(" (line")[0] for p in problems] == ["enums.joint_mode.tables[2].versions"], problems
    assert 'through: "e-Series"' in problems[0] and "into PolyScope X" in problems[0]


def test_series_must_follow_one_another():
    data = yaml.safe_load(SPEC_TEXT)
    data["protocol"]["generations"][2]["versions"] = {"from": "3.10", "until": "5.99"}
    problems = problems_of(yaml.safe_dump(data, sort_keys=False, allow_unicode=True))
    assert any(p.startswith("protocol.generations[2].versions") and "e-Series must start after CB3 ends" in p
               for p in problems), problems


# ---- what a range stated per series covers ----

def test_a_range_through_a_series_ends_with_it_in_the_model_and_the_plan():
    protocol = compile_text(with_field({"from": NEW, "through": "e-Series"}))
    assert new_field(protocol).versions == ir.VersionRange(NEW_V, ir.parse_version("5.99", upper=True))
    planned = plan(protocol)
    assert "made_up_scaling" in additional_info_fields(planned, NEW)
    assert "made_up_scaling" not in additional_info_fields(planned, BEFORE)
    assert "made_up_scaling" not in additional_info_fields(planned, "10.13")
    # make spec-diff says where it goes away.
    assert "  - made_up_scaling: float64" in diff(planned, NEW_V, (10, 13, 0))


def test_a_range_through_the_last_series_runs_on():
    protocol = compile_text(with_field({"from": NEW, "through": LAST_SERIES}))
    assert new_field(protocol).versions == ir.VersionRange(NEW_V, None)
    planned = plan(protocol)
    assert "made_up_scaling" in additional_info_fields(planned, NEW)
    assert "made_up_scaling" in additional_info_fields(planned, "10.13")
    assert not any("made_up_scaling" in line for line in diff(planned, NEW_V, (10, 13, 0)))


def test_an_open_range_in_the_last_series_and_a_range_through_an_earlier_one_are_allowed():
    compile_text(with_field({"from": "10.14"}))
    protocol = compile_text(with_field({"through": "CB3"}))
    assert new_field(protocol).versions == ir.VersionRange(None, ir.parse_version("3.15", upper=True))


def test_the_real_spec_opens_no_range_outside_the_last_series():
    last = SPEC["protocol"]["generations"][-1]["versions"]
    assert "until" not in last

    def ranges(node, path):
        if isinstance(node, dict):
            for key, value in node.items():
                if key == "versions" and isinstance(value, dict) and path[:2] != ["protocol", "generations"]:
                    yield path + [key], value
                else:
                    yield from ranges(value, path + [key])
        elif isinstance(node, list):
            for i, item in enumerate(node):
                yield from ranges(item, path + [i])

    written = list(ranges(SPEC, []))
    assert len(written) > 40
    open_before_last = [path for path, r in written if "from" in r and "until" not in r and "through" not in r
                        and ir.parse_version(r["from"]) < ir.parse_version(last["from"])]
    assert open_before_last == []


# ---- what the decoders make of it ----

def decoded_additional_info(tmp_path, versions: dict, body: bytes, version: str):
    """Decode one additional-info package with bindings generated from the spec with the new field."""
    from tests.codegen.test_version_gates import render_variant

    def edit(data):
        data.clear()
        data.update(yaml.safe_load(with_field(versions)))
    root = render_variant(tmp_path, edit)
    (code,) = [v["value"] for v in SPEC["enums"]["package_type"]["values"] if v["name"] == "ADDITIONAL_INFO"]
    pkg = struct.pack(">iB", 5 + len(body), code) + body
    saved = {k: v for k, v in sys.modules.items() if k == "urwire" or k.startswith("urwire.")}
    for k in saved:
        del sys.modules[k]
    sys.path.insert(0, str(root))
    try:
        stream = struct.pack(">iB", 5 + len(pkg), 16) + pkg
        (message,) = importlib.import_module("urwire").decode_stream(stream, version)
        return message.packages[0]
    finally:
        sys.path.remove(str(root))
        for k in [k for k in sys.modules if k == "urwire" or k.startswith("urwire.")]:
            del sys.modules[k]
        sys.modules.update(saved)


@pytest.mark.deep          # generates and builds a whole parser: `make test-deep`
def test_a_10x_stream_keeps_its_layout_when_the_change_ends_with_the_e_series(tmp_path):
    (layout,) = [lay for lay in compile_text(SPEC_TEXT).all_layouts() if lay.name == "additional_info"]
    today = bytes(layout.struct.at((10, 13, 0)).fixed_size)
    scaled = bytes(layout.struct.at(NEW_V).fixed_size) + struct.pack(">d", 0.5)
    through_e_series = {"from": NEW, "through": "e-Series"}
    assert decoded_additional_info(tmp_path / "a", through_e_series, scaled, NEW).made_up_scaling == 0.5
    on_10x = decoded_additional_info(tmp_path / "b", through_e_series, today, "10.13")
    assert on_10x.made_up_scaling is None and on_10x.decoded_version == (10, 13, 0) and on_10x.extra == b""
    # Through PolyScope X, the same 10.13 bytes no longer fit 10.13's layout: the length picks an older one.
    leaked = decoded_additional_info(tmp_path / "c", {"from": NEW, "through": LAST_SERIES}, today, "10.13")
    assert leaked.made_up_scaling is None and leaked.decoded_version < NEW_V
