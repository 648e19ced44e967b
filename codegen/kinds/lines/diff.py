"""What changes from one software version to another in a text-line interface (`python -m
codegen diff 5.0 5.11 --spec spec/ur_dashboard.yaml`): the commands each version has, by the
rule every target applies (a version reads its series' column: CB, e-Series, PolyScope X)."""
from __future__ import annotations

from ... import ir
from ...version_diff import offered_changes
from .plan import CommandPlan, LinesPlan


def has(planned: LinesPlan, command: CommandPlan, version: ir.Version) -> bool:
    number = ir.version_number(version)
    since = (command.since_polyscope_x if number >= planned.polyscope_x_from
             else command.since_e_series if number >= planned.e_series_from else command.since_cb)
    return since is not None and number >= since


def diff(planned: LinesPlan, a: ir.Version, b: ir.Version) -> list[str]:
    def offered(version: ir.Version) -> dict[str, str]:
        return {c.command.name: "" for c in planned.commands if has(planned, c, version)}

    return offered_changes("command", offered(a), offered(b))
