"""`urwire export --format mcap` of a capture of the whole cell (dissector/samples/cell_session.pcapng),
read back with the `mcap` package's reader: the summary, the chunk indexes, the metadata and every
message against the records urwire decodes from the same capture (docs/mcap.md)."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "dissector" / "samples" / "cell_session.pcapng"
ENV = {"PYTHONPATH": f"{ROOT / 'python'}:{ROOT / 'generated' / 'python'}"}
ENVELOPE = ("interface", "direction", "conversation")
JOINTS = ("base", "shoulder", "elbow", "wrist_1", "wrist_2", "wrist_3")

pytest.importorskip("mcap")


def export(out: Path, source: Path = SAMPLE) -> Path:
    """The real command on a capture or raw stream (the sample by default), as a user runs it; the
    file it writes."""
    done = subprocess.run([sys.executable, "-m", "urwire", "export", "--format", "mcap", "--out", str(out),
                           str(source)], capture_output=True, text=True, env=ENV, timeout=120)
    assert done.returncode == 0, done.stderr
    return out / f"{source.stem}.mcap"


def raw_vector(folder: Path, name: str) -> Path:
    """A golden vector's bytes as a raw stream file."""
    from tests.vectors import golden_cases

    raw = folder / f"{name}.raw"
    raw.write_bytes(next(c for c in golden_cases() if c.name == name).data)
    return raw


def dashboard_capture(folder: Path) -> Path:
    """A dashboard conversation that asks the robot's serial number and model."""
    from tests.tools import capture
    from tests.tools.capture import Segment

    talk = [Segment(True, b"Connected: Universal Robots Dashboard Server\n"),
            Segment(False, b"get serial number\n"), Segment(True, b"20185500042\n"),
            Segment(False, b"get robot model\n"), Segment(True, b"UR5\n")]
    return capture.write(folder / "dashboard.pcapng", capture.session_frames(talk, port=29999), pcapng=True)


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> Path:
    return export(tmp_path_factory.mktemp("mcap"))


def expected_messages() -> list[tuple[str, int, dict]]:
    """(topic, log time, message) of each record kind's message, in capture order, from the records
    urwire decodes: a robot state's sub-packages each on their own, with the record's envelope."""
    from urwire.canonical import to_dict
    from urwire.data.records import records_of_file

    out = []
    with open(SAMPLE, "rb") as fh:
        for item in records_of_file(fh):
            shown = to_dict(item)
            time = int(Decimal(repr(item.capture_time)) * 10**9)
            envelope = {k: shown[k] for k in ENVELOPE}
            for part in shown.pop("packages", None) or [shown]:
                out.append((f"/{item.interface}/{item.conversation}/{part['type']}", time, {**envelope, **part}))
    return out


def read_back(path: Path) -> tuple:
    from mcap.reader import make_reader

    with open(path, "rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        messages = [(channel.topic, schema.name, message) for schema, channel, message in reader.iter_messages()]
        metadata = [(m.name, m.metadata) for m in reader.iter_metadata()]
    return summary, messages, metadata


def test_every_record_is_a_message_on_its_kinds_channel(written):
    _, messages, _ = read_back(written)
    records = [(topic, m.log_time, json.loads(m.data)) for topic, _, m in messages
               if not topic.endswith(("/tcp_pose", "/joint_positions"))]
    assert records == expected_messages()
    assert len(records) == 82   # 69 records, one of them a robot state of 14 sub-packages


def test_summary_and_chunk_indexes(written):
    summary, messages, _ = read_back(written)
    topics = {topic for topic, _, _ in messages}
    assert {c.topic for c in summary.channels.values()} == topics
    assert len(summary.channels) == len(topics) == 54
    # A schema per record kind, and the two that every interface shares: the pose and the joints.
    assert len(summary.schemas) == len({name for _, name, _ in messages}) == 45
    assert {s.encoding for s in summary.schemas.values()} == {"jsonschema"}
    assert {c.message_encoding for c in summary.channels.values()} == {"json"}
    assert summary.statistics.message_count == len(messages) == 88
    assert summary.statistics.channel_message_counts == {
        id: sum(1 for topic, _, _ in messages if topic == c.topic) for id, c in summary.channels.items()}
    assert summary.chunk_indexes
    for chunk in summary.chunk_indexes:
        inside = [m for _, _, m in messages if chunk.message_start_time <= m.log_time <= chunk.message_end_time]
        assert inside and set(chunk.message_index_offsets) <= set(summary.channels)
    assert min(c.message_start_time for c in summary.chunk_indexes) == summary.statistics.message_start_time
    assert max(c.message_end_time for c in summary.chunk_indexes) == summary.statistics.message_end_time
    assert sum(len(c.message_index_offsets) for c in summary.chunk_indexes) >= len(summary.channels)


def test_every_message_fits_its_schema_and_labels_describe_fields(written):
    jsonschema = pytest.importorskip("jsonschema")
    summary, messages, _ = read_back(written)
    schemas = {s.name: json.loads(s.data) for s in summary.schemas.values()}
    for _, name, message in messages:
        jsonschema.validate(json.loads(message.data), schemas[name])
    joints = schemas["urwire.ur.joint_data"]["properties"]["joints"]["items"]["properties"]
    assert joints["q_actual"]["description"] == "Actual joint position [rad]"
    assert schemas["urwire.ur.robot_mode_data"]["properties"]["robot_mode"] == {"type": "integer",
                                                                               "description": "Robot mode"}
    assert schemas["foxglove.PoseInFrame"]["title"] == "foxglove.PoseInFrame"


def test_pose_and_joints_for_foxglove(written):
    _, messages, _ = read_back(written)
    by_topic = {}
    for topic, _, m in messages:
        by_topic.setdefault(topic, []).append((m.log_time, json.loads(m.data)))
    primary = "/ur/192.168.56.101:30001-192.168.56.1:50101"
    (state_time, cartesian), = by_topic[f"{primary}/cartesian_info"]
    (pose_time, pose), = by_topic[f"{primary}/tcp_pose"]
    assert pose_time == state_time and pose["frame_id"] == "base"
    assert pose["timestamp"] == {"sec": state_time // 10**9, "nsec": state_time % 10**9}
    assert pose["pose"]["position"] == {k: cartesian[k] for k in "xyz"}
    # The quaternion turns back into the rotation vector the robot sent.
    q = pose["pose"]["orientation"]
    angle = 2 * math.acos(q["w"])
    axis = [q[k] / math.sin(angle / 2) for k in "xyz"]
    assert [a * angle for a in axis] == pytest.approx([cartesian[k] for k in ("rx", "ry", "rz")], abs=1e-12)
    assert math.isclose(sum(v * v for v in q.values()), 1.0)
    (_, joint_data), = by_topic[f"{primary}/joint_data"]
    (_, joints), = by_topic[f"{primary}/joint_positions"]
    assert [joints[name] for name in JOINTS] == [j["q_actual"] for j in joint_data["joints"]]
    # The real-time interface's pose, and RTDE's joints where its recipe has actual_q.
    (_, realtime), = by_topic["/ur_realtime/192.168.56.101:30003-192.168.56.1:50102/rt_5_10"]
    (_, rt_joints), = by_topic["/ur_realtime/192.168.56.101:30003-192.168.56.1:50102/joint_positions"]
    assert [rt_joints[name] for name in JOINTS] == realtime["q_actual"]
    rtde = [(t, m) for topic, items in by_topic.items() if topic.startswith("/rtde/") and "/data_package" in topic
            for t, m in items if "actual_q" in m]
    rtde_joints = [(t, [m[name] for name in JOINTS]) for topic, items in by_topic.items()
                   if topic.startswith("/rtde/") and topic.endswith("/joint_positions") for t, m in items]
    assert sorted(rtde_joints) == sorted((t, m["actual_q"]) for t, m in rtde) and len(rtde) == 2


def test_metadata_says_the_robot(written):
    _, _, metadata = read_back(written)
    assert metadata == [("robot", {"address": "192.168.56.101", "software_version": "5.11.1.108318"})]


def test_log_times_are_the_captures_exact_times(written):
    _, messages, _ = read_back(written)
    times = [m.log_time for _, _, m in messages]
    assert times == sorted(times) and times[0] == 1_700_000_000_066_000_000


def test_dataset_refuses_mcap(tmp_path):
    done = subprocess.run([sys.executable, "-m", "urwire", "export", "--format", "mcap", "--dataset",
                           str(tmp_path), str(SAMPLE)], capture_output=True, text=True, env=ENV, timeout=120)
    assert done.returncode == 2


def test_metadata_takes_the_serial_number_and_model_from_the_dashboard(tmp_path):
    from tests.tools import capture

    _, messages, metadata = read_back(export(tmp_path, dashboard_capture(tmp_path)))
    assert metadata == [("robot", {"address": capture.ROBOT, "serial_number": "20185500042", "robot_model": "UR5"})]
    assert [json.loads(m.data)["reply"] for topic, _, m in messages if topic.endswith("/reply")] == \
        ["Connected: Universal Robots Dashboard Server", "20185500042", "UR5"]


def test_a_raw_stream_numbers_its_records_in_place_of_times(tmp_path):
    from urwire.canonical import to_dict
    from urwire.reading import records_of_raw

    raw = raw_vector(tmp_path, "generation_eseries_5_11_robot_state")
    _, messages, metadata = read_back(export(tmp_path / "out", raw))
    with open(raw, "rb") as fh:
        records = [to_dict(r) for r in records_of_raw(fh, None, lambda n: None)]
    expected = [(f"/ur/{part['type']}", position, part) for position, record in enumerate(records)
                for part in record.get("packages") or [record]]
    assert [(topic, m.log_time, json.loads(m.data)) for topic, _, m in messages
            if not topic.endswith(("/tcp_pose", "/joint_positions"))] == expected
    assert {topic for topic, _, _ in messages} >= {"/ur/tcp_pose", "/ur/joint_positions"}
    assert metadata == []   # a raw stream says no robot address


def test_non_finite_floats_become_null_for_a_strict_json_parser(tmp_path):
    jsonschema = pytest.importorskip("jsonschema")
    from urwire.canonical import to_json_line
    from urwire.reading import records_of_raw

    raw = raw_vector(tmp_path, "nonfinite_floats")
    summary, messages, _ = read_back(export(tmp_path / "out", raw))
    with open(raw, "rb") as fh:
        canonical = [json.loads(to_json_line(r)) for r in records_of_raw(fh, None, lambda n: None)]
    parts = [part for record in canonical for part in record.get("packages") or [record]]

    def no_constant(name):
        raise ValueError(f"{name} is not strict JSON")

    def nulled(value):   # the canonical value with each NaN and infinity as None
        if isinstance(value, dict):
            return {k: nulled(v) for k, v in value.items()}
        if isinstance(value, list):
            return [nulled(v) for v in value]
        return None if isinstance(value, float) and not math.isfinite(value) else value

    schemas = {s.name: json.loads(s.data) for s in summary.schemas.values()}
    got = []
    for topic, name, m in messages:
        message = json.loads(m.data, parse_constant=no_constant)
        jsonschema.validate(message, schemas[name])
        if not topic.endswith(("/tcp_pose", "/joint_positions")):
            got.append(message)
    assert got == [nulled(part) for part in parts]
    assert any(json.dumps(p) != json.dumps(nulled(p)) for p in parts)   # the vector has some
