"""Decisions every target of a text-line interface shares, made once over the model: the order
in which commands are tried, and the numbers targets without tuples compare versions by."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ... import ir, series
from .model import Command, LinesProtocol


@dataclass(frozen=True)
class CommandPlan:
    index: int                        # the command's number in spec order (C enum, Lua table index - 1)
    command: Command
    since_cb: Optional[int]           # ir.version_number, None: no CB-series version has it
    since_e_series: Optional[int]
    since_polyscope_x: Optional[int]


@dataclass(frozen=True)
class LinesPlan:
    model: LinesProtocol
    commands: tuple[CommandPlan, ...]          # spec order
    lookup: tuple[CommandPlan, ...]            # the order a line is tried against: longest text first
    version_command: Optional[CommandPlan]
    e_series_from: int                         # ir.version_number of 5.0
    polyscope_x_from: int                      # ir.version_number of 10.0


def _number(version: Optional[ir.Version]) -> Optional[int]:
    return ir.version_number(version) if version else None


def plan(model: LinesProtocol) -> LinesPlan:
    commands = tuple(CommandPlan(i, c, _number(c.since_cb), _number(c.since_e_series), _number(c.since_polyscope_x))
                     for i, c in enumerate(model.commands))
    # "power on" before "power", "load installation" before "load": the longest text that opens
    # the line is the command; equal lengths keep spec order.
    lookup = tuple(sorted(commands, key=lambda c: -len(c.command.text)))
    version = next((c for c in commands if c.command.name == model.version_command), None)
    return LinesPlan(model, commands, lookup, version, ir.version_number((model.E_SERIES_MAJOR, 0, 0)),
                     ir.version_number(series.POLYSCOPE_X_FROM))
