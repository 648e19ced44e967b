"""The C target's robot-state fast paths (codegen/kinds/packages/c.py fast_paths): which rows of forms
get a loop of their own, what each case checks, which segments take each loop, and that a newer
version takes no loop away from an older one. Which version is the newest is read from the spec."""
from __future__ import annotations

import pytest
import yaml

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_file, compile_text
from codegen.kinds.packages.pin import pin
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import c as c_target


@pytest.fixture(scope="module")
def planned():
    return plan(compile_file(DEFAULT_SPEC))


@pytest.fixture(scope="module")
def built(planned):
    return c_target.build(planned)


def segment_of(built, version: ir.Version) -> int:
    """The segment the C tables (urwire__segment_bounds) put `version` in."""
    starts = [(-1, 0, 0) if b["kind"] == "lowest" else (b["first"]["major"], b["first"]["minor"], b["first"]["bugfix"])
              for b in built["segment_bounds"]]
    return max(k for k, start in enumerate(starts) if start <= version)


def path_of(built, version: ir.Version) -> dict | None:
    number = built["package_fast"]["of_segment"][segment_of(built, version)]
    return next((p for p in built["package_fast"]["paths"] if p["number"] == number), None)


def row_of(built, path: dict) -> tuple:
    """What a fast path reads, without the numbers that a new form elsewhere shifts: each type's
    form (layout, exact sizes, least size, and whether it is the nearest below's), and each
    case's check."""
    listed = [f for c in built["package_forms"]["codes"] for f in c["forms"]]
    forms = []
    for type_code, n in enumerate(path["forms"]):
        if n:
            f = listed[(n & ~c_target.NEAREST_BIT) - 1]
            forms.append((type_code, f["layout"], tuple(f["sizes"][:f["nsizes"]]), f["min_size"],
                          bool(n & c_target.NEAREST_BIT)))
    cases = [(c["type"], c["member"], c["layout"], c["check"], c["size"]) for c in path["cases"]]
    return tuple(forms), tuple(cases)


def case_of(built, version: ir.Version, member: str) -> tuple:
    """The fast path's case for `member` at `version`: its type, check and size."""
    case = next(c for c in path_of(built, version)["cases"] if c["member"] == member)
    return case["type"], case["check"], case["size"]


def sends_forms(row: dict) -> bool:
    """A segment some released version sends: not every form is the nearest below's."""
    return any(n["kind"] != "none" for n in row["first"])


def test_every_row_from_the_default_version_on_has_a_fast_path(planned, built):
    fast, rows = built["package_fast"], built["package_forms"]["rows"]
    default = planned.protocol.default_version
    assert fast["default_segment"] == planned.segment_of(default) == segment_of(built, default)
    assert path_of(built, default)["number"] == 1
    for k, row in enumerate(rows):
        number = fast["of_segment"][k]
        if k >= fast["default_segment"] and sends_forms(row):
            assert number, row["versions"]
        if number:
            assert fast["paths"][number - 1]["forms"] == row["forms"], row["versions"]
    # One loop per row; the newest versions (the axis's last segment, and each series' last) have one.
    assert len({tuple(p["forms"]) for p in fast["paths"]}) == len(fast["paths"])
    assert path_of(built, planned.segments[-1].first) is not None
    for _, series in planned.protocol.generations:
        inside = [s.first for s in planned.segments if s.first and series.contains(s.first)]
        if inside[-1] >= default:
            assert path_of(built, inside[-1]) is not None, series
    # Every e-Series from 5.4 to 5.25.0 sends the default's row; 5.25.1 another.
    for version in [(5, 4, 0), (5, 9, 0), (5, 25, 0)]:
        assert path_of(built, version)["number"] == 1, version
    late = path_of(built, (5, 25, 1))
    assert late is not None and late["number"] != 1
    # Older generations, and the gaps between series, go by the general rule alone.
    for version in [(1, 8, 0), (3, 2, 0), (3, 15, 0), (5, 3, 0), (4, 0, 0)]:
        assert path_of(built, version) is None, version


def test_each_case_checks_the_size_of_the_form_its_row_sends(built):
    default = path_of(built, (5, 9, 0))
    assert case_of(built, (5, 9, 0), "configuration_data")[1:] == ("exact", 440)   # 445 bytes with its header
    assert case_of(built, (5, 25, 1), "configuration_data")[1:] == ("exact", 444)  # 449 from 5.25.1
    masterboard = next(c for c in default["cases"] if c["member"] == "masterboard_data")
    assert (masterboard["check"], masterboard["size"]) == ("exact", 70)  # 75 bytes, no euromap
    # An open-ended form with no least size needs no check at all.
    safety = next(c for c in default["cases"] if c["member"] == "safety_data")
    assert safety["check"] == "any"
    # One case per sub-package type that the row sends, each with one decoder.
    assert len({c["type"] for c in default["cases"]}) == len(default["cases"]) == 15


def test_a_pinned_build_has_the_one_row_of_its_version():
    pinned = c_target.build(plan(pin(compile_file(DEFAULT_SPEC), (3, 15, 0))))
    (path,) = pinned["package_fast"]["paths"]
    assert {c["member"] for c in path["cases"]} >= {"robot_mode_data", "joint_data", "masterboard_data"}


def newer_in(planned, series: str) -> ir.Version:
    """A made-up firmware of `series` past every form the spec knows there: two minor releases after
    the newest one (5.27 while 5.25.1 is the e-Series' newest), so that a real newer firmware added
    to the spec moves it on."""
    (versions,) = [r for name, r in planned.protocol.generations if name == series]
    major, minor, _ = [s.first for s in planned.segments if s.first and versions.contains(s.first)][-1]
    return major, minor + 2, 0


def with_a_field_from(version: ir.Version, until: str | None) -> dict:
    """The C build of the spec with a made-up `version` that appends a float64 to additional_info
    (up to `until`, else to the end of the axis: then `version` must be in the last series)."""
    data = yaml.safe_load(DEFAULT_SPEC.read_text(encoding="utf-8"))
    versions = {"from": ir.version_text(version)} | ({"until": until} if until else {})
    data["messages"]["robot_state"]["packages"]["additional_info"]["fields"].append(
        {"name": "made_up_float", "label": "Made-up float", "type": "float64", "versions": versions})
    return c_target.build(plan(compile_text(yaml.safe_dump(data, sort_keys=False))))


@pytest.mark.parametrize("series,until,into_polyscope_x", [
    ("e-Series", "5.99", False),        # the e-Series alone
    ("e-Series", "10.99", True),        # on into PolyScope X, whose later versions send what they did
    ("PolyScope X", None, True)])       # the axis's last row: where "the newest" loop used to move
def test_a_newer_version_keeps_every_older_versions_fast_path(planned, built, series, until, into_polyscope_x):
    """Adding a version never changes what older ones get: every version that had a loop has one,
    on the same row below the new version; the new version has one of its own (today one more
    loop: its flash cost, docs/c.md)."""
    newer = newer_in(planned, series)
    grown = with_a_field_from(newer, until)
    just_before = (newer[0], newer[1] - 1, 0)
    versions = {s.first for s in planned.segments if s.first} | {just_before, (5, 99, 0), (10, 13, 0), newer}
    for version in sorted(versions):
        before, after = path_of(built, version), path_of(grown, version)
        if before is not None:
            assert after is not None, version
        if version < newer:
            assert (after is None) == (before is None), version
            if before is not None:
                assert row_of(grown, after) == row_of(built, before), version
    fresh = path_of(grown, newer)
    assert fresh is not None and row_of(grown, fresh) != row_of(grown, path_of(grown, just_before))
    was = case_of(built, just_before, "additional_info")[2]
    assert case_of(grown, newer, "additional_info")[1:] == ("exact", was + 8)   # and the float64
    assert len(grown["package_fast"]["paths"]) > len(built["package_fast"]["paths"])   # each new row, a loop
    # PolyScope X sends the new field only where it runs on into it.
    polyscope_x = max(newer, (10, 13, 0))
    grew = case_of(grown, polyscope_x, "additional_info")[2] - case_of(built, polyscope_x, "additional_info")[2]
    assert grew == (8 if into_polyscope_x else 0)


def test_the_spec_diff_says_whether_two_versions_take_the_same_loop(planned):
    """`make spec-diff` names the loop each version takes, so that a new version's loop shows."""
    assert c_target.fast_path_change(planned, (5, 4, 0), (5, 25, 0)) == \
        "C robot-state fast path: the same, loop 1 (5.4 to 5.25.0)"
    assert c_target.fast_path_change(planned, (3, 15, 0), (5, 9, 0)) == \
        "C robot-state fast path: none (the general rule) -> loop 1 (5.4 to 5.25.0)"
    assert c_target.fast_path_change(planned, (5, 25, 0), (5, 25, 1)).startswith(
        "C robot-state fast path: loop 1 (5.4 to 5.25.0) -> loop 2 (5.25.1 to ")
