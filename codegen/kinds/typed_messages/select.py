"""The selection pass of a typed-messages interface (codegen/select.py): RTDE with a variable
table of only the variables a firmware uses.

A pick is a variable's name as a recipe spells it (`actual_q`, `output_int_register_0`); a
register named for both directions keeps both rows. Every message stays: the setup requests and
replies make the recipes, and a data package is read by the types its setup reply gave, so a
recipe may still name a variable outside the table and its values are read all the same. The
table gives a name its type, label, unit and first versions (C's `rtde_variables`, Python's
`VARIABLES`, the dissectors' fields); outside it, a variable shows under its name alone.
"""
from __future__ import annotations

import dataclasses

from ... import ir
from ...errors import Problem
from ...select import Pick, unknown
from . import model


def select(interface: model.Interface, picks: tuple[Pick, ...],
           where: ir.Where) -> tuple[model.Interface, list[Problem]]:
    known = list(dict.fromkeys(v.name for v in interface.variables))
    problems = [p.where.problem(unknown(p.name, "variable", f"{interface.name}'s table", known))
                for p in picks if p.name not in known]
    if problems:
        return interface, problems
    names = {p.name for p in picks}
    return dataclasses.replace(interface, variables=[v for v in interface.variables if v.name in names]), []
