"""The IR of an interface of fixed int32 records (the ROS driver's sockets): each direction's
record, its fields (counts, scales, enums) and the driver releases that send each field."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir

TO_ROBOT, FROM_ROBOT = "to_robot", "from_robot"


@dataclass(frozen=True)
class Int32Field:
    name: str
    label: str
    doc: str
    count: int                     # 1: one value; more: a list of that many
    scale: Optional[int]           # the wire holds round(value * scale); None: the value itself
    scale_name: str                # the driver's constant for the scale (MULT_JOINTSTATE)
    unit: Optional[str]
    enum: Optional[ir.Enum]
    versions: ir.VersionRange      # the driver releases that send it
    where: ir.Where


@dataclass(frozen=True)
class Record:
    name: str
    direction: str                 # TO_ROBOT (the control PC sends it) or FROM_ROBOT
    label: str
    doc: str
    fields: tuple[Int32Field, ...]
    where: ir.Where


@dataclass(frozen=True)
class RecordsProtocol:
    name: str
    title: str
    doc: str
    ports: tuple[int, ...]
    releases: tuple[ir.Version, ...]     # the driver releases the spec was written from
    default_release: ir.Version          # what a decoder takes when it is told none
    enums: dict[str, ir.Enum]
    records: tuple[Record, ...]
