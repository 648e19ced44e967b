"""The sized-packets kind (spec/ur_realtime.yaml): its resolver checks sizes and names with their
YAML paths, its plan places every field, and the same_size rule picks a layout by version."""
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from codegen import ir
from codegen.compile import SPEC_DIR, compile_file, compile_text
from codegen.errors import SpecError
from codegen.kinds.sized_packets.plan import choose, plan

SPEC = SPEC_DIR / "ur_realtime.yaml"
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def planned():
    return plan(compile_file(SPEC))


def _spec_with(change) -> str:
    data = yaml.safe_load(SPEC.read_text(encoding="utf-8"))
    change(data)
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def _problems(change) -> list:
    with pytest.raises(SpecError) as caught:
        compile_text(_spec_with(change), "probe.yaml")
    return caught.value.problems


def test_every_layout_size_is_its_fields_and_size_field(planned):
    sizes = {lp.layout.name: lp.layout.size for lp in planned.layouts}
    # UR's sheets and the drivers' classes: 756 (1.5), 812 (1.8), 1044 (3.0), 1060 (3.2), 1108, 1116
    assert sizes == {"rt_540": 540, "rt_692": 692, "rt_1_5": 756, "rt_1_6": 764, "rt_1_8": 812,
                     "rt_3_0": 1044, "rt_3_2": 1060, "rt_3_5": 1108, "rt_3_10": 1116, "rt_5_10": 1220}
    for lp in planned.layouts:
        assert 4 + 8 * lp.doubles == lp.layout.size


def test_offsets_follow_the_document(planned):
    rt = {lp.layout.name: {s.field.name: s for s in lp.slots} for lp in planned.layouts}
    # RealTime 5.9: q actual is gnuplot columns 32-37, after the size field and 31 doubles.
    assert rt["rt_3_10"]["q_actual"].offset == 4 + 31 * 8
    assert rt["rt_3_10"]["robot_mode"].offset == 4 + 94 * 8      # column 95
    assert rt["rt_3_10"]["safety_status"].offset == 4 + 138 * 8  # column 139, the last
    # CB2: TCP force comes after the accelerometer and 15 unused doubles.
    assert rt["rt_1_8"]["tcp_force"].offset == 4 + (1 + 48 + 3 + 15) * 8
    assert rt["rt_1_8"]["joint_modes"].count == 6


def test_extends_takes_the_older_layouts_fields_first(planned):
    names = {lp.layout.name: [s.field.name for s in lp.slots] for lp in planned.layouts}
    assert names["rt_3_2"][:-2] == names["rt_3_0"]
    assert names["rt_5_10"][-4:] == ["unused_5", "payload_mass", "payload_cog", "payload_inertia"]


def test_same_size_rule_takes_the_version_else_the_newest(planned):
    assert choose(planned, 1108, (3, 6, 0)).describe() == "3.5 to 3.9"
    assert choose(planned, 1108, (5, 2, 0)).describe() == "5.0 to 5.3"
    assert choose(planned, 1108, None).describe() == "5.0 to 5.3"
    assert choose(planned, 1108, (1, 8, 0)).describe() == "5.0 to 5.3"   # no range holds it
    assert choose(planned, 1220, None).describe() == "5.10 and later"
    assert choose(planned, 1000, None) is None


def test_forms_read_enum_codes_of_their_generation(planned):
    cb3, eseries = (planned.forms[i] for i in planned.by_size[1116])
    assert "PART_D_CALIBRATION" in [v.name for v in cb3.tables["joint_mode"].values]
    assert "READY_FOR_POWER_OFF" in [v.name for v in eseries.tables["joint_mode"].values]
    cb2 = planned.forms[planned.by_size[812][0]]
    assert cb2.tables["robot_mode"].values[0].name == "RUNNING" and cb2.tables["robot_mode"].values[0].value == 0


def test_a_size_that_is_not_the_fields_is_named_at_its_line():
    problems = _problems(lambda d: d["layouts"]["rt_3_0"].update(size=1040))
    (p,) = problems
    assert p.path == "layouts.rt_3_0.size" and p.line and "1044" in p.message


def test_unknown_field_and_unknown_extends_are_named():
    def change(d):
        d["layouts"]["rt_1_5"]["fields"].append("q_nowhere")
        d["layouts"]["rt_1_6"]["extends"] = "rt_9_9"
    paths = {p.path for p in _problems(change)}
    assert "layouts.rt_1_5.fields[3]" in paths and "layouts.rt_1_6.extends" in paths


def test_two_layouts_of_one_size_must_not_share_a_version():
    def change(d):
        d["layouts"]["rt_1_6"]["size"] = 812
        d["layouts"]["rt_1_6"]["fields"] = ["robot_mode", "joint_modes"]
        d["layouts"]["rt_1_6"]["versions"] = [{"from": "1.8", "until": "1.8"}]
    problems = _problems(change)
    assert any(p.path == "layouts.rt_1_8.versions" and "shares size 812" in p.message for p in problems)


def test_the_schema_refuses_a_field_of_another_type():
    problems = _problems(lambda d: d["fields"][0].update(type="int32"))
    assert problems[0].path.startswith("fields[0]")


def test_fields_are_the_primary_irs_own():
    model = compile_file(SPEC)
    q = next(f for f in model.layouts[-1].fields if f.name == "q_actual")
    assert isinstance(q, ir.ArrayField) and (q.label, q.unit, q.count) == ("Actual joint position", "rad", 6)


def _range_words(r: dict) -> str:
    low, high = r.get("from"), r.get("until")
    if low and high:
        return low if low == high else f"{low} to {high}"
    return f"up to {high}" if high else f"from {low}"


def test_the_real_time_page_lists_every_layout_as_the_spec_has_it():
    """docs/realtime.md's table of sizes and versions is the spec's, row for row."""
    import re

    spec = yaml.safe_load((SPEC_DIR / "ur_realtime.yaml").read_text(encoding="utf-8"))
    want = [(str(lay["size"]), f"`{name}`", ", ".join(_range_words(r) for r in lay["versions"]))
            for name, lay in spec["layouts"].items()]
    page = (SPEC_DIR.parent / "docs" / "realtime.md").read_text(encoding="utf-8")
    rows = [tuple(cell.strip() for cell in line.strip("|").split("|"))
            for line in page.splitlines() if re.match(r"\| \d+ \|", line)]
    assert rows == want


def test_a_field_named_like_the_size_field_is_refused_by_target_c(tmp_path):
    """The size field is ur_realtime.message_size in both dissectors, beside every field; a field of
    that name would make two fields of one filter name. The C target renders no dissector and still
    refuses the spec, at the field's YAML path."""
    def rename(data):
        data["fields"][0]["name"] = data["framing"]["size"]["name"]
    bad = tmp_path / "ur_realtime.yaml"
    bad.write_text(_spec_with(rename), encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "codegen", "--spec", str(bad), "--target", "c",
                             "--out", str(tmp_path / "out")], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode != 0
    assert "fields[0].name" in result.stderr, result.stderr
    assert "ur_realtime.message_size is the size field's filter name" in result.stderr


def _field(d, name):
    return next(f for f in d["fields"] if f["name"] == name)


def test_a_pose_without_item_names_cannot_share_its_two_units():
    (p,) = _problems(lambda d: _field(d, "tool_vector_actual").pop("item_names"))
    assert p.path.endswith(".unit") and "needs item_names" in p.message


def test_item_names_of_another_count_and_bits_on_a_vector_are_refused():
    def change(d):
        _field(d, "elbow_position")["item_names"] = "joints"
        _field(d, "q_actual")["bits"] = ["a"]
    messages = [p.message for p in _problems(change)]
    assert any("'joints' names 6 items, the vector has 3" in m for m in messages)
    assert any("bits need one double" in m for m in messages)


def test_the_items_take_the_parts_of_the_unit_in_runs(planned):
    items = planned.protocol.items
    assert [(i.label, i.unit) for i in items["tcp_speed_actual"]][2:4] == [("Z", "m/s"), ("RX", "rad/s")]
    assert [i.label for i in items["joint_modes"]][-1] == "Wrist 3" and items["joint_modes"][0].unit is None
    assert [b.mask for b in planned.protocol.bits["digital_outputs"]][:3] == [1, 2, 4]
