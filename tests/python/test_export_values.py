"""`urwire export` writes every value that `decode` reads, as `decode` shows it: a float32 NaN as
NaN, an unsigned 64-bit value in a uint64 column, any nonzero bool byte as true, and text that
is not UTF-8 with each invalid byte as U+FFFD; from a raw stream and from a capture alike."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest
import urwire

from tests.python.test_cli import records, urwire as run
from tests.tools import capture

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "primary_session.pcapng"
UINT64_MAX = (1 << 64) - 1
BOOL_BYTE = 18   # is_real_robot_connected: message header 5, sub-package header 5, timestamp 8


def odd_stream() -> bytes:
    """A Version message with a project name that is not UTF-8, then a robot state whose
    robot_mode_data has the largest timestamp and a bool byte of 2, and whose first joint's
    v_actual (float32) is NaN."""
    recs = list(urwire.decode_file(SAMPLE))
    version = next(r for r in recs if r.TYPE == "version")
    state = next(r for r in recs if getattr(r, "packages", None)
                 and {p.TYPE for p in r.packages} >= {"robot_mode_data", "joint_data"})
    assert state.packages[0].TYPE == "robot_mode_data"
    version.project_name = "URControl\udcff\udcfe"
    state.package(urwire.RobotModeData).timestamp = UINT64_MAX
    state.package(urwire.JointData).joints[0].v_actual = float("nan")
    data = bytearray(state.encode())
    assert data[BOOL_BYTE] == 1
    data[BOOL_BYTE] = 2
    return version.encode() + bytes(data)


def inputs(tmp_path: Path, form: str) -> Path:
    data = odd_stream()
    if form == "stream":
        path = tmp_path / "odd.bin"
        path.write_bytes(data)
        return path
    return capture.write(tmp_path / "odd.pcap", capture.robot_session([data]))


def table(out: Path, name: str, fmt: str) -> list[dict]:
    if fmt == "csv":
        with open(out / f"{name}.csv", newline="", encoding="utf-8") as fh:
            return list(csv.DictReader(fh))
    import pyarrow.parquet as pq
    return pq.read_table(out / f"{name}.parquet").to_pylist()


def odd_stream_with(case: str) -> bytes:
    """One odd value at a time, so that each is shown to pass on its own."""
    recs = list(urwire.decode_file(SAMPLE))
    version = next(r for r in recs if r.TYPE == "version")
    state = next(r for r in recs if getattr(r, "packages", None)
                 and {p.TYPE for p in r.packages} >= {"robot_mode_data", "joint_data"})
    if case == "text":
        version.project_name = "URControl\udcff\udcfe"
    if case == "uint64":
        state.package(urwire.RobotModeData).timestamp = UINT64_MAX
    if case == "nan":
        state.package(urwire.JointData).joints[0].v_actual = float("nan")
    data = bytearray(state.encode())
    if case == "bool":
        data[BOOL_BYTE] = 2
    return version.encode() + bytes(data)


def export_case(tmp_path: Path, case: str, form: str, fmt: str) -> tuple[dict, Path]:
    if fmt == "parquet":
        pytest.importorskip("pyarrow")
    data = odd_stream_with(case) if case != "all" else odd_stream()
    if form == "stream":
        path = tmp_path / "odd.bin"
        path.write_bytes(data)
    else:
        path = capture.write(tmp_path / "odd.pcap", capture.robot_session([data]))
    shown = {r["type"]: r for r in records(run("decode", str(path)))}
    out = tmp_path / "tables"
    result = run("export", str(path), "--format", fmt, "--out", str(out))
    assert result.returncode == 0, result.stderr
    return shown, out


FORMS = [("stream", "csv"), ("stream", "parquet"), ("capture", "csv"), ("capture", "parquet")]


@pytest.mark.parametrize("form, fmt", FORMS)
def test_a_float32_nan_is_nan(tmp_path, form, fmt):
    _, out = export_case(tmp_path, "nan", form, fmt)
    (joints,) = table(out, "joint_data", fmt)
    assert math.isnan(float(joints["v_actual_0"]))


@pytest.mark.parametrize("form, fmt", FORMS)
def test_an_unsigned_64_bit_value_keeps_its_range(tmp_path, form, fmt):
    shown, out = export_case(tmp_path, "uint64", form, fmt)
    (mode,) = table(out, "robot_mode_data", fmt)
    assert int(mode["timestamp"]) == UINT64_MAX
    if fmt == "parquet":
        import pyarrow.parquet as pq
        assert str(pq.read_schema(out / "robot_mode_data.parquet").field("timestamp").type) == "uint64"


@pytest.mark.parametrize("form, fmt", FORMS)
def test_any_nonzero_bool_byte_is_true(tmp_path, form, fmt):
    shown, out = export_case(tmp_path, "bool", form, fmt)
    state = shown["robot_state"]["packages"][0]
    assert state["is_real_robot_connected"] is True
    (mode,) = table(out, "robot_mode_data", fmt)
    assert mode["is_real_robot_connected"] in (True, "True")


@pytest.mark.parametrize("form, fmt", FORMS)
def test_text_that_is_not_utf8_is_shown_as_decode_shows_it(tmp_path, form, fmt):
    shown, out = export_case(tmp_path, "text", form, fmt)
    (version,) = table(out, "version", fmt)
    assert version["project_name"] == shown["version"]["project_name"] == "URControl\ufffd\ufffd"


@pytest.mark.parametrize("form, fmt", FORMS)
def test_all_odd_values_at_once(tmp_path, form, fmt):
    shown, out = export_case(tmp_path, "all", form, fmt)
    assert {"version", "robot_mode_data", "joint_data"} <= {p.stem for p in out.iterdir()}


def test_every_unsigned_64_bit_field_is_marked_for_typed_columns():
    """The generated metadata says which fields are uint64, so that a column gets its type before
    any value is seen; a small timestamp still lands in a uint64 column."""
    import dataclasses

    from urwire.generated import messages

    wire = {f.name: f.metadata.get("wire") for f in dataclasses.fields(messages.RobotModeData)}
    assert wire["timestamp"] == "uint64" and wire["robot_mode"] is None


def test_export_names_a_stream_as_a_stream_when_it_cannot_read_it(tmp_path, monkeypatch, capsys):
    from urwire import cli
    from urwire.data import export

    def fails(*args, **kwargs):
        raise ValueError("bad bytes")

    path = tmp_path / "odd.bin"
    path.write_bytes(odd_stream())
    monkeypatch.setattr(export, "gather", fails)
    assert cli.main(["export", str(path), "--format", "csv", "--out", str(tmp_path / "t")]) == 2
    assert f"cannot read stream {path}" in capsys.readouterr().err
