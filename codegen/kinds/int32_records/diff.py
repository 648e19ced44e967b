"""What changes from one release to another in an interface of int32 records (`python -m codegen
diff 1.3 2.10 --spec spec/ur_trajectory.yaml`): each record's layout at each, as the plan lays
them out. The releases are the ones the spec gates layouts by (the ROS driver's, for its sockets)."""
from __future__ import annotations

from ... import ir
from ...version_diff import Form, enum_changes, form_changes
from .plan import Layout, RecordsPlan


def _holds(layout: Layout, version: ir.Version) -> bool:
    return (layout.first is None or layout.first <= version) and (layout.next is None or version < layout.next)


def _slot_type(count: int, scale_name: str) -> str:
    return ("int32" if count == 1 else f"int32[{count}]") + (f" (scaled by {scale_name})" if scale_name else "")


def forms_at(planned: RecordsPlan, version: ir.Version) -> dict[int, Form]:
    out = {}
    for n, rp in enumerate(planned.records):
        layout = next(lay for lay in rp.layouts if _holds(lay, version))
        out[n] = Form(rp.record.name, rp.record.name,
                      [(s.field.name, _slot_type(s.count, s.scale_name)) for s in layout.slots], str(4 * layout.size))
    return out


def diff(planned: RecordsPlan, a: ir.Version, b: ir.Version) -> list[str]:
    return form_changes(forms_at(planned, a), forms_at(planned, b)) + enum_changes(planned.model.enums.values(), a, b)
