"""The selection pass of the primary interface (codegen/select.py): a protocol with only the
messages and layouts a firmware reads.

A pick is a message (`robot_state`: every layout it has) or one of its layouts
(`robot_state.joint_data`, `robot_message.text`). What is not picked loses its layout and nothing
else: its codes stay in their enums, so the framer still frames every message type, and a
sub-package or subtype without a layout is kept raw with its type and length, as the codes the
spec names but does not lay out always were (never an error). Two parts are always kept:

- the layout that announces the software version (the Version message), which the framer reads
  to know the version of every other message;
- at least one robot-state sub-package: every target's parser is built around the robot state,
  and a selection with none is refused.

A type code whose layouts change across versions (code 5: `laser_pointer` up to 1.7, then
`kinematics_info`) is picked whole or not at all, or a stream of the other versions would be read
in the wrong layout; after --pin, one layout is left and it is picked alone. Enums that only the
dropped layouts used are dropped with them (their name functions and texts with them).
"""
from __future__ import annotations

import copy

from ... import ir
from ...errors import Problem
from ...select import Pick, unknown
from . import model


def select(protocol: model.Protocol, picks: tuple[Pick, ...], where: ir.Where) -> tuple[model.Protocol, list[Problem]]:
    problems: list[Problem] = []
    wanted = _wanted(protocol, picks, problems)
    for m in protocol.messages:
        kept = _kept(m, wanted.get(m.name, set()))
        for lay in kept:
            problems += _split_code(m, lay, kept, wanted.get(m.name), picks)
        if isinstance(m, model.PackageListMessage) and not kept and not problems:
            example = f"{m.name}.{m.packages[0].name}"
            problems.append(where.problem(f"keep at least one {m.name} sub-package (e.g. {example}): the parser "
                                          "is built around the robot state"))
    if problems:
        return protocol, problems
    p = copy.deepcopy(protocol)
    messages = []
    for m in p.messages:
        kept = _kept(m, wanted.get(m.name, set()))
        if isinstance(m, model.PackageListMessage):
            m.packages = kept
        elif kept:
            m.subtypes = kept
        else:
            continue
        messages.append(m)
    p.messages = messages
    used = _used_enums(p)
    p.enums = {name: e for name, e in p.enums.items() if id(e) in used}
    return p, []


def _layouts(m: model.Message) -> list[model.Layout]:
    return m.packages if isinstance(m, model.PackageListMessage) else m.subtypes


def _what(m: model.Message) -> str:
    if isinstance(m, model.PackageListMessage):
        return "sub-package"
    return "subtype" if m.has_subtype else "layout"


def _wanted(protocol: model.Protocol, picks: tuple[Pick, ...], problems: list[Problem]) -> dict:
    """Message name -> the layout names picked, or None for every layout."""
    messages = {m.name: m for m in protocol.messages}
    wanted: dict = {}
    for pick in picks:
        message, _, layout = pick.name.partition(".")
        m = messages.get(message)
        if m is None:
            problems.append(pick.where.problem(f"{pick.name}: " + unknown(message, "message", protocol.name, messages)))
            continue
        names = list(dict.fromkeys(lay.name for lay in _layouts(m)))
        if not layout:
            wanted[message] = None
        elif layout not in names:
            problems.append(pick.where.problem(f"{pick.name}: " + unknown(layout, _what(m), message, names)))
        elif wanted.get(message, set()) is not None:
            wanted.setdefault(message, set()).add(layout)
    return wanted


def _kept(m: model.Message, names) -> list[model.Layout]:
    """The layouts of a message that the selection keeps, the version's announcer always."""
    return [lay for lay in _layouts(m) if names is None or lay.name in names or lay.sets_version]


def _split_code(m: model.Message, lay: model.Layout, kept: list[model.Layout], names, picks) -> list[Problem]:
    others = [o for o in _layouts(m) if o.code.value == lay.code.value and o not in kept]
    if not others or names is None:
        return []
    pick = next((p for p in picks if p.name == f"{m.name}.{lay.name}"), None)
    if pick is None:
        return []
    sent = ", ".join(f"{o.name} ({o.versions.describe()})" for o in others)
    return [pick.where.problem(f"{pick.name}: type code {lay.code.value} is also {sent}: pick "
                               f"{' and '.join(f'{m.name}.{o.name}' for o in others)} too, or pin one version "
                               f"(--pin)")]


def _used_enums(p: model.Protocol) -> set[int]:
    """The enums (by identity) that the protocol's headers and kept layouts name."""
    used = {id(h.enum) for h in (p.message_length, p.message_type, p.package_length, p.package_type) if h.enum}
    used.add(id(p.value_type))
    for m in p.messages:
        if isinstance(m, model.PackageListMessage):
            used.add(id(m.package_type))
        else:
            _struct_enums(m.header, used)
            if m.subtype is not None and m.subtype.enum is not None:
                used.add(id(m.subtype.enum))
            if m.message_types is not None:
                used.add(id(m.message_types))
        for lay in _layouts(m):
            _struct_enums(lay.struct, used)
    return used


def _struct_enums(struct: ir.Struct, used: set[int]) -> None:
    for f in struct.fields:
        if isinstance(f, (ir.ScalarField, ir.ArrayField)) and f.enum is not None:
            used.add(id(f.enum))
        elif isinstance(f, ir.SwitchField) and f.selector.enum is not None:
            used.add(id(f.selector.enum))
        elif isinstance(f, ir.ValueListField):
            used.add(id(f.value_type))
        elif isinstance(f, ir.GroupField):
            _struct_enums(f.item, used)
