"""`urwire export` of a capture of every interface of the cell: each record `urwire decode` prints
is found, value by value, in the row of its interface's table (docs/tables.md), and no table holds
a row that decode did not print. The capture is the golden vectors' conversations
(tests/tools/cell_session.py), with a second RTDE connection (the same recipe, in the same table),
a protocol 1 connection (no recipe ids), one that starts after its setup (a data package of a
recipe never seen, kept raw) and a second dashboard connection (replies that say an error)."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from tests.tools import capture, cell_session
from tests.tools.cell_session import Conversation
from tests.interface_vectors import conversation_cases

duckdb = pytest.importorskip("duckdb")

ROOT = Path(__file__).resolve().parents[2]
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
ENVELOPE = ("interface", "direction", "conversation")
PRIMARY_TABLES = {"version", "robot_state", "robot_mode_data", "joint_data", "payload_info"}


def urwire(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "urwire", *args], capture_output=True, text=True, env=ENV,
                          timeout=120)


def _rtde_cases(*names: str) -> list:
    from tests.rtde_vectors import rtde_cases

    cases = {c.name: c for c in rtde_cases()}
    return [cases[n] for n in names]


@pytest.fixture(scope="module")
def cell(tmp_path_factory) -> Path:
    conversations = cell_session.conversations()
    rtde = next(c for c in conversations if c.port == 30004)
    again = Conversation(rtde.vector, 30004, 50201, rtde.segments)
    dash = next(c for c in conversation_cases("ur_dashboard") if c.name == "error_replies")
    errors = Conversation("ur_dashboard/error_replies", 29999, 50202,
                          tuple(capture.Segment(s.from_robot, s.data) for s in dash.segments))
    more_rtde = [Conversation(f"rtde/{c.name}", 30004, port, tuple(capture.Segment(f, d) for f, d in c.messages))
                 for c, port in zip(_rtde_cases("protocol1_session", "unknown_recipe_and_refused_start"),
                                    (50203, 50204))]
    frames = cell_session.interleave([c.frames() for c in [*conversations, again, errors, *more_rtde]])
    return capture.write(tmp_path_factory.mktemp("cell") / "cell.pcapng", frames, pcapng=True)


@pytest.fixture(scope="module")
def decoded(cell) -> list[dict]:
    res = urwire("decode", str(cell))
    records = [json.loads(line) for line in res.stdout.splitlines()]
    # Exit 1: the data package of a recipe never set up is kept whole with an error, as it should.
    assert [r["error"] for r in records if isinstance(r.get("error"), str) or r["type"] == "error"] == [
        "data package of a recipe this connection did not set up"]
    assert res.returncode == 1, res.stderr
    return records


@pytest.fixture(scope="module", params=["parquet", "csv"])
def tables(request, cell, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp(request.param)
    res = urwire("export", str(cell), "--out", str(out), "--format", request.param)
    assert res.returncode == 1, res.stderr      # as decode's, by the same rule
    return out


def rows(out: Path, table: str) -> list[dict]:
    files = list(out.glob(f"{table}.*"))
    assert len(files) == 1, f"no table {table} in {sorted(p.name for p in out.iterdir())}"
    reader = "read_csv_auto" if files[0].suffix == ".csv" else "read_parquet"
    rel = duckdb.sql(f"SELECT * FROM {reader}('{files[0]}', {'all_varchar=true' if reader == 'read_csv_auto' else ''})"
                     if reader == "read_csv_auto" else f"SELECT * FROM read_parquet('{files[0]}')")
    return [dict(zip(rel.columns, row)) for row in rel.fetchall()]


def same(cell, value) -> bool:
    """A cell equals a decoded JSON value; CSV cells are text, compared as what they stand for."""
    if isinstance(cell, str) and not isinstance(value, str):
        if value is None:
            return cell == ""
        if isinstance(value, bool):
            return cell == str(value)
        return math.isclose(float(cell), value, rel_tol=0, abs_tol=0) or float(cell) == value
    if value is None:
        return cell is None or cell == ""
    return cell == value


def flat(record: dict) -> dict:
    """The columns a record's members become: a list of numbers one column per item."""
    out = {}
    for key, value in record.items():
        if key in ENVELOPE or value is None:
            continue
        if isinstance(value, list) and value and all(isinstance(v, (int, float)) for v in value):
            out.update({f"{key}_{j}": v for j, v in enumerate(value)})
        elif isinstance(value, (list, dict)):
            out[key] = json.dumps(value) if value else None
        else:
            out[key] = value
    return out


def check_row(row: dict, expected: dict, where: str) -> None:
    for column, value in expected.items():
        if value is None:
            continue
        assert column in row, f"{where}: no column {column}"
        cell = row[column]
        if isinstance(value, str) and value.startswith(("[", "{")) and isinstance(cell, str):
            assert json.loads(cell) == json.loads(value), f"{where}: {column}"
        else:
            assert same(cell, value), f"{where}: {column} is {cell!r}, decode says {value!r}"


def test_every_record_is_its_tables_row(tables, decoded):
    recipes = rows(tables, "rtde_recipes")
    # CSV reads an empty recipe id (protocol 1's outputs) as text, Parquet as None.
    table_of = {(r["conversation"], r["kind"], str(r["recipe_id"] if r["recipe_id"] != "" else None)): r["table"]
                for r in recipes}
    by_table: dict[tuple, dict[int, dict]] = {}

    def row_at(table: str, position: int, column: str = "position") -> dict:
        if (table, column) not in by_table:
            index = by_table[table, column] = {}
            for r in rows(tables, table):
                if r[column] not in (None, ""):
                    index[int(r[column])] = r
        found = by_table[table, column].get(position)
        assert found is not None, f"{table}: no row at {column} {position}"
        return found

    expected_counts: dict[str, int] = {}
    dashboard_pairs = 0
    for position, record in enumerate(decoded):
        interface = record.get("interface")
        if interface == "ur":
            continue      # the primary interface's tables are tested by test_live.py and test_export_values.py
        where = f"line {position} ({interface} {record['type']})"
        assert_values = {k: v for k, v in flat(record).items() if k != "type"}
        if isinstance(record.get("error"), str):      # what makes decode exit 1, export too
            row = row_at("errors", position)
            assert json.loads(row["record"]) == record, where
            expected_counts["errors"] = expected_counts.get("errors", 0) + 1
        elif interface == "rtde" and record["type"] in ("data_package", "data_package_v1", "input_data_package"):
            kind = "inputs" if record["type"] == "input_data_package" else "outputs"
            table = table_of[(record["conversation"], kind, str(record.get("recipe_id")))]
            assert table.startswith(f"rtde_{kind}_")
            row = row_at(table, position)
            check_row(row, {"conversation": record["conversation"], **assert_values}, where)
        elif interface == "ur_dashboard" and record["type"] == "command":
            row = row_at("ur_dashboard", position)
            check_row(row, {"conversation": record["conversation"], **assert_values}, where)
        elif interface == "ur_dashboard":
            row = row_at("ur_dashboard", position, "reply_position")
            check_row(row, {"reply": record["reply"], "reply_name": record["reply_name"],
                            "error": record["error"]}, where)
            assert same(row["command_name"], record.get("command_name")), where
            dashboard_pairs += 1
        else:
            table = "rtde_messages" if interface == "rtde" else interface
            expected_counts[table] = expected_counts.get(table, 0) + 1
            row = row_at(table, position)
            check_row(row, {"conversation": record["conversation"], "direction": record["direction"],
                            "type": record["type"], **assert_values}, where)
    # No table holds a row decode did not print.
    for table, count in expected_counts.items():
        assert len(rows(tables, table)) == count, table
    commands = sum(1 for r in decoded if r.get("interface") == "ur_dashboard" and r["type"] == "command")
    banners = sum(1 for r in decoded if r.get("reply_name") == "connected" and r.get("command_name") is None)
    # Each reply makes a row, and so does each command no reply answered.
    unanswered = commands - (dashboard_pairs - banners)
    assert len(rows(tables, "ur_dashboard")) == dashboard_pairs + unanswered


def test_a_recipe_is_one_table_across_connections(tables, decoded):
    recipes = rows(tables, "rtde_recipes")
    outputs = [r for r in recipes if r["kind"] == "outputs" and r["variables"].startswith("timestamp,actual_q")]
    assert len(outputs) == 2 and len({r["conversation"] for r in outputs}) == 2
    assert len({r["table"] for r in outputs}) == 1
    assert outputs[0]["variables"] == "timestamp,actual_q,robot_mode"
    assert outputs[0]["types"] == "DOUBLE,VECTOR6D,INT32"
    data = rows(tables, outputs[0]["table"])
    assert [str(r["recipe_id"]) for r in data] == ["2", "2"]
    assert [c for c in data[0] if c != "capture_time"] == [
        "position", "conversation", "recipe_id", "timestamp", *(f"actual_q_{j}" for j in range(6)), "robot_mode"]


def test_a_protocol_1_recipe_has_no_id(tables):
    recipes = [r for r in rows(tables, "rtde_recipes") if r["conversation"].endswith(":50203")]
    assert [(r["kind"], r["recipe_id"] in (None, ""), r["variables"]) for r in recipes] == [
        ("outputs", True, "timestamp,safety_mode")]
    (row,) = rows(tables, recipes[0]["table"])
    assert row["recipe_id"] in (None, "") and same(row["timestamp"], 1.0) and same(row["safety_mode"], 1)


def test_dashboard_rows_pair_each_command_with_its_reply(tables):
    pairs = [(r["command"] or None, r["reply"] or None)
             for r in rows(tables, "ur_dashboard") if r["conversation"].endswith(":50104")]
    assert pairs == [
        (None, "Connected: Universal Robots Dashboard Server"),
        ("PolyscopeVersion", "URSoftware 5.11.1.108318 (Nov 26 2021)"),
        ("load /programs/pick.urp", "Loading program: /programs/pick.urp"),
        ("play", "Starting program"),
        ("stop", "Stopped"),
    ]


def test_the_primary_tables_are_as_before(tables, cell, tmp_path):
    """The primary interface's tables of a cell capture are those of its primary conversation alone."""
    primary = cell_session.conversations()[0]
    alone = capture.write(tmp_path / "primary.pcapng", primary.frames(), pcapng=True)
    out = tmp_path / "alone"
    fmt = "csv" if next(tables.glob("version.*")).suffix == ".csv" else "parquet"
    assert urwire("export", str(alone), "--out", str(out), "--format", fmt).returncode == 0
    for table in PRIMARY_TABLES:
        drop = {"position", "capture_time"}
        assert [{k: v for k, v in r.items() if k not in drop} for r in rows(tables, table)] == \
            [{k: v for k, v in r.items() if k not in drop} for r in rows(out, table)], table


@pytest.mark.deep  # a long export (about 30 s): make test-deep
def test_export_of_a_long_rtde_connection_takes_flat_memory(tmp_path):
    """RTDE's tables keep to the export's memory bound (test_memory.py): twice the data packages,
    the same memory, and every package a row of its recipe's table. CSV only: the rows wait on
    disk the same way for either format, and test_memory.py measures Parquet's writer."""
    from tests.python.test_memory import EXPORT_GROWTH_LIMIT, PEAK_LIMIT, rows, run
    from tests.tools import rtde_inputs

    form = "csv"
    peaks = []
    for megabytes in (12, 24):
        out = tmp_path / f"{megabytes}-{form}"
        usage = run(["-m", "urwire", "export", str(rtde_inputs.capture(megabytes)), "--format", form,
                     "--out", str(out)])
        (table,) = out.glob(f"rtde_outputs_*.{form}")
        assert rows(table) == rtde_inputs.package_count(megabytes)
        peaks.append(usage.peak)
    assert peaks[-1] < PEAK_LIMIT, f"{peaks[-1] / (1 << 20):.0f} MiB"
    assert peaks[-1] - peaks[0] < EXPORT_GROWTH_LIMIT, f"{peaks[0] / (1 << 20):.0f} -> {peaks[-1] / (1 << 20):.0f} MiB"
