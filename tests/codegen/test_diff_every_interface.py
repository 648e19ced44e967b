"""`python -m codegen diff A B --spec S` works for every interface's spec, not only the primary's:
each kind says what one version sends (codegen/version_diff.py), and what it says agrees with the
rule the generated Python applies at run time."""
from __future__ import annotations

import importlib
import subprocess

import pytest

from codegen import ir
from codegen.__main__ import main
from codegen.compile import compile_loaded, kind_of, spec_files
from codegen.kinds.lines.diff import has
from codegen.kinds.typed_messages.diff import offered
from codegen.load import load_file

SPECS = spec_files()
VERSIONS = [(1, 4, 0), (1, 8, 2), (3, 2, 0), (3, 15, 0), (5, 0, 0), (5, 11, 1), (5, 99, 3), (10, 0, 0), (10, 13, 0)]


def kind_and_plan(spec):
    loaded = load_file(spec)
    kind = kind_of(loaded)
    return kind.name, kind.plan(compile_loaded(loaded))


def available(note):
    """A variable's note as the runtime's Variable.available_in says it: True, False, or None
    when its first version is not known."""
    return {"": True, None: False}.get(note)


@pytest.mark.parametrize("spec", SPECS, ids=lambda p: p.stem)
def test_diff_runs_on_every_spec_and_a_version_against_itself_is_no_change(spec, capsys):
    assert main(["diff", "5.9", "5.9", "--spec", str(spec)]) == 0
    assert capsys.readouterr().out.startswith("5.9 -> 5.9: no change\n")


def test_a_spec_that_cannot_be_read_is_said_in_one_line(tmp_path, capsys):
    missing = tmp_path / "no_such_spec.yaml"
    assert main(["diff", "3.1", "3.2", "--spec", str(missing)]) == 2
    assert capsys.readouterr().err == f"{missing}: cannot read the spec: No such file or directory\n"


def test_make_spec_diff_takes_any_interface_spec():
    out = subprocess.run(["make", "-s", "spec-diff", "FROM=3.1", "TO=3.2", "SPEC=spec/ur_realtime.yaml"],
                         capture_output=True, text=True, check=True).stdout
    assert "rt_3_0 (1044 bytes) becomes rt_3_2 (1060 bytes)" in out


@pytest.mark.parametrize("stem, a, b, wanted", [
    ("ur_realtime", "3.1", "3.2", ["~ packet: rt_3_0 (1044 bytes) becomes rt_3_2 (1060 bytes)",
                                   "  + digital_outputs: float64"]),
    ("ur_realtime", "1.4", "1.5", ["- another packet: rt_540 (540 bytes)"]),
    ("ur_realtime", "3.15", "5.11", ["~ enum joint_mode", "  240: (none) -> READY_FOR_POWER_OFF"]),
    ("ur_dashboard", "3.4", "5.11", ["+ command get_serial_number"]),
    ("rtde", "3.2", "3.3", ["+ output variable target_q"]),
    ("ur_trajectory", "1.0", "2.10", ["~ trajectory_point: trajectory_point", "  size 36 -> 84"]),
])
def test_diff_names_what_each_kind_changes(stem, a, b, wanted, capsys):
    (spec,) = [s for s in SPECS if s.stem == stem]
    assert main(["diff", a, b, "--spec", str(spec)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"{a} -> {b}: ") and out[0] != f"{a} -> {b}: no change"
    assert all(line in out for line in wanted), out


def test_the_commands_and_variables_a_version_has_are_those_the_runtime_offers():
    for spec in SPECS:
        kind, plan = kind_and_plan(spec)
        if kind not in ("lines", "typed_messages"):
            continue
        module = importlib.import_module(f"urwire.generated.{spec.stem}")
        for version in VERSIONS:
            if kind == "lines":
                ours = {c.command.name for c in plan.commands if has(plan, c, version)}
                theirs = {c.name for c in module.COMMANDS if c.available(version)}
            else:
                ours = {(v.name, v.direction, available(offered(plan.interface, v, version)))
                        for v in plan.interface.variables}
                theirs = {(v.name, v.direction, v.available_in(version)) for v in module.VARIABLES}
            assert ours == theirs, (spec.stem, ir.version_text(version), ours ^ theirs)
