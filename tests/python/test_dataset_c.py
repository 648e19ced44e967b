"""The dataset's columns made in C (urwire._ccore.PrimaryColumns, python/urwire/data/dataset_c.py)
against pure Python's (dataset.PartBuilder over the Python decoder): every kind's table of every
robot and day, row for row, with its types and nulls, over every golden and conformance vector,
every kept fuzz input, sessions of every controller generation and a run of real robot states as
raw streams; the bundled captures, every golden vector of every interface in one capture (whole and
cut in segments), a capture cut short, two robots across midnight; in batches of any size; and
`urwire export --dataset` writes the same files under both backends. The C code also runs under
ASan and UBSan (dataset_c_asan_peer.py).

The extension is built by `make python-ext`; without it these tests fail."""
from __future__ import annotations

import datetime
import io
import math
import os
import random
import subprocess
import sys
from pathlib import Path

import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

import urwire  # noqa: E402
from urwire import capture  # noqa: E402
from urwire.data import dataset, dataset_c  # noqa: E402

from tests.tools import capture as capture_file, golden_sessions, robot_inputs, valid  # noqa: E402
from tests.tools.fuzz_inputs import HARNESSES, decodable  # noqa: E402
from tests.vectors import all_cases  # noqa: E402
from tests.tools import ccore_sanitized  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "dissector" / "samples"
PRIMARY_PORTS = {30001, 30002, 30011, 30012}


@pytest.fixture(scope="module", autouse=True)
def c_columns():
    if not dataset_c.available():
        ccore_sanitized.missing("the C extension urwire._ccore is not built (make python-ext), or URWIRE_BACKEND=python")


def python_tables(data: bytes, hint, robot="r", date="2024-01-01") -> dict:
    """Each kind's rows of each robot and day as pure Python makes them (the C path turned off)."""
    available = dataset_c.available
    dataset_c.available = lambda: False
    try:
        return _tables(dataset.parts_of(io.BufferedReader(io.BytesIO(data)), "c0ffee", "in.bin", hint, robot, date))
    finally:
        dataset_c.available = available


def c_tables(data: bytes, hint, batch: int = dataset_c.BATCH_ROWS, chunk: int = dataset_c.CHUNK, robot="r",
             date="2024-01-01") -> dict:
    saved = dataset_c.BATCH_ROWS, dataset_c.CHUNK
    dataset_c.BATCH_ROWS, dataset_c.CHUNK = batch, chunk
    try:
        return _tables(dataset.parts_of(io.BufferedReader(io.BytesIO(data)), "c0ffee", "in.bin", hint, robot, date))
    finally:
        dataset_c.BATCH_ROWS, dataset_c.CHUNK = saved


def _tables(parts) -> dict:
    tables: dict = {}
    for part in parts:
        assert part.table.schema == dataset.dataset_schema(part.interface, part.kind), part.kind
        tables.setdefault((part.interface, part.kind, part.robot, part.date), []).append(part.table)
    return {key: pa.concat_tables(batches) for key, batches in tables.items()}


def _same_value(a, b) -> bool:
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return a == b and type(a) is type(b)


def assert_same(data: bytes, hint, what: str, batches=(dataset_c.BATCH_ROWS, 3), chunks=(dataset_c.CHUNK,),
                robot="r", date="2024-01-01") -> dict:
    expected = python_tables(data, hint, robot, date)
    for batch in batches:
        for chunk in chunks:
            actual = c_tables(data, hint, batch, chunk, robot, date)
            assert sorted(actual) == sorted(expected), f"{what}: the kinds (batch {batch}, chunk {chunk})"
            for kind, table in expected.items():
                got = actual[kind]
                assert got.schema == table.schema and got.num_rows == table.num_rows, f"{what}: {kind}"
                if got.equals(table):
                    continue
                for name in table.column_names:       # NaN: equal to itself here, not in Arrow's equals
                    want, have = table.column(name).to_pylist(), got.column(name).to_pylist()
                    bad = [i for i, (w, h) in enumerate(zip(want, have)) if not _same_value(w, h)]
                    assert not bad, f"{what}: {kind}.{name} row {bad[0]}: {want[bad[0]]!r} != {have[bad[0]]!r}"
    return expected


@pytest.mark.parametrize("case", all_cases(), ids=lambda c: c.name)
def test_every_vector_gives_the_same_tables(case):
    assert_same(case.data, case.version, case.name)


@pytest.mark.parametrize("harness", HARNESSES)
def test_every_kept_fuzz_input_gives_the_same_tables(harness):
    inputs = decodable(harness)
    assert len(inputs) > 20
    for hint, data, name in inputs:
        assert_same(data, hint, name, batches=(2,), chunks=(97,))


@pytest.mark.parametrize("version", valid.versions(), ids=lambda v: ".".join(map(str, v)))
def test_sessions_of_every_generation_give_the_same_tables(version):
    rng = random.Random(hash(version))
    hint = ".".join(map(str, version))
    for _ in range(3):
        data = valid.session(rng, version, 12)
        cut = data[int.from_bytes(data[:4], "big"):]
        for stream, given in ((data, None), (cut, None), (cut, hint)):
            assert_same(stream, given, f"{given} {stream[:40].hex()}", batches=(5,), chunks=(1000,))


def primary_streams(path: Path) -> list[bytes]:
    """The robot->client streams of a capture's primary and secondary ports, each whole."""
    streams: dict = {}
    with open(path, "rb") as fh:
        for key, data, _ in capture.robot_streams(fh, PRIMARY_PORTS):
            streams[key] = streams.get(key, b"") + data
    return list(streams.values())


@pytest.mark.parametrize("path", [SAMPLES / "cell_session.pcapng", SAMPLES / "primary_session.pcapng",
                                  SAMPLES / "secondary_session.pcap", robot_inputs.capture(1)], ids=lambda p: p.name)
def test_the_primary_streams_of_the_bundled_captures_give_the_same_tables(path):
    streams = primary_streams(path)
    assert streams and sum(map(len, streams)) > 1000
    for data in streams:
        assert_same(data, None, path.name, batches=(dataset_c.BATCH_ROWS, 100), chunks=(dataset_c.CHUNK, 4093))


def test_real_robot_states_give_the_same_tables_and_fill_the_robot_state_kinds():
    data = b"".join(robot_inputs.real_states() * 3)
    assert_same(data, None, "real states", batches=(dataset_c.BATCH_ROWS, 64), chunks=(dataset_c.CHUNK, 1000))
    joints = c_tables(data, None)[("ur", "joint_data", "r", "2024-01-01")]
    assert joints.num_rows == len(robot_inputs.real_states()) * 3
    assert joints.column("t_motor_5").null_count == 0


# ---- captures: Python reads the file, C makes each robot's primary rows --------------------------

@pytest.mark.parametrize("path", [SAMPLES / "cell_session.pcapng", SAMPLES / "primary_session.pcapng",
                                  SAMPLES / "secondary_session.pcap", robot_inputs.capture(1),
                                  robot_inputs.capture(1, pcapng=True)], ids=lambda p: p.name)
def test_the_bundled_captures_give_the_same_tables(path):
    tables = assert_same(path.read_bytes(), None, path.name, batches=(dataset_c.BATCH_ROWS, 50), robot=None,
                         date=None)
    assert any(kind[:2] == ("ur", "robot_state") for kind in tables)


@pytest.mark.parametrize("cut", [False, True], ids=["whole", "segments"])
def test_every_vector_of_every_interface_in_one_capture_gives_the_same_tables(tmp_path, cut):
    path = golden_sessions.write(tmp_path / "golden.pcapng", cut=cut, pcapng=True)
    tables = assert_same(path.read_bytes(), None, path.name, batches=(dataset_c.BATCH_ROWS, 4), robot=None,
                         date="2024-01-01")
    assert {kind[0] for kind in tables} == {"ur", "ur_realtime"}


def test_a_capture_cut_short_files_its_fault_with_the_rows_before_it():
    whole = robot_inputs.capture(1).read_bytes()
    data = whole[:len(whole) // 2] + b"garbage"
    tables = assert_same(data, None, "cut", batches=(dataset_c.BATCH_ROWS, 7), robot=None, date=None)
    errors = [table for kind, table in tables.items() if kind[1] == "errors"]
    assert len(errors) == 1 and errors[0].num_rows == 1
    assert errors[0].column("capture_time").null_count == 1


def test_a_capture_that_lost_a_segment_gives_the_same_tables(tmp_path):
    """A gap inside a message of a primary stream: its error row, the message it cut short, then
    the stream framed afresh after it, the same rows in C as in Python."""
    from tests.vectors import golden_cases

    state = next(c for c in golden_cases() if c.name == "generation_cb3_3_10_robot_state").data
    payloads = [state] * 4 + [state[:30], state[30:60], state[60:]] + [state] * 3
    frames = capture_file.session_frames([capture_file.Segment(True, p) for p in payloads], port=30001)
    del frames[3 + 2 * 5]
    data = capture_file.write(tmp_path / "lost.pcap", frames).read_bytes()
    tables = assert_same(data, None, "lost", batches=(dataset_c.BATCH_ROWS, 3), robot=None, date=None)
    errors = [table for kind, table in tables.items() if kind[1] == "errors"]
    assert len(errors) == 1 and errors[0].num_rows >= 3       # the gap, the cut state, the resync
    assert [kind for kind in tables if kind[1] == "version"] and \
        sum(t.num_rows for kind, t in tables.items() if kind[1] == "version") == 7


def test_two_robots_across_midnight_give_the_same_tables_by_robot_and_day(tmp_path):
    states = robot_inputs.real_states()[:40]
    frames = []
    for n, robot in enumerate(("192.168.56.101", "192.168.56.102")):
        frames.append(capture_file.robot_session(states, robot=robot, client_port=50000 + n))
    interleaved = [frame for pair in zip(*frames) for frame in pair]
    midnight = datetime.datetime(2024, 3, 5, tzinfo=datetime.timezone.utc).timestamp()
    path = capture_file.write(tmp_path / "two.pcap", interleaved, start=midnight - 3.0, step=0.05)
    tables = assert_same(path.read_bytes(), None, "two robots", batches=(dataset_c.BATCH_ROWS, 16), robot=None,
                         date=None)
    days = {(kind[2], kind[3]) for kind in tables if kind[1] == "joint_data"}
    assert days == {(r, d) for r in ("192.168.56.101", "192.168.56.102") for d in ("2024-03-04", "2024-03-05")}


def test_a_raw_stream_without_robot_or_date_is_refused_at_its_first_row():
    data = robot_inputs.real_states()[0]
    with pytest.raises(ValueError, match="--robot"):
        list(dataset_c.raw_parts(io.BytesIO(data), "c0ffee", "in.bin"))
    with pytest.raises(ValueError, match="--date"):
        list(dataset_c.raw_parts(io.BytesIO(data), "c0ffee", "in.bin", robot="r"))
    assert list(dataset_c.raw_parts(io.BytesIO(b""), "c0ffee", "in.bin")) == []


def test_the_extension_refuses_a_layout_without_its_routing_kinds_and_a_closed_stream():
    ccore = urwire.backends.ccore()
    with pytest.raises(ValueError, match="robot_state"):
        ccore.PrimaryColumns(None, [("errors", [("record", 5)])], 10)
    with pytest.raises(ValueError, match="no type"):
        ccore.PrimaryColumns(None, [("joint_data", [("joints/0/q_actual", 99)])], 10)
    stream = ccore.PrimaryColumns(None, dataset_c.layout(), 10)
    stream.close()
    with pytest.raises(ValueError):
        stream.feed(b"\0\0\0\5\x14")


def test_segments_whose_stamps_do_not_cut_their_bytes_in_order_are_refused():
    import struct

    columns = dataset_c.columns(None)
    stream = urwire.backends.ccore().PrimaryStream(None)
    data = robot_inputs.real_states()[0]
    for ends in ([len(data) - 1], [len(data), len(data) - 1, len(data)], [-1, len(data)], [len(data) + 1]):
        stamps = b"".join(struct.pack("=qd", end, 1.7e9) for end in ends)
        with pytest.raises(ValueError, match="stamps"):
            columns.feed_segments(stream, data, stamps, 0)
    with pytest.raises(ValueError, match="stamps"):
        columns.feed_segments(stream, data, struct.pack("=qd", len(data), 1.7e9) + b"\0", 0)
    assert columns.feed_segments(stream, data, struct.pack("=qd", len(data), 1.7e9), 0) == 1


def test_the_command_writes_the_same_dataset_under_both_backends(tmp_path):
    stream = tmp_path / "stream.bin"
    stream.write_bytes(b"".join(case.data for case in all_cases() if case.version is None)
                       + b"".join(robot_inputs.real_states()))
    runs = {}
    for backend in ("c", "python"):
        env = dict(os.environ, URWIRE_BACKEND=backend,
                   PYTHONPATH=os.pathsep.join([str(ROOT / "python"), str(ROOT / "generated" / "python")]))
        root = tmp_path / backend
        result = subprocess.run([sys.executable, "-m", "urwire", "export", "--dataset", str(root), "--robot", "r",
                                 "--date", "2024-01-01", str(stream)], env=env, capture_output=True, timeout=300)
        files = sorted(p.relative_to(root) for p in root.rglob("*.parquet"))
        runs[backend] = (result.returncode, result.stderr, files)
        assert len(files) > 20
    assert runs["c"] == runs["python"]
    for name in runs["c"][2]:
        c_table, python_table = pq.read_table(tmp_path / "c" / name), pq.read_table(tmp_path / "python" / name)
        assert c_table.schema == python_table.schema and c_table.num_rows == python_table.num_rows, name
        assert c_table.to_pylist() == python_table.to_pylist() or _nan_equal(c_table, python_table), name


def _nan_equal(a, b) -> bool:
    return all(_same_value(x, y) for ra, rb in zip(a.to_pylist(), b.to_pylist()) for x, y in
               zip(ra.values(), rb.values()))


@pytest.mark.deep  # a sanitized build of the extension: make test-deep
def test_the_columns_under_asan_and_ubsan(tmp_path):
    """columns.c built with ASan and UBSan into urwire._ccore and run over every vector and kept
    fuzz input, in batches of a few rows (dataset_c_asan_peer.py): no report."""
    result = ccore_sanitized.run_peer("dataset_c_asan_peer.py", tmp_path)
    assert result.returncode == 0 and "ERROR" not in result.stderr, result.stderr[-3000:]
    assert int(result.stdout) > 300


@pytest.mark.parametrize("bad", [b"\xff\xfe", b"\xed\xa0\x80", b"\xe0\x80\x80", b"\xf4\x90\x80\x80", b"a\xc3"])
def test_text_that_is_not_utf8_is_replaced_as_python_replaces_it(bad):
    """A text message's bytes made invalid UTF-8 (a stray byte, a surrogate, overlong, beyond
    U+10FFFF, cut short): the C column holds what bytes.decode("utf-8", "replace") gives."""
    case = next(c for c in all_cases() if c.name == "stream_fault_garbage_at_end")
    at = case.data.index(b"before")
    data = case.data[:at] + bad + case.data[at + len(bad):]
    tables = assert_same(data, None, repr(bad))
    texts = tables[("ur", "text", "r", "2024-01-01")].column("text").to_pylist()
    assert "\ufffd" in texts[0]
