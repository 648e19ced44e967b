"""The kind `int32_records`: interfaces whose records are fixed runs of big-endian int32 with no
length header, values scaled by powers of ten, layouts gated by driver release (the ROS driver's
reverse, trajectory and script command sockets: spec/ur_reverse.yaml and its siblings)."""
from __future__ import annotations

from .. import define
from . import c, diff, epan, lua, plan, python, resolve

KIND = define("int32_records", "int32_records.schema.json", resolve, plan, [c, epan, lua, python],
             diff.diff)
