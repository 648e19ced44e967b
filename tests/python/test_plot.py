"""`urwire plot` takes only numeric fields of the spec, and says which it can plot."""
from __future__ import annotations

from pathlib import Path

import pytest

from tests.python.test_cli import urwire

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "primary_session.pcapng"


@pytest.mark.parametrize("field", ["version.project_name", "joint_data.no_such_field", "no_such_kind.q_actual",
                                   "joint_data", "key.title"])
def test_a_field_it_cannot_plot_exits_2_and_lists_those_it_can(tmp_path, field):
    out = tmp_path / "plot.png"
    result = urwire("plot", str(SAMPLE), "--field", field, "--out", str(out))
    assert result.returncode == 2, result.stderr
    message = result.stderr.decode()
    assert "Traceback" not in message and field in message
    assert "fields it can plot" in message
    assert not out.exists()


def test_the_list_holds_the_numeric_fields_of_the_kind_asked_for(tmp_path):
    message = urwire("plot", str(SAMPLE), "--field", "joint_data.nothing", "--out", str(tmp_path / "p.png")).stderr
    listed = message.decode().rsplit(": ", 1)[1].strip().split(", ")
    assert {"joint_data.q_actual", "joint_data.t_motor", "joint_data.joint_mode"} <= set(listed)
    assert all(name.startswith("joint_data.") for name in listed)


def test_plottable_fields_are_the_numeric_fields_of_the_generated_classes():
    from urwire.data import plot

    fields = plot.plottable_fields()
    assert "joint_data.q_actual" in fields and "tool_data.tool_current" in fields
    assert "robot_mode_data.timestamp" in fields and "version.major_version" in fields
    assert "version.project_name" not in fields and "key.title" not in fields


def test_a_numeric_field_plots(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "plot.png"
    result = urwire("plot", str(SAMPLE), "--field", "joint_data.q_actual", "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert out.stat().st_size > 0 and b"6 lines" in result.stderr
