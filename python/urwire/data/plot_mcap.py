"""`urwire plot RECORDING.mcap`: what a viewer shows of a urwire recording without being told where to
look, drawn from the MCAP file itself (docs/recording-view.md):

- left, the joint positions over the recording's time, a line per joint: Foxglove's Plot panel on
  `.../joint_positions`;
- right, the TCP's path in the base frame with the tool's z axis (the way it points) at a few
  poses along it: its 3D panel on `.../tcp_pose` (a foxglove.PoseInFrame).

Both are found by their schemas, the ones urwire writes beside the records (mcap_robot.py,
docs/mcap.md). A recording with several sources (a capture of a cell: the primary, real-time and
RTDE conversations) is drawn from the one with the most joint positions; its topic prefix is the
figure's title. Only its two topics are read, through the file's index, and memory stays flat
however long the recording: the joints go through min/max decimation (decimate.py), the path keeps
every n-th pose.
"""
from __future__ import annotations

import json
import os
from typing import BinaryIO

from .. import __version__
from ..mcap_robot import JOINTS, JOINTS_SCHEMA_NAME, POSE_SCHEMA_NAME
from .decimate import MinMaxLines

MAGIC = b"\x89MCAP0\r\n"    # how every MCAP file opens (and ends)
PATH_POINTS = 2048          # at most this many poses of the path are kept
AXES_SHOWN = 12             # the tool's axis is drawn at this many poses along the path
AXIS_LENGTH = 0.08          # m


def is_mcap(path: str) -> bool:
    try:
        with open(path, "rb") as fh:
            return fh.read(len(MAGIC)) == MAGIC
    except OSError:
        return False


def ends_whole(fh: BinaryIO) -> bool:
    """Whether the file ends with MCAP's magic, as one whose writer finished does."""
    size = fh.seek(0, os.SEEK_END)
    fh.seek(max(size - len(MAGIC), 0))
    whole = size >= 2 * len(MAGIC) and fh.read(len(MAGIC)) == MAGIC
    fh.seek(0)
    return whole


class Thinned:
    """A path of any length kept in at most `most` points: every `stride`-th point; when full,
    every other point goes and the stride doubles, so the points stay evenly spread."""

    def __init__(self, most: int = PATH_POINTS) -> None:
        self.most, self.stride, self.seen = most, 1, 0
        self.points: list[tuple] = []

    def add(self, point: tuple) -> None:
        if self.seen % self.stride == 0:
            if len(self.points) == self.most:
                self.points = self.points[::2]
                self.stride *= 2
            if self.seen % self.stride == 0:
                self.points.append(point)
        self.seen += 1


def tool_z_axis(q: dict) -> tuple:
    """The third column of the rotation matrix of a unit quaternion: where the tool points."""
    x, y, z, w = q["x"], q["y"], q["z"], q["w"]
    return 2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)


def robot_topics(summary) -> tuple[str, dict[str, str]]:
    """The source (the topic prefix, `/<interface>/<conversation>`) with the most joint positions,
    of those with a pose too, and its topics by schema name (urwire's joints and
    foxglove.PoseInFrame); ("", {}) if none."""
    counts = summary.statistics.channel_message_counts if summary.statistics else {}
    sources: dict[str, dict[str, str]] = {}
    joints: dict[str, int] = {}
    for channel in summary.channels.values():
        schema = summary.schemas.get(channel.schema_id)
        if schema is not None and schema.name in (JOINTS_SCHEMA_NAME, POSE_SCHEMA_NAME):
            prefix = channel.topic.rsplit("/", 1)[0]
            sources.setdefault(prefix, {})[schema.name] = channel.topic
            if schema.name == JOINTS_SCHEMA_NAME:
                joints[prefix] = joints.get(prefix, 0) + counts.get(channel.id, 0)
    if not joints:
        return "", {}
    prefix = max(joints, key=lambda name: (len(sources[name]) == 2, joints[name], name))   # both topics first
    return prefix, sources[prefix]


class RecordedMotion:
    """The joints (decimated lines) and the TCP path (thinned) of one source, times in seconds from
    the recording's start."""

    def __init__(self, fh: BinaryIO) -> None:
        from mcap.exceptions import McapError   # an optional extra: urwire[mcap]
        from mcap.reader import make_reader

        self.joints, self.path = MinMaxLines(), Thinned()
        if not ends_whole(fh):
            raise ValueError("it does not end as an MCAP file does: a recording cut short (`mcap recover` mends it)")
        try:
            self._read(make_reader(fh))
        except (McapError, KeyError, TypeError) as exc:   # a cut file, or topics of another shape
            raise ValueError(f"{type(exc).__name__}: {exc}") from None

    def _read(self, reader) -> None:
        summary = reader.get_summary()
        if summary is None:
            raise ValueError("it has no summary")
        self.source, self.topics = robot_topics(summary)
        self.robot = dict(next((m.metadata for m in reader.iter_metadata() if m.name == "robot"), {}))
        start = summary.statistics.message_start_time if summary.statistics else 0
        if not self.topics:
            return
        for schema, _, message in reader.iter_messages(topics=list(self.topics.values())):
            data = json.loads(message.data)
            if schema.name == POSE_SCHEMA_NAME:
                pose = data["pose"]
                position = pose["position"]
                self.path.add((position["x"], position["y"], position["z"], *tool_z_axis(pose["orientation"])))
            else:
                self.joints.add((message.log_time - start) / 1e9, [data[name] for name in JOINTS])

    def title(self) -> str:
        robot = ", ".join(f"{key.replace('_', ' ')} {self.robot[key]}"
                          for key in ("robot_model", "software_version", "serial_number") if key in self.robot)
        return self.source + (f" ({robot})" if robot else "")


def draw(motion: RecordedMotion, out: str, plt) -> None:
    """The two panels of the module's docstring, written to `out` (PNG)."""
    fig = plt.figure(figsize=(11, 4.6))
    fig.suptitle(motion.title(), fontsize="medium")
    left = fig.add_subplot(1, 2, 1)
    for i, name in enumerate(JOINTS):
        left.plot(*motion.joints.line(i), label=name)
    left.set_xlabel("time since the recording's start (s)")
    left.set_ylabel("actual joint position (rad)")
    left.set_title(_shortened(motion.topics[JOINTS_SCHEMA_NAME]), fontsize="small")
    left.legend(loc="upper right", fontsize="x-small", ncol=2)
    right = fig.add_subplot(1, 2, 2, projection="3d")
    x, y, z, ax, ay, az = zip(*motion.path.points)
    right.plot(x, y, z, color="tab:blue", linewidth=1)
    every = max(1, len(x) // AXES_SHOWN)
    right.quiver(x[::every], y[::every], z[::every], ax[::every], ay[::every], az[::every],
                 length=AXIS_LENGTH, color="tab:red", linewidth=0.8)
    right.scatter([x[0]], [y[0]], [z[0]], color="black", s=12)
    spans = []
    for values, limits in zip((x, y, z), (right.set_xlim, right.set_ylim, right.set_zlim)):
        middle, half = (max(values) + min(values)) / 2, max((max(values) - min(values)) / 2, AXIS_LENGTH)
        limits(middle - half, middle + half)   # a TCP standing still still shows its tool's axis
        spans.append(half)
    right.set_box_aspect(spans)   # metres alike on every axis
    right.locator_params(nbins=4)
    right.set_xlabel("x (m)")
    right.set_ylabel("y (m)")
    right.set_zlabel("z (m)")
    right.set_title(f"{_shortened(motion.topics[POSE_SCHEMA_NAME])}: the TCP's path in the base frame,\n"
                    "the tool's z axis in red (start: black)", fontsize="small")
    fig.tight_layout()
    # Matplotlib names itself in the PNG's Software text; Source names what drew with it.
    fig.savefig(out, dpi=100, metadata={"Source": f"urwire {__version__} (urwire plot)"})
    plt.close(fig)



def _shortened(topic: str) -> str:
    return ".../" + topic.rsplit("/", 1)[-1]   # the source is the figure's title
