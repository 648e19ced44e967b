"""The C target's robot-state fast paths (codegen/kinds/packages/c.py fast_paths): which rows of forms
get a loop of their own, what each case checks, and which segments take each loop."""
from __future__ import annotations

import pytest

from codegen import ir
from codegen.compile import DEFAULT_SPEC, compile_file
from codegen.kinds.packages.pin import pin
from codegen.kinds.packages.plan import plan
from codegen.kinds.packages import c as c_target


@pytest.fixture(scope="module")
def built():
    return c_target.build(plan(compile_file(DEFAULT_SPEC)))


def segment_of(built, version: ir.Version) -> int:
    starts = [(-1, 0, 0) if b["kind"] == "lowest" else (b["first"]["major"], b["first"]["minor"], b["first"]["bugfix"])
              for b in built["segment_bounds"]]
    return max(k for k, start in enumerate(starts) if start <= version)


def path_of(built, version: ir.Version) -> dict | None:
    number = built["package_fast"]["of_segment"][segment_of(built, version)]
    return next((p for p in built["package_fast"]["paths"] if p["number"] == number), None)


def test_the_default_version_and_the_newest_layouts_have_a_fast_path(built):
    fast = built["package_fast"]
    assert [p["number"] for p in fast["paths"]] == [1, 2]
    assert fast["default_segment"] == segment_of(built, (5, 9, 0))
    # Every e-Series from 5.4 to 5.25.0 sends the default's row; 5.25.1 on and PolyScope X the newest.
    for version in [(5, 4, 0), (5, 9, 0), (5, 25, 0)]:
        assert path_of(built, version)["number"] == 1, version
    for version in [(5, 25, 1), (5, 26, 0), (10, 13, 0)]:
        assert path_of(built, version)["number"] == 2, version
    # Older generations, and the gaps between series, go by the general rule alone.
    for version in [(1, 8, 0), (3, 2, 0), (3, 15, 0), (5, 3, 0), (4, 0, 0)]:
        assert path_of(built, version) is None, version


def test_each_case_checks_the_size_of_the_form_its_row_sends(built):
    one, two = built["package_fast"]["paths"]
    config = {p["number"]: next(c for c in p["cases"] if c["member"] == "configuration_data") for p in (one, two)}
    assert (config[1]["check"], config[1]["size"]) == ("exact", 440)   # 445 bytes with its header
    assert (config[2]["check"], config[2]["size"]) == ("exact", 444)   # 449 from 5.25.1
    masterboard = next(c for c in one["cases"] if c["member"] == "masterboard_data")
    assert (masterboard["check"], masterboard["size"]) == ("exact", 70)  # 75 bytes, no euromap
    # An open-ended form with no least size needs no check at all.
    safety = next(c for c in one["cases"] if c["member"] == "safety_data")
    assert safety["check"] == "any"
    # One case per sub-package type that the row sends, each with one decoder.
    assert len({c["type"] for c in one["cases"]}) == len(one["cases"]) == 15


def test_a_pinned_build_has_the_one_row_of_its_version():
    pinned = c_target.build(plan(pin(compile_file(DEFAULT_SPEC), (3, 15, 0))))
    (path,) = pinned["package_fast"]["paths"]
    assert {c["member"] for c in path["cases"]} >= {"robot_mode_data", "joint_data", "masterboard_data"}
