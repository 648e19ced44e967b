"""Records as one MCAP file (docs/mcap.md), the robotics log format that Foxglove,
PlotJuggler and Rerun open.

A channel per interface, conversation and record kind, topic /<interface>/<conversation>/<kind>
(a robot state's sub-packages each on the channel of their kind, as `export` gives each its
table; a raw stream, which has no conversation, /<interface>/<kind>); each message is the record's
canonical JSON as `decode` prints it, envelope included, and each channel's schema the JSON Schema
of its class (mcap_schema). Records with an error go to their interface's `error` channel as
decode prints them. Beside them, per interface and conversation, the TCP pose as
foxglove.PoseInFrame (/.../tcp_pose) and the joint positions (/.../joint_positions: mcap_robot).
Log times are the capture's times in nanoseconds since the epoch; a raw stream has none, and its
records are numbered instead (the n-th at n ns) so that the order stays. A `robot` metadata record
per robot address holds what the capture says of it: software version, serial number, model.
Needs the `mcap` package (pip install urwire[mcap]). `urwire export --format mcap` writes a capture
with it (data/mcap_export.py), `urwire listen --mcap` what it records.
"""
from __future__ import annotations

import json
import re
import time
from decimal import Decimal
from typing import BinaryIO, Optional

from . import __version__, mcap_robot
from .canonical import has_error, to_json_line
from .cell import PRIMARY
from .envelope import FROM_ROBOT, Endpoints, Enveloped
from .mcap_schema import ANY_RECORD, schema_text

LIBRARY = f"urwire {__version__}"
_VERSION = "{major_version}.{minor_version}.{bugfix_version}.{build_number}"   # the primary's version message
_RTDE_VERSION = "{major}.{minor}.{bugfix}.{build}"                             # RTDE's controller version
# The dashboard commands whose reply is a fact of the robot, by the metadata key it goes under.
_DASHBOARD_FACTS = {"get_serial_number": "serial_number", "get_robot_model": "robot_model"}


def mcap_missing() -> Optional[str]:
    """Why MCAP cannot be written here, or None when the mcap package is installed."""
    try:
        import mcap  # noqa: F401
    except ImportError:
        return "MCAP needs the mcap package: pip install urwire[mcap]"
    return None


# A JSON string (kept as it is), or a non-finite number as the canonical JSON writes it.
_STRING_OR_NONFINITE = re.compile(r'"(?:[^"\\]|\\.)*"|-?Infinity|NaN')


def strict_json(line: str) -> str:
    """A canonical JSON line as strict JSON, which Foxglove's parser demands: NaN and the
    infinities, bare in the canonical JSON (docs/canonical-json.md), become null; all else stays."""
    if "NaN" not in line and "Infinity" not in line:
        return line
    return _STRING_OR_NONFINITE.sub(lambda m: m.group(0) if m.group(0)[0] == '"' else "null", line)


def nanoseconds(seconds: float) -> int:
    """A capture time in whole nanoseconds, from its shortest decimal text: 1700000000.066 gives
    ...066000000, where seconds * 1e9 would give ...065999872."""
    return int(Decimal(repr(seconds)).scaleb(9).to_integral_value())


class McapRecording:
    """Records written to an open binary file as they come; finish() writes the summary."""

    def __init__(self, fh: BinaryIO) -> None:
        from mcap.writer import Writer   # the optional extra, needed only here
        self._writer = Writer(fh)
        self._writer.start(profile="", library=LIBRARY)
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._sequence: dict[int, int] = {}
        self.robots: dict[str, dict[str, str]] = {}
        self.counts: dict[str, int] = {}

    def add(self, position: int, item) -> None:
        """One record: Enveloped, from a capture, or a raw primary stream's record as it is."""
        enveloped = isinstance(item, Enveloped)
        record = item.record if enveloped else item
        seconds = item.capture_time if enveloped else None
        log_time = position if seconds is None else nanoseconds(seconds)
        interface = (item.interface if enveloped else None) or PRIMARY
        base = f"/{interface}/{item.conversation}" if enveloped and item.conversation else f"/{interface}"
        if has_error(record) or not hasattr(record, "packages"):
            parts = [record]
        else:
            parts = record.packages
        for part in parts:
            if part is record:
                line = to_json_line(item)       # as decode prints it
            else:                               # a sub-package, with its record's envelope
                line = to_json_line(Enveloped(item.interface, item.direction, item.conversation, part)
                                    if enveloped else part)
            line = strict_json(line)
            shown = json.loads(line)
            kind = "error" if has_error(part) else str(shown.get("type", "unknown"))
            self._write(f"{base}/{kind}", type(part), f"urwire.{interface}.{kind}", line.encode(), log_time)
            if kind != "error":
                self._robot_parts(base, kind, shown, log_time)
                if enveloped and item.conversation is not None:
                    self._learn(item.conversation.robot_address, interface, kind, shown)

    def _robot_parts(self, base: str, kind: str, shown: dict, log_time: int) -> None:
        pose, joints = mcap_robot.pose_and_joints(kind, shown)
        if pose is not None:
            self._write_as(f"{base}/tcp_pose", mcap_robot.POSE_SCHEMA_NAME, mcap_robot.POSE_SCHEMA,
                           mcap_robot.pose_message(pose, log_time), log_time)
        if joints is not None:
            self._write_as(f"{base}/joint_positions", mcap_robot.JOINTS_SCHEMA_NAME, mcap_robot.JOINTS_SCHEMA,
                           mcap_robot.joints_message(joints, log_time), log_time)

    def _learn(self, address: Optional[str], interface: str, kind: str, shown: dict) -> None:
        """What a record says of its robot: the software version (the primary interface's version
        message, RTDE's controller version), or a dashboard reply with its serial number or model."""
        robot = self.robots.setdefault(address, {"address": address})
        if interface == PRIMARY and kind == "version":
            robot["software_version"] = _VERSION.format(**shown)
        elif kind == "get_urcontrol_version_reply":
            robot.setdefault("software_version", _RTDE_VERSION.format(**shown))
        elif kind == "reply" and interface == "ur_dashboard" and not shown.get("error"):
            name = _DASHBOARD_FACTS.get(shown.get("command_name"))
            if name:
                robot[name] = str(shown["reply"])

    def _write(self, topic: str, cls: type, schema_name: str, data: bytes, log_time: int) -> None:
        """A record kind's message; its schema is made from the class of the first record of the kind."""
        if schema_name not in self._schemas:
            text = json.dumps({**ANY_RECORD, "title": schema_name}).encode() if schema_name.endswith(".error") \
                else schema_text(cls, schema_name)
            self._schemas[schema_name] = self._writer.register_schema(schema_name, "jsonschema", text)
        self._message(topic, self._schemas[schema_name], data, log_time)

    def _write_as(self, topic: str, name: str, text: bytes, data: bytes, log_time: int) -> None:
        if name not in self._schemas:
            self._schemas[name] = self._writer.register_schema(name, "jsonschema", text)
        self._message(topic, self._schemas[name], data, log_time)

    def _message(self, topic: str, schema: int, data: bytes, log_time: int) -> None:
        channel = self._channels.get(topic)
        if channel is None:
            channel = self._channels[topic] = self._writer.register_channel(topic, "json", schema)
        sequence = self._sequence.get(channel, 0)
        self._sequence[channel] = sequence + 1
        self._writer.add_message(channel, log_time=log_time, data=data, publish_time=log_time, sequence=sequence)
        self.counts[topic] = self.counts.get(topic, 0) + 1

    def finish(self) -> None:
        for address in sorted(self.robots):
            self._writer.add_metadata("robot", self.robots[address])
        self._writer.finish()


def endpoints_of(sock) -> Endpoints:
    """The conversation of a connection this side opened: the peer listens."""
    peer, own = sock.getpeername(), sock.getsockname()
    return Endpoints(peer[0], peer[1], own[0], own[1])


class McapFile:
    """`urwire listen --mcap FILE`: the records of a live connection as they come, each stamped
    with the time it was decoded and enveloped with its interface and the current connection's
    conversation (set by listen on each connection); close() writes the summary."""

    def __init__(self, path: str, interface: str) -> None:
        self.path, self.interface = path, interface
        self.conversation: Optional[Endpoints] = None
        self._fh = open(path, "wb")
        self._recording = McapRecording(self._fh)

    def add(self, position: int, record) -> None:
        self._recording.add(position, Enveloped(self.interface, FROM_ROBOT, self.conversation, record, time.time()))

    def close(self) -> None:
        try:
            self._recording.finish()
        finally:
            self._fh.close()
