"""What changes from one software version to another in RTDE (`python -m codegen diff 5.0 5.11
--spec spec/rtde.yaml`): the variables a recipe can name, by the rule every target applies (a
version reads the last generation's column of the table that starts at or below it)."""
from __future__ import annotations

from typing import Optional

from ... import ir
from ...version_diff import offered_changes
from .model import NONE, UNKNOWN, Interface, Variable
from .plan import TypedPlan


def offered(interface: Interface, variable: Variable, version: ir.Version) -> Optional[str]:
    """"" when the version has the variable, "(first version not known)" when the sources do not
    say, None when it has not."""
    generation = [g for g in interface.generations if g.column_from <= version][-1]
    first = variable.since[generation.name]
    if first == NONE:
        return None
    if first == UNKNOWN:
        return "(first version not known)"
    return "" if first <= version else None


def diff(planned: TypedPlan, a: ir.Version, b: ir.Version) -> list[str]:
    interface, lines = planned.interface, []
    for direction in ("output", "input"):
        def names(version: ir.Version) -> dict[str, str]:
            found = {v.name: offered(interface, v, version) for v in interface.variables if v.direction == direction}
            return {name: note for name, note in found.items() if note is not None}

        lines += offered_changes(f"{direction} variable", names(a), names(b))
    return lines
