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
Writing needs the `mcap` package (pip install urwire[mcap]). `urwire export --format mcap` writes a
capture with it (data/mcap_export.py), `urwire listen --mcap` what it records (live/listen_views.py,
which also sends the same messages to a live viewer with `--foxglove`: RecordMessages).
"""
from __future__ import annotations

import json
import re
from decimal import Decimal
from typing import BinaryIO, NamedTuple, Optional

from . import __version__, mcap_robot
from .canonical import has_error, to_json_line
from .cell import PRIMARY
from .envelope import Enveloped
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


class Message(NamedTuple):
    """One message for a viewer: an MCAP message, or a Foxglove WebSocket one (foxglove_server)."""
    topic: str
    schema_name: str
    schema: bytes       # its JSON Schema's text
    data: bytes         # the message, strict JSON
    log_time: int       # nanoseconds since the epoch


class RecordMessages:
    """What records are for a viewer: each record's messages, on their topics with their schemas,
    and what the records say of each robot (`robots`, by address). The MCAP file and the live view
    (`listen --foxglove`) both take their channels, schemas and messages from here."""

    def __init__(self) -> None:
        self._schemas: dict[str, bytes] = {}
        self.robots: dict[str, dict[str, str]] = {}

    def of(self, position: int, item) -> list[Message]:
        """One record's messages: Enveloped, from a capture, or a raw primary stream's record as it is."""
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
        out = []
        for part in parts:
            if part is record:
                line = to_json_line(item)       # as decode prints it
            else:                               # a sub-package, with its record's envelope
                line = to_json_line(Enveloped(item.interface, item.direction, item.conversation, part)
                                    if enveloped else part)
            line = strict_json(line)
            shown = json.loads(line)
            kind = "error" if has_error(part) else str(shown.get("type", "unknown"))
            name = f"urwire.{interface}.{kind}"
            out.append(Message(f"{base}/{kind}", name, self._schema(name, type(part)), line.encode(), log_time))
            if kind != "error":
                out.extend(self._robot_parts(base, kind, shown, log_time))
                if enveloped and item.conversation is not None:
                    self._learn(item.conversation.robot_address, interface, kind, shown)
        return out

    def _schema(self, name: str, cls: type) -> bytes:
        """A record kind's schema, made from the class of the first record of the kind."""
        if name not in self._schemas:
            self._schemas[name] = json.dumps({**ANY_RECORD, "title": name}).encode() if name.endswith(".error") \
                else schema_text(cls, name)
        return self._schemas[name]

    @staticmethod
    def _robot_parts(base: str, kind: str, shown: dict, log_time: int) -> list[Message]:
        pose, joints = mcap_robot.pose_and_joints(kind, shown)
        out = []
        if pose is not None:
            out.append(Message(f"{base}/tcp_pose", mcap_robot.POSE_SCHEMA_NAME, mcap_robot.POSE_SCHEMA,
                               mcap_robot.pose_message(pose, log_time), log_time))
        if joints is not None:
            out.append(Message(f"{base}/joint_positions", mcap_robot.JOINTS_SCHEMA_NAME, mcap_robot.JOINTS_SCHEMA,
                               mcap_robot.joints_message(joints, log_time), log_time))
        return out

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


class McapRecording:
    """Records written to an open binary file as they come; finish() writes the summary. `messages`
    is where they become messages (its robots the metadata), shared when another view takes them too."""

    def __init__(self, fh: BinaryIO, messages: Optional[RecordMessages] = None) -> None:
        from mcap.writer import Writer   # the optional extra, needed only here
        self._writer = Writer(fh)
        self._writer.start(profile="", library=LIBRARY)
        self.messages = messages or RecordMessages()
        self._schemas: dict[str, int] = {}
        self._channels: dict[str, int] = {}
        self._sequence: dict[int, int] = {}
        self.counts: dict[str, int] = {}

    def add(self, position: int, item) -> None:
        """One record: Enveloped, from a capture, or a raw primary stream's record as it is."""
        for message in self.messages.of(position, item):
            self.write(message)

    def write(self, message: Message) -> None:
        schema = self._schemas.get(message.schema_name)
        if schema is None:
            schema = self._schemas[message.schema_name] = \
                self._writer.register_schema(message.schema_name, "jsonschema", message.schema)
        channel = self._channels.get(message.topic)
        if channel is None:
            channel = self._channels[message.topic] = self._writer.register_channel(message.topic, "json", schema)
        sequence = self._sequence.get(channel, 0)
        self._sequence[channel] = sequence + 1
        self._writer.add_message(channel, log_time=message.log_time, data=message.data,
                                 publish_time=message.log_time, sequence=sequence)
        self.counts[message.topic] = self.counts.get(message.topic, 0) + 1

    def finish(self) -> None:
        robots = self.messages.robots
        for address in sorted(robots):
            self._writer.add_metadata("robot", robots[address])
        self._writer.finish()
