"""The primary/secondary interface's kind: messages framed by an int32 length and a type byte,
robot state made of sub-packages, layouts gated by software version (spec/ur_primary.yaml)."""
from __future__ import annotations

from ..resolve import resolve
from ..targets import render_protocol
from . import DEFAULT_KIND, Kind

KIND = Kind(name=DEFAULT_KIND, schema="spec.schema.json", resolve=resolve, render=render_protocol)
