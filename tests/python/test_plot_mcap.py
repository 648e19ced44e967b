"""`urwire plot RECORDING.mcap` (data/plot_mcap.py, docs/recording-view.md): the joints and the TCP
path it draws are those the file holds, read from the source with the most joint positions, in
flat memory; and the command says what it cannot draw."""
from __future__ import annotations

import json
import math
from pathlib import Path
from types import SimpleNamespace

import pytest

from tests.python.test_cli import urwire
from tests.python.test_mcap import export

ROOT = Path(__file__).resolve().parents[2]
PRIMARY = ROOT / "dissector" / "samples" / "primary_session.pcapng"
START = 1_700_000_000_000_000_000   # ns
STEP = 20_000_000                   # 50 states a second

pytest.importorskip("mcap")


def simulated(path: Path, states: int, source: str = "/ur/10.0.0.2:30001-10.0.0.1:50000") -> list[tuple]:
    """An MCAP file as urwire writes its pose and joints (mcap_robot.py), of serve's moving arm, with
    a second source that has fewer joint positions; returns (t, q, pose) of each state written."""
    from mcap.writer import Writer

    from urwire.live.motion import Motion
    from urwire.live.robot_models import MODELS
    from urwire.mcap_robot import (JOINTS_SCHEMA, JOINTS_SCHEMA_NAME, POSE_SCHEMA, POSE_SCHEMA_NAME,
                                   joints_message, pose_message)

    motion = Motion(MODELS["ur5e"])
    written = []
    with open(path, "wb") as fh:
        writer = Writer(fh)
        writer.start(library="test")
        joints = writer.register_schema(JOINTS_SCHEMA_NAME, "jsonschema", JOINTS_SCHEMA)
        poses = writer.register_schema(POSE_SCHEMA_NAME, "jsonschema", POSE_SCHEMA)
        channels = {prefix: (writer.register_channel(f"{prefix}/joint_positions", "json", joints),
                             writer.register_channel(f"{prefix}/tcp_pose", "json", poses))
                    for prefix in (source, "/rtde/10.0.0.2:30004-10.0.0.1:50001")}
        for n in range(states):
            t = START + n * STEP
            for prefix, (joint_channel, pose_channel) in channels.items():
                if prefix != source and n % 10:
                    continue
                q = motion.joints(n * STEP / 1e9).q
                pose = motion.tcp_pose(q)
                writer.add_message(joint_channel, t, joints_message(list(q), t), t)
                writer.add_message(pose_channel, t, pose_message(list(pose), t), t)
                if prefix == source:
                    written.append((n * STEP / 1e9, q, pose))
        writer.add_metadata("robot", {"address": "10.0.0.2", "software_version": "5.11.0"})
        writer.finish()
    return written


def test_the_joints_and_path_are_those_of_the_file(tmp_path):
    from urwire.data.plot_mcap import RecordedMotion

    written = simulated(tmp_path / "r.mcap", 300)
    with open(tmp_path / "r.mcap", "rb") as fh:
        motion = RecordedMotion(fh)
    assert motion.source == "/ur/10.0.0.2:30001-10.0.0.1:50000"
    assert motion.title() == "/ur/10.0.0.2:30001-10.0.0.1:50000 (software version 5.11.0)"
    assert motion.joints.points == motion.path.seen == 300
    for joint in range(6):
        xs, ys = motion.joints.line(joint)
        assert xs == pytest.approx([t for t, _, _ in written])
        assert ys == pytest.approx([q[joint] for _, q, _ in written])
    assert [v for p in motion.path.points for v in p[:3]] == pytest.approx([v for *_, pose in written
                                                                            for v in pose[:3]])


def test_the_tool_axis_is_the_rotation_vectors_z_axis(tmp_path):
    from urwire.data.plot_mcap import tool_z_axis
    from urwire.mcap_robot import pose_message

    def axis(rx, ry, rz):
        return tool_z_axis(json.loads(pose_message([0, 0, 0, rx, ry, rz], 0))["pose"]["orientation"])

    assert axis(0, 0, 0) == pytest.approx((0, 0, 1))
    assert axis(math.pi / 2, 0, 0) == pytest.approx((0, -1, 0))      # about x: z turns to -y
    assert axis(0, math.pi, 0) == pytest.approx((0, 0, -1))          # UR's tool pointing down


def test_a_long_path_keeps_evenly_spread_points_in_bounded_memory():
    from urwire.data.plot_mcap import Thinned

    path = Thinned(most=8)
    for n in range(100):
        path.add((n,))
        assert len(path.points) <= 8
    assert path.seen == 100 and path.stride == 16
    assert path.points == [(n,) for n in range(0, 100, 16)]


def test_the_source_is_the_one_with_the_most_joint_positions():
    from urwire.data.plot_mcap import robot_topics
    from urwire.mcap_robot import JOINTS_SCHEMA_NAME, POSE_SCHEMA_NAME

    channels = {1: ("/ur_realtime/a/joint_positions", 1), 2: ("/ur/b/joint_positions", 1),
                3: ("/ur/b/tcp_pose", 2), 4: ("/rtde/c/joint_positions", 1), 5: ("/ur/d/joint_data", 3)}
    schemas = {1: JOINTS_SCHEMA_NAME, 2: POSE_SCHEMA_NAME, 3: "urwire.ur.joint_data"}
    summary = SimpleNamespace(
        channels={i: SimpleNamespace(id=i, topic=topic, schema_id=schema) for i, (topic, schema) in channels.items()},
        schemas={i: SimpleNamespace(name=name) for i, name in schemas.items()},
        statistics=SimpleNamespace(channel_message_counts={1: 5, 2: 9, 3: 9, 4: 20, 5: 50}))   # 4 has no pose
    assert robot_topics(summary) == ("/ur/b", {JOINTS_SCHEMA_NAME: "/ur/b/joint_positions",
                                               POSE_SCHEMA_NAME: "/ur/b/tcp_pose"})
    assert robot_topics(SimpleNamespace(channels={}, schemas={}, statistics=None)) == ("", {})


def test_plot_draws_a_recording_urwire_wrote(tmp_path):
    pytest.importorskip("matplotlib")
    recording = export(tmp_path, PRIMARY)
    out = tmp_path / "view.png"
    result = urwire("plot", str(recording), "--out", str(out))
    assert result.returncode == 0, result.stderr
    assert b": 210 joint positions, 210 TCP poses -> " in result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_what_plot_cannot_draw_is_said(tmp_path):
    pytest.importorskip("matplotlib")
    simulated(tmp_path / "r.mcap", 20)
    field = urwire("plot", str(tmp_path / "r.mcap"), "--field", "joint_data.q_actual", "--out", str(tmp_path / "a.png"))
    assert field.returncode == 2 and b"no --field" in field.stderr
    capture = urwire("plot", str(PRIMARY), "--out", str(tmp_path / "b.png"))
    assert capture.returncode == 2 and b"needs --field" in capture.stderr
    cut = tmp_path / "cut.mcap"
    cut.write_bytes((tmp_path / "r.mcap").read_bytes()[:400])
    broken = urwire("plot", str(cut), "--out", str(tmp_path / "c.png"))
    assert broken.returncode == 2, broken.stderr
    assert f"cannot read {cut}: it does not end as an MCAP file does".encode() in broken.stderr
    assert b"Traceback" not in field.stderr + capture.stderr + broken.stderr
    assert not any((tmp_path / name).exists() for name in ("a.png", "b.png", "c.png"))
