"""What changes from one software version to another in a stream of packets chosen by size
(`python -m codegen diff 3.1 3.2 --spec spec/ur_realtime.yaml`): the packet each version sends,
from the plan's forms as every target chooses them, and its enums' members."""
from __future__ import annotations

from ... import ir
from ...version_diff import Form, enum_changes, field_type, form_changes
from .plan import SizedPlan


def forms_at(planned: SizedPlan, version: ir.Version) -> dict[int, Form]:
    """The packets a version sends, largest first (a version before 1.5 sends two sizes)."""
    number = ir.version_number(version)
    layouts = sorted({planned.layouts[f.layout].layout.name: planned.layouts[f.layout].layout
                      for f in planned.forms if f.low <= number <= f.high}.values(), key=lambda lay: -lay.size)
    return {rank: Form("packet" if rank == 0 else "another packet", layout.name,
                       [(f.name, field_type(f)) for f in layout.fields], str(layout.size))
            for rank, layout in enumerate(layouts)}


def diff(planned: SizedPlan, a: ir.Version, b: ir.Version) -> list[str]:
    return form_changes(forms_at(planned, a), forms_at(planned, b)) + enum_changes(planned.enums, a, b)
