"""Every table exported from a capture names each row's conversation, the primary interface's as
the other interfaces' do (docs/tables.md). Two robots in one capture (test_two_robots_capture.py's:
a CB2 1.8 and an e-Series 5.11 on the same ports and client port, their messages interleaved)
split by conversation into each robot's own rows, value for value those of its golden stream
exported alone, in `urwire export --out`'s CSV and Parquet and in the dataset under both backends.
A raw stream's tables name no conversation: `--out`'s have no such column, the dataset's holds
null. A primary error row holds its record as `urwire decode` prints it, envelope and all; a fault
of the capture file belongs to no conversation."""
from __future__ import annotations

import csv
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest
import urwire
from urwire.canonical import fails
from urwire.data import dataset, dataset_c

from tests.python.test_two_robots_capture import ESERIES, ROBOTS, conversation, two_robots  # noqa: F401 (a fixture)
from tests.tools import capture
from tests.vectors import golden_cases

pq = pytest.importorskip("pyarrow.parquet")

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "tables.md"
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
WHERE = ("position", "capture_time", "conversation")     # where a row is, not what it holds
LEAD = ("capture", "capture_file", *WHERE)


def export(path: Path, out: Path, fmt: str, hint=None) -> dict[str, list[dict]]:
    """`urwire export --out` of a file: each table's rows."""
    hinted = ["--version-hint", hint] if hint else []
    result = subprocess.run([sys.executable, "-m", "urwire", "export", str(path), "--out", str(out), "--format", fmt,
                             *hinted], capture_output=True, text=True, env=ENV, timeout=120)
    assert result.returncode in (0, 1), result.stderr
    tables = {}
    for table in out.glob(f"*.{fmt}"):
        if fmt == "csv":
            with open(table, newline="", encoding="utf-8") as fh:
                tables[table.stem] = list(csv.DictReader(fh))
        else:
            tables[table.stem] = pq.read_table(table).to_pylist()
    return tables


def held(row: dict, where=WHERE) -> dict:
    """What a row holds, without where it is; an empty cell (a field the robot's layout lacks, in
    a table both robots fill) left out, a NaN as text so that it equals itself."""
    return {k: "nan" if isinstance(v, float) and math.isnan(v) else v for k, v in row.items()
            if k not in where and v not in (None, "")}


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_two_robots_tables_split_by_conversation_into_each_robots_own(two_robots, tmp_path, fmt):
    both = export(two_robots, tmp_path / "both", fmt)
    assert all("conversation" in rows[0] and all(r["conversation"] for r in rows) for rows in both.values())
    assert {r["conversation"] for rows in both.values() for r in rows} == \
        {conversation(robot, port) for robot in ROBOTS for port in (30001, 30003)}
    primary_rows = 0
    for robot, (primary, realtime) in ROBOTS.items():
        raw = tmp_path / f"{robot}.bin"
        raw.write_bytes(primary.data)
        alone = export(raw, tmp_path / robot, fmt, primary.version)
        assert alone and not any("conversation" in rows[0] for rows in alone.values())    # a raw stream: none
        own = conversation(robot, 30001)
        for table, rows in alone.items():
            assert [held(r) for r in both[table] if r["conversation"] == own] == [held(r) for r in rows], table
            primary_rows += len(rows)
        # The real-time packets, in the table they had a conversation column in already.
        packets = [r for r in both["ur_realtime"] if r["conversation"] == conversation(robot, 30003)]
        assert [r["type"] for r in packets] == [r["type"] for r in realtime.expect]
    # Each row is one robot's: none is left over, none counted twice.
    assert primary_rows == sum(len(rows) for table, rows in both.items() if table != "ur_realtime")


def test_the_docs_query_of_one_robot_in_a_capture_of_two_answers_with_its_rows(two_robots, tmp_path, monkeypatch):
    duckdb = pytest.importorskip("duckdb")
    statement = re.search(r"-- one robot's joints, in a capture of two\n(.*?);", DOC.read_text(encoding="utf-8"),
                          re.S).group(1)
    assert conversation(ESERIES, 30001) in statement
    export(two_robots, tmp_path / "tables", "parquet")
    monkeypatch.chdir(tmp_path)
    got = duckdb.sql(statement).fetchall()
    expected = [package["joints"][0]["q_actual"] for record in ROBOTS[ESERIES][0].expect
                for package in record.get("packages", []) if package["type"] == "joint_data"]
    assert got and [q for _, q in got] == expected and all(time is not None for time, _ in got)
    assert duckdb.sql("SELECT count(*) FROM 'tables/joint_data.parquet'").fetchall()[0][0] > len(got)  # both robots'


def _dataset_rows(parts) -> dict[tuple, list[dict]]:
    rows: dict = {}
    for part in parts:
        rows.setdefault((part.interface, part.kind, part.robot), []).extend(part.table.to_pylist())
    return rows


@pytest.fixture(params=["python", "c"])
def backend(request, monkeypatch):
    if request.param == "python":
        monkeypatch.setattr(dataset_c, "available", lambda: False)
    elif not dataset_c.available():
        pytest.skip("the C extension urwire._ccore is not built (make python-ext)")
    return request.param


def test_two_robots_dataset_rows_name_their_conversation_and_are_each_robots_own(two_robots, backend):
    both = _dataset_rows(dataset.capture_parts(two_robots.read_bytes(), two_robots.name))
    assert {robot for _, _, robot in both} == set(ROBOTS)
    for robot, (primary, realtime) in ROBOTS.items():
        alone = _dataset_rows(dataset.capture_parts(primary.data, "alone.bin", primary.version, robot=robot,
                                                    date="2024-01-01"))
        assert all(r["conversation"] is None for rows in alone.values() for r in rows)      # a raw stream: null
        for key, rows in alone.items():
            got = both[key]
            assert {r["conversation"] for r in got} == {conversation(robot, 30001)}, key
            assert [held(r, LEAD) for r in got] == [held(r, LEAD) for r in rows], key
        state = both[("ur_realtime", "state", robot)]
        assert {r["conversation"] for r in state} == {conversation(robot, 30003)}
        assert [r["type"] for r in state] == [r["type"] for r in realtime.expect]
        assert {key for key in both if key[2] == robot} == {*alone, ("ur_realtime", "state", robot)}


@pytest.fixture(scope="module")
def lost_segment(tmp_path_factory) -> Path:
    """A primary stream that lost a segment inside a message (a gap, the message it cut short, the
    stream framed afresh), then a block of the capture file that cannot be read."""
    state = next(c for c in golden_cases() if c.name == "generation_cb3_3_10_robot_state").data
    payloads = [state] * 2 + [state[:30], state[30:60], state[60:]] + [state] * 2
    frames = capture.session_frames([capture.Segment(True, p) for p in payloads], port=30001)
    del frames[3 + 2 * 3]
    path = capture.write(tmp_path_factory.mktemp("lost") / "lost.pcap", frames)
    path.write_bytes(path.read_bytes() + b"garbage")
    return path


def _decoded_errors(path: Path) -> list[dict]:
    """The lines `urwire decode` prints for the capture's records that fail."""
    return [urwire.to_dict(r) for r in urwire.decode_capture(path) if fails(r)]


def test_a_primary_error_row_holds_the_record_as_decode_prints_it(lost_segment, tmp_path):
    expected = _decoded_errors(lost_segment)
    own = conversation("192.168.56.101", 30001)
    assert [r.get("conversation") for r in expected] == [own] * (len(expected) - 1) + [None]
    assert len(expected) >= 3
    for fmt in ("csv", "parquet"):
        errors = export(lost_segment, tmp_path / fmt, fmt)["errors"]
        assert [json.loads(r["record"]) for r in errors] == expected, fmt
        assert [r["conversation"] or None for r in errors] == [own] * (len(expected) - 1) + [None], fmt


def test_a_primary_error_row_of_the_dataset_holds_the_record_as_decode_prints_it(lost_segment, backend):
    rows = _dataset_rows(dataset.capture_parts(lost_segment.read_bytes(), lost_segment.name))
    (errors,) = [rows_ for (interface, kind, _), rows_ in rows.items() if kind == "errors"]
    assert [json.loads(r["record"]) for r in errors] == _decoded_errors(lost_segment)
    assert [r["conversation"] for r in errors] == [e.get("conversation") for e in _decoded_errors(lost_segment)]
