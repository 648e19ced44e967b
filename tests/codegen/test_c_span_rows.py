"""The C target's span tables (codegen/kinds/packages/c.py Run.rows): a group's elements after
the first are one repeat row, which urwire__short_in_run expands as written here; every table of
the spec gives back its spans, and the groups of joint data and kinematics info are folded."""
from __future__ import annotations

import pytest

from codegen.compile import DEFAULT_SPEC, compile_file
from codegen.kinds.packages import c as c_target
from codegen.kinds.packages.plan import plan


def expand(rows: list[dict]) -> list[tuple]:
    """The spans a table's rows stand for, as (path, offset, size, index), in the order
    urwire__short_in_run tries them."""
    out: list[tuple] = []
    for k, row in enumerate(rows):
        if not row["repeat"]:
            out.append((row["path"], row["offset"], row["size"], row["index"]))
            continue
        block = rows[k - row["index"]:k]
        out += [(r["path"], r["offset"] + n * row["offset"], r["size"], n) for n in range(1, row["size"]) for r in block]
    return out


@pytest.fixture(scope="module")
def runs() -> dict[str, c_target.Run]:
    return {r.table: r for s in c_target.build(plan(compile_file(DEFAULT_SPEC)))["structs"] for r in s.runs}


def test_every_table_gives_back_its_spans(runs):
    for run in runs.values():
        assert expand(run.rows) == [(s.template, s.offset, s.size, s.index) for s in run.spans], run.table


def test_groups_are_folded(runs):
    joints = runs["urwire__joint_data_run0"]
    assert len(joints.spans) == 48 and len(joints.rows) == 9
    assert joints.rows[-1] == dict(path=None, path_c="NULL", offset=41, size=6, size_c="URWIRE__REPEAT | 6", index=8,
                                   repeat=True)
    assert len(runs["urwire__kinematics_info_run0"].rows) == 11       # five arrays of 6, and a field
    assert sum(len(r.rows) for r in runs.values()) < 0.7 * sum(len(r.spans) for r in runs.values())


def test_a_group_that_does_not_repeat_stays_as_it_is():
    spans = [c_target.Span("a[0]", 0, 4), c_target.Span("b[0]", 4, 2), c_target.Span("b[1]", 6, 2),
             c_target.Span("c", 8, 1)]
    rows = c_target.Run("t", spans).rows
    assert expand(rows) == [(s.template, s.offset, s.size, s.index) for s in spans]
