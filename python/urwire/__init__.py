"""urwire: decode and encode every interface of a Universal Robots cell, from one spec: the
primary/secondary client interface, the real-time interface, RTDE, the dashboard server and the
ROS driver's sockets, on every software version from CB2 to PolyScope X.

    import urwire
    for record in urwire.decode_capture("session.pcapng"):   # every interface of a cell's capture
        print(record.interface, record.conversation, urwire.to_json_line(record.record))
    for record in urwire.decode_file("session.raw"):         # the primary interface: a raw stream or a capture
        print(urwire.to_json_line(record))

This package is the decoding core. `decode_capture` reads a .pcap/.pcapng capture (capture.py
reassembles its TCP streams, cell.py hands each conversation to its interface's decoder by port,
interfaces.py), each record Enveloped with its interface, direction and conversation (Endpoints);
`decode_file` reads the primary interface of a raw stream or a capture; `Framer` and `decode_stream` frame such a
stream in chunks and `decode_message` decodes one message; realtime.py, rtde.py and the decoders
of the dashboard and the driver's sockets (generated.ur_*, over text_lines.py and
int32_records.py) do the same for the other interfaces; `to_dict` and `to_json_line` give the
canonical JSON that every urwire decoder prints. The primary interface's records and enums are
offered here by name (urwire.RobotStateMessage, urwire.RobotMode); every interface's are in
`urwire.generated`, which `make generate` writes from the spec (in the source tree under
generated/python/urwire/, which extend_path adds to this package's path when both python/ and
generated/python/ are on sys.path).

Two subpackages build on it and never on each other: urwire.live (`urwire serve`, a simulated
robot cell, and `urwire listen`) and urwire.data (`urwire export`, the dataset, `urwire spark`,
`urwire plot`). The `urwire` command (cli.py, also `python -m urwire`) joins them.
"""
import os
from pkgutil import extend_path

# Other folders named urwire on sys.path join this package: in the tree, generated/python/urwire,
# which holds the subpackage `generated` and no __init__.py. A folder with an __init__.py of its
# own is another install of urwire and stays out, so that none of its modules is imported here.
_OWN = list(__path__)
__path__ = [p for p in extend_path(__path__, __name__)
            if p in _OWN or not os.path.isfile(os.path.join(p, "__init__.py"))]

from ._runtime import (DecodeError, EncodeError, GlobalValue, MalformedPackage, MalformedSubtype,  # noqa: E402
                       StreamError, UnknownMessage, UnknownPackage, UnknownSubtype)
from .arguments import parse_version  # noqa: E402
from .backends import backend  # noqa: E402
from .canonical import to_dict, to_json_line  # noqa: E402
from .decoding import decode_message, encode_message, package_classes  # noqa: E402
from .framer import Framer, decode_stream  # noqa: E402
from .message_kinds import encode_package  # noqa: E402
from .envelope import Endpoints, Enveloped  # noqa: E402
from .reading import CaptureRecords, decode_capture, decode_file  # noqa: E402
from .generated.spec import DEFAULT_VERSION, DOCUMENTED_VERSIONS, PORTS  # noqa: E402
# The primary interface's records and enums by name (tests/python/test_package_layers.py checks
# that every class of generated.messages and generated.enums is here).
from .generated.enums import (  # noqa: E402,F401
    ControlBoxType, ControlMode, JointMode, JointMode3_0To3_15, JointMode5_0To5_0, JointModeUpTo1_8,
    MasterOnOffState, MasterSafetyState, MessageSource, MessageSourceUpTo1_8, MessageType, PackageType,
    PackageTypeUpTo1_7, ProgramStateMessageType, ReportLevel, RequestedType, RobotMessageType,
    RobotMessageTypeUpTo1_8, RobotMode, RobotModeUpTo1_8, SafetyMode, SafetyStatus, ToolFlangeType, ToolMode,
    ValueType, ValueType3_3To5_8, ValueTypeUpTo3_2)
from .generated.messages import (  # noqa: E402,F401
    AdditionalInfo, CalibrationData, CartesianInfo, ConfigurationData, ForceModeData, GlobalVariablesSetupMessage,
    GlobalVariablesUpdateMessage, HardwareInfoMessage, HmcMessage, Joint, JointData, JointMotionLimit,
    JointPositionLimit, KeyMessage, KinematicsInfo, LabelMessage, LaserPointer, MasterboardData, ModbusInfoMessage,
    PayloadInfo, PopupMessage, ProgramThread, ProgramThreadsMessage, RequestValueMessage, RobotCommMessage,
    RobotMessage12Message, RobotModeData, RobotStateMessage, RuntimeExceptionMessage,
    SafetyComplianceTolerancesMessage, SafetyData, SafetyModeMessage, SafetySetupBroadcastMessage, SingularityInfo,
    TextMessage, ToolCommInfo, ToolData, ToolModeInfo, VarMessage, VersionMessage)

__version__ = "0.1.0"

__all__ = [
    "DecodeError", "EncodeError", "GlobalValue", "MalformedPackage", "MalformedSubtype", "StreamError",
    "UnknownMessage", "UnknownPackage", "UnknownSubtype", "Framer", "decode_stream", "parse_version",
    "decode_file", "decode_capture", "CaptureRecords", "Enveloped", "Endpoints", "decode_message", "encode_message",
    "package_classes", "to_dict", "to_json_line",
    "DEFAULT_VERSION", "DOCUMENTED_VERSIONS", "PORTS", "backend",
]
