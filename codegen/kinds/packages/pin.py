"""An optional pass between resolve and plan: the protocol as one software version sends it.

`pin(protocol, (5, 11, 0))` keeps only the layouts, fields, enum tables and value-type table of
that version, and drops their version ranges, so that the targets render no version branches at
all. Small firmware that talks to one controller generation builds this
(`make pinned-c PIN=5.11`).
"""
from __future__ import annotations

import copy
import dataclasses

from ... import ir
from . import model


def pin(protocol: model.Protocol, version: ir.Version) -> model.Protocol:
    p = copy.deepcopy(protocol)
    for e in p.enums.values():
        e.tables = [_table_for(e, version)]
    for m in p.messages:
        if isinstance(m, model.PackageListMessage):
            m.packages = [_layout(lay, version) for lay in m.packages if lay.versions.contains(version)]
        else:
            m.header = m.header.at(version)
            m.subtypes = [_layout(lay, version) for lay in m.subtypes if lay.versions.contains(version)]
    p.documented_versions = [version]
    p.default_version = version
    return p


def _table_for(e: ir.Enum, version: ir.Version) -> ir.EnumTable:
    table = e.table_for(version)
    return ir.EnumTable(ir.ALL_VERSIONS, [dataclasses.replace(v, versions=ir.ALL_VERSIONS) for v in table.values])


def _layout(lay: model.Layout, version: ir.Version) -> model.Layout:
    struct = lay.struct.at(version)
    sets_version = lay.sets_version
    if sets_version and sets_version[2] and not struct.named(sets_version[2]):
        # The version's form has no bugfix number (the Version message up to 3.2): 0 then.
        sets_version = (sets_version[0], sets_version[1], None)
    return dataclasses.replace(lay, struct=struct, versions=ir.ALL_VERSIONS, sets_version=sets_version)
