"""`urwire export --dataset` and urwire.data.dataset: one schema per kind that every layout of every
vector fills with the values `urwire export --out` writes (null where a version has no field);
folders by interface, kind, robot and day; another capture appends, the same capture replaces
its rows; row groups of the size docs/tables.md gives, with statistics; and the DuckDB queries of
docs/tables.md, run exactly as written on two robots over two days, with their answers."""
from __future__ import annotations

import datetime
import json
import math
import os
import re
import shutil
from pathlib import Path

import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import urwire  # noqa: E402
from urwire.data import dataset, dataset_files, dataset_rows, export  # noqa: E402
from urwire.canonical import has_error, to_dict  # noqa: E402

from tests import vectors  # noqa: E402
from tests.python.test_cli import urwire as run  # noqa: E402
from tests.tools import capture, robot_inputs  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "tables.md"
LEAD = ["capture", "capture_file", "position", "capture_time", "conversation"]
PRIMARY_CASES = vectors.all_cases()


def _same(expected, actual) -> bool:
    if isinstance(expected, float) and math.isnan(expected):
        return isinstance(actual, float) and math.isnan(actual)
    return expected == actual


def _rows_by_kind(parts) -> dict:
    rows = {}
    for part in parts:
        assert part.table.schema == dataset.dataset_schema(part.interface, part.kind), part.kind
        for row in part.table.to_pylist():
            rows[(part.kind, row["position"])] = row
    return rows


def _objects(record) -> list:
    """The messages and sub-packages of a record that have tables of their own."""
    if has_error(record) or getattr(record, "TYPE", "unknown") == "unknown":
        return []
    if hasattr(record, "packages"):
        return [p for p in record.packages if hasattr(p, "JSON") and not has_error(p)]
    return [record]


def test_every_kind_has_one_schema_of_the_lead_columns_then_its_fields():
    for kind in dataset.kinds("ur"):
        schema = dataset.dataset_schema("ur", kind)
        assert schema.names[:5] == LEAD and len(set(schema.names)) == len(schema.names), kind
        assert schema.field("capture_time").type == pa.timestamp("us", "UTC")
        assert schema.field("conversation").type == pa.string()
    joints = dataset.dataset_schema("ur", "joint_data")
    assert joints.names[5:13] == [f"{name}_0" for name in ("q_actual", "q_target", "qd_actual", "i_actual",
                                                           "v_actual", "t_motor", "t_micro", "joint_mode")]
    assert joints.names[-1] == "joint_mode_5" and len(joints) == 5 + 6 * 8
    mode = dataset.dataset_schema("ur", "robot_mode_data")
    # the union of CB2's, CB3's and the e-Series' layouts, each field at its widest type
    assert mode.field("timestamp").type == pa.uint64() and mode.field("reserved").type == pa.int64()
    assert mode.field("target_speed_fraction_limit").type == pa.float64()
    limits = dataset.dataset_schema("ur", "configuration_data")
    assert "joint_position_limits_joint_min_limit_5" in limits.names and "motor_type_5" in limits.names
    threads = dataset.dataset_schema("ur", "program_threads")
    assert threads.field("threads").type == pa.string()    # a count only the message tells: JSON


def test_unknown_interfaces_and_kinds_are_refused():
    with pytest.raises(ValueError, match="holds the interfaces ur, ur_realtime"):
        dataset.dataset_schema("rtde", "outputs")
    with pytest.raises(ValueError, match="no kind"):
        dataset.dataset_schema("ur", "joint_dat")


@pytest.mark.parametrize("case", PRIMARY_CASES, ids=lambda c: c.name)
def test_every_layout_fills_its_kinds_schema_with_what_export_writes(case):
    rows = _rows_by_kind(dataset.capture_parts(case.data, case.name, case.version, robot="r", date="2024-01-01"))
    for position, record in enumerate(urwire.decode_stream(case.data, case.version)):
        for obj in _objects(record):
            row = rows[(obj.TYPE, position)]
            assert row["capture"] == dataset.capture_id(case.data) and row["capture_file"] == case.name
            written = {}
            for name, _, value in export._columns(obj):
                written[name] = value
            json_columns = {c.name for c in dataset.columns_of("ur", obj.TYPE) if c.kind == "json"}
            for name in row:
                if name in LEAD:
                    continue
                if name in json_columns:
                    value = getattr(obj, name)
                    assert row[name] == (None if value is None else json.dumps(to_dict(obj)[name], ensure_ascii=False))
                elif name in written:
                    assert _same(written[name], row[name]), (obj.TYPE, name, written[name], row[name])
                else:           # a field this version's layout lacks
                    assert row[name] is None, (obj.TYPE, name)
            assert set(written) <= set(row) or json_columns, (obj.TYPE, set(written) - set(row))


REALTIME_CASES = vectors.interface_cases("ur_realtime")


@pytest.mark.parametrize("case", REALTIME_CASES, ids=lambda c: c.name)
def test_every_real_time_layout_fills_one_schema_with_what_export_writes(case, tmp_path):
    from urwire import realtime
    from urwire.data.export_cell import value_columns

    pcap = capture.write(tmp_path / "rt.pcap", capture.robot_session([case.data], port=30003))
    parts = list(dataset.capture_parts(pcap.read_bytes(), "rt.pcap", case.version))
    assert {(p.interface, p.kind) for p in parts} <= {("ur_realtime", "state"), ("ur_realtime", "errors")}
    rows = [row for p in parts if p.kind == "state" for row in p.table.to_pylist()]
    schema = dataset.dataset_schema("ur_realtime", "state")
    assert all(p.table.schema == dataset.dataset_schema(p.interface, p.kind) for p in parts)
    decoded = [r for r in realtime.decode_stream(case.data, case.version) if not has_error(r)]
    assert len(rows) == len(decoded) and decoded
    for row, record in zip(rows, decoded):
        written = {name: value for key, value in to_dict(record).items()
                   for name, _, value in value_columns(key, value)}
        assert written["type"] == row["type"]
        for name in schema.names[len(LEAD):]:
            assert _same(written.get(name), row[name]), (case.name, name)


def test_the_vectors_reach_every_kind_of_the_schema():
    seen = set()
    for case in PRIMARY_CASES:
        for part in dataset.capture_parts(case.data, case.name, case.version, robot="r", date="2024-01-01"):
            seen.add(part.kind)
    assert set(dataset.kinds("ur")) - {"unknown"} <= seen


def test_a_capture_appends_and_the_same_capture_again_replaces_its_own_rows(tmp_path):
    states = robot_inputs.real_states()
    first = robot_inputs.capture(1)
    second = capture.write(tmp_path / "b.pcap", capture.robot_session(states[:5], robot="192.168.56.102"))
    root = tmp_path / "fleet"
    for path in (first, second):
        result = run("export", "--dataset", str(root), str(path))
        assert result.returncode == 0, result.stderr
    again = tmp_path / "first-renamed.pcap"      # the capture id is of the bytes, not the name
    shutil.copy(first, again)
    assert run("export", "--dataset", str(root), str(again)).returncode == 0

    files = sorted(p.relative_to(root).as_posix() for p in root.rglob("*.parquet"))
    ids = {dataset.file_capture_id(first), dataset.file_capture_id(second)}
    assert {re.search(r"part-(\w+)-0\.parquet", f).group(1) for f in files} == ids
    folders = [f.rsplit("/", 1)[0] for f in files]
    assert len(folders) == len(set(folders))     # one file a folder: the export again replaced its own
    table = pq.read_table(root / "interface=ur" / "kind=robot_state")
    by_robot = {}
    for robot, name in zip(table.column("robot").to_pylist(), table.column("capture_file").to_pylist()):
        by_robot.setdefault((robot, name), 0)
        by_robot[(robot, name)] += 1
    assert by_robot == {("192.168.56.101", again.name): robot_inputs.message_count(1), ("192.168.56.102", "b.pcap"): 5}
    assert not list(root.rglob(".*.tmp")) and not list(root.rglob(".*.arrows"))


def test_a_root_given_as_a_uri_is_written_through_pyarrows_filesystem(tmp_path):
    states = robot_inputs.real_states()
    day = capture.write(tmp_path / "a.pcap", capture.robot_session(states[:4]))
    data = day.read_bytes()
    uri = (tmp_path / "fleet").as_uri()          # file:///...: what s3:// and gs:// go through
    stale = tmp_path / "fleet" / "interface=ur" / "kind=joint_data" / "robot=old" / "date=2024-01-01"
    stale.mkdir(parents=True)
    (stale / f"part-{dataset.capture_id(data)}-0.parquet").write_bytes(b"a former export's file")
    for _ in range(2):
        counts = dataset.write_parts(uri, dataset.capture_parts(data, "a.pcap"), dataset.capture_id(data))
    assert counts["robot_state"] == 4
    table = pq.read_table(tmp_path / "fleet" / "interface=ur" / "kind=robot_state")
    assert table.num_rows == 4                   # written twice, held once
    assert not list(stale.iterdir())


def test_a_robot_is_its_serial_number_where_the_dashboard_told_it(tmp_path):
    states = robot_inputs.real_states()[:3]
    dashboard = capture.session_frames([capture.Segment(False, b"get serial number\n"),
                                        capture.Segment(True, b"20165500123\n")], port=29999, client_port=50200)
    primary = capture.robot_session(states)
    other = capture.robot_session(states, robot="192.168.56.102", client_port=50300)
    told = capture.write(tmp_path / "cell.pcap", primary + dashboard + other)
    folders = {(p.interface, p.robot) for p in dataset.capture_parts(told.read_bytes(), "cell.pcap")}
    # the primary rows before the answer too; the robot nobody asked stays its address
    assert folders == {("ur", "20165500123"), ("ur", "192.168.56.102")}


def test_a_capture_cut_short_keeps_its_rows_and_files_the_fault_with_them(tmp_path):
    whole = robot_inputs.capture(1).read_bytes()
    cut = tmp_path / "cut.pcap"
    cut.write_bytes(whole[:len(whole) // 2] + b"garbage")
    root = tmp_path / "fleet"
    result = run("export", "--dataset", str(root), str(cut))
    assert result.returncode == 1, result.stderr      # an error record, as decode gives
    errors = pq.read_table(root / "interface=ur" / "kind=errors")
    assert errors.num_rows == 1 and "capture cut short" in errors.column("record")[0].as_py()
    assert errors.column("robot")[0].as_py() == "192.168.56.101"
    assert pq.read_table(root / "interface=ur" / "kind=robot_state").num_rows > 500


def test_a_raw_stream_needs_a_robot_and_takes_its_files_date(tmp_path):
    stream = tmp_path / "robot.bin"
    stream.write_bytes(b"".join(robot_inputs.real_states()[:3]))
    when = datetime.datetime(2024, 5, 6, 23, 30, tzinfo=datetime.timezone.utc).timestamp()
    os.utime(stream, (when, when))
    root = tmp_path / "fleet"
    refused = run("export", "--dataset", str(root), str(stream))
    assert refused.returncode == 2 and b"--robot" in refused.stderr
    assert run("export", "--dataset", str(root), "--robot", "cell-7", str(stream)).returncode == 0
    folder = root / "interface=ur" / "kind=joint_data" / "robot=cell-7" / "date=2024-05-06"
    table = pq.read_table(next(folder.glob("part-*-0.parquet")))
    assert table.num_rows == 3 and table.column("capture_time").null_count == 3
    assert run("export", "--dataset", str(root), "--robot", "cell-7", "--date", "2024-06-01",
               str(stream)).returncode == 0
    assert not folder.exists()      # the same capture, now dated by hand: its former rows are gone
    assert (root / "interface=ur" / "kind=joint_data" / "robot=cell-7" / "date=2024-06-01").is_dir()
    assert run("export", "--dataset", str(root), "--out", str(tmp_path / "t"), str(stream)).returncode == 2


@pytest.mark.parametrize("batch", [64, 256])     # batches smaller and larger than a row group
def test_row_groups_take_a_kinds_share_of_the_bound_and_carry_statistics(tmp_path, monkeypatch, batch):
    schema = dataset.dataset_schema("ur", "joint_data")
    files = dataset_files
    row_bytes = sum(map(files._width, schema))
    assert files._row_group_rows(schema) == files.ROW_GROUP_BYTES // row_bytes
    assert 300_000 < files._row_group_rows(schema) < files.ROW_GROUP_ROWS
    assert files._row_group_rows(pa.schema([("position", pa.int64())])) == files.ROW_GROUP_ROWS
    monkeypatch.setattr(files, "ROW_GROUP_BYTES", row_bytes * 100)   # 100 rows a group
    monkeypatch.setattr(dataset_rows, "BATCH_ROWS", batch)
    data = robot_inputs.capture(1).read_bytes()
    dataset.write_parts(tmp_path, dataset.capture_parts(data, "one.pcap"), "c0ffee")
    meta = pq.ParquetFile(next((tmp_path / "interface=ur" / "kind=joint_data").rglob("*.parquet"))).metadata
    count = robot_inputs.message_count(1)
    assert meta.num_rows == count and meta.num_row_groups == -(-count // 100)
    assert [meta.row_group(i).num_rows for i in range(meta.num_row_groups - 1)] == [100] * (meta.num_row_groups - 1)
    stats = meta.row_group(0).column(schema.names.index("t_motor_0")).statistics
    assert stats.has_min_max and stats.min <= stats.max
    dictionary = {name for name in schema.names
                  if "RLE_DICTIONARY" in meta.row_group(0).column(schema.names.index(name)).encodings}
    assert dictionary == set(schema.names) - set(files.UNIQUE_COLUMNS)     # unique per row: written plainly


# ---- the fleet queries of docs/tables.md ------------------------------------------------------

# (robot address, day, [(robot mode, protective stop)] one state a second from 08:00 UTC); joint
# j's motor is at base + j + 0.5 * i degrees in state i.
FLEET = [
    ("192.168.56.101", "2024-03-04", 30.0, [(7, 0), (7, 0), (7, 1), (7, 1), (5, 0), (5, 0), (7, 0), (7, 1), (7, 0),
                                            (7, 0)]),
    ("192.168.56.101", "2024-03-05", 30.0, [(5, 0), (5, 0), (5, 0), (7, 0), (7, 0), (7, 0)]),
    ("192.168.56.102", "2024-03-04", 40.0, [(3, 0), (3, 1), (5, 0), (7, 1), (7, 1)]),
    ("192.168.56.102", "2024-03-05", 40.0, [(7, 1), (7, 0), (7, 1)]),
]


def _state(template: bytes, mode: int, stopped: int, temperatures: list) -> bytes:
    (record,) = list(urwire.decode_stream(template))
    modes = record.package(urwire.RobotModeData)
    modes.robot_mode, modes.is_protective_stopped = mode, bool(stopped)
    for joint, t in zip(record.package(urwire.JointData).joints, temperatures):
        joint.t_motor = t
    return record.encode()


def _fleet(root: Path, tmp_path: Path) -> None:
    wanted = {"robot_mode_data", "joint_data"}
    template = next(m for m in robot_inputs.real_states()
                    if {p.TYPE for p in next(iter(urwire.decode_stream(m))).packages} >= wanted)
    for n, (robot, day, base, states) in enumerate(FLEET):
        payloads = [_state(template, mode, stop, [base + j + 0.5 * i for j in range(6)])
                    for i, (mode, stop) in enumerate(states)]
        start = datetime.datetime.fromisoformat(f"{day}T08:00:00+00:00").timestamp()
        # three handshake frames, then each state and its ACK: the states are a second apart
        path = capture.write(tmp_path / f"capture{n}.pcap", capture.robot_session(payloads, robot=robot),
                             start=start, step=0.5)
        result = run("export", "--dataset", str(root), str(path))
        assert result.returncode == 0, result.stderr


def doc_statements() -> list[str]:
    """The SQL block of the doc's fleet section, one statement at a time."""
    section = DOC.read_text(encoding="utf-8").split("### Querying a fleet with DuckDB", 1)[1]
    block = re.search(r"```sql\n(.*?)```", section, re.S).group(1)
    return [s.strip() for s in re.split(r";\s*$", block, flags=re.M) if s.strip()]


def test_the_docs_fleet_queries_answer_on_two_robots_over_two_days(tmp_path, monkeypatch):
    duckdb = pytest.importorskip("duckdb")
    _fleet(tmp_path / "fleet", tmp_path)
    monkeypatch.chdir(tmp_path)
    con = duckdb.connect()
    con.execute("SET TimeZone = 'UTC'")
    answers = []
    for statement in doc_statements():
        result = con.execute(statement)
        code = [line for line in statement.splitlines() if not line.startswith("--")]
        if code[0].startswith("SELECT"):
            answers.append(result.fetchall())
    stops, temperatures, modes = answers
    a, b, d4, d5 = "192.168.56.101", "192.168.56.102", datetime.date(2024, 3, 4), datetime.date(2024, 3, 5)
    assert stops == [(a, d4, 2), (b, d4, 2), (b, d5, 2)]
    utc = datetime.timezone.utc
    assert [(r[0], r[1].astimezone(utc), *r[2:]) for r in temperatures] == [
        (a, datetime.datetime(2024, 3, 4, 8, tzinfo=utc), 32.25, 33.25, 34.25, 35.25, 36.25, 37.25, 39.5),
        (a, datetime.datetime(2024, 3, 5, 8, tzinfo=utc), 31.25, 32.25, 33.25, 34.25, 35.25, 36.25, 37.5),
        (b, datetime.datetime(2024, 3, 4, 8, tzinfo=utc), 41.0, 42.0, 43.0, 44.0, 45.0, 46.0, 47.0),
        (b, datetime.datetime(2024, 3, 5, 8, tzinfo=utc), 40.5, 41.5, 42.5, 43.5, 44.5, 45.5, 46.0),
    ]
    assert modes == [(a, d4, 5, 2.0), (a, d4, 7, 7.0), (a, d5, 5, 3.0), (a, d5, 7, 2.0),
                     (b, d4, 3, 2.0), (b, d4, 5, 1.0), (b, d4, 7, 1.0), (b, d5, 7, 2.0)]
