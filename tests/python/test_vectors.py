"""Every golden vector and conformance case decodes to its expected canonical records."""
from __future__ import annotations

import pytest
import urwire

from tests.vectors import all_cases, mismatches

CASES = all_cases()


def decode(case) -> list[dict]:
    return [urwire.to_dict(r) for r in urwire.decode_stream(case.data, case.version)]


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_case_decodes_to_expected_records(case):
    problems = mismatches(case.expect, decode(case), partial=case.partial, tolerance=case.tolerance)
    assert not problems, "\n".join(problems)


def test_there_is_a_vector_for_every_layout():
    laid_out = {lay.name for lay in urwire_layouts()}
    seen = set()
    for case in CASES:
        for record in decode(case):
            seen.add(record["type"])
            seen.update(p["type"] for p in record.get("packages", []))
    assert laid_out <= seen, laid_out - seen


def urwire_layouts():
    from tests.tools.valid import PROTOCOL
    return PROTOCOL.all_layouts()


def test_the_cb2_packet_decodes_in_the_cb2_layouts():
    """The real CB2 capture has no Version message: the lengths choose the CB2 layouts, which
    read every package exactly (docs/firmware-history.md#sizes-by-version)."""
    (case,) = [c for c in CASES if c.name.endswith("packet")]
    (state,) = decode(case)
    flagged = {p["type"] for p in state["packages"] if "error" in p or "extra" in p}
    assert not flagged, flagged
    assert [p["type"] for p in state["packages"]] == [
        "robot_mode_data", "joint_data", "cartesian_info", "masterboard_data", "tool_data",
        "force_mode_data", "additional_info"]
