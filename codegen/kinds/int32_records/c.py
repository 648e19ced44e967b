"""The C target of an int32-record interface: generated/c/<name>.{h,c}: enums, a caller-owned
struct per record, its size and decoder by driver release, its JSON writer, with the runtime of
runtime/c/common/ and runtime/c/int32_records/records.c joined in (static, so that every interface
holds its own copy)."""
from __future__ import annotations

from ... import ir
from ...emit import environment, runtime_section
from .model import FROM_ROBOT
from .plan import PublicField, RecordsPlan

# The runtime each interface's .c joins, in order: what every kind shares, then the kind's own.
RUNTIME = ("common/macros.h", "common/buffer.h", "common/loads.h", "common/buffer.c", "int32_records/records.c")


def _member(f: PublicField) -> dict:
    kind = ("scaled_list" if f.scaled else "int_list") if f.is_list else ("scaled" if f.scaled else "int")
    comment = f.label + (f" ({f.unit})" if f.unit else "") + (f": {f.doc}" if f.doc else "")
    if f.enum:
        comment += f" (a {f.enum.name} code)"
    return dict(name=f.name, kind=kind, count=f.max_count, optional=not f.always, comment=comment)


def _release(version: ir.Version) -> str:
    return "%du" % ir.version_number(version)


def view(p: RecordsPlan) -> dict:
    m = p.model
    prefix, upper = m.name, m.name.upper()
    enums = [dict(type=f"{prefix}_{e.name}", doc=e.doc,
                  members=[dict(name=f"{upper}_{e.name.upper()}_{v.name}", value=v.value) for v in e.values])
             for e in m.enums.values()]
    records = []
    for r in p.records:
        layouts = []
        for i, lay in enumerate(r.layouts):
            reads = [dict(name=s.field.name, kind=_member(s.field)["kind"], offset=4 * s.index, count=s.count,
                          decimals=len(str(s.scale)) - 1 if s.scale else 0, optional=not s.field.always)
                     for s in lay.slots]
            layouts.append(dict(index=i, describe=lay.describe(), size=4 * lay.size, reads=reads,
                                start=_release(lay.first) if lay.first else None))
        scales = []
        for f in r.fields:
            if f.scaled:
                by_layout = [(i, len(str(s.scale)) - 1) for i, lay in enumerate(r.layouts) for s in lay.slots
                             if s.field is f]
                scales.append(dict(name=f.name, by_layout=by_layout[:-1], last=by_layout[-1][1]))
        records.append(dict(
            scales=scales, name=r.record.name, type=f"{prefix}_{r.record.name}", doc=f"{r.record.label}: {r.record.doc}",
            from_robot=r.record.direction == FROM_ROBOT, members=[_member(f) for f in r.fields],
            lists=any(f.is_list for f in r.fields), layouts=layouts, last=len(r.layouts) - 1))
    directions = {rec["from_robot"]: rec for rec in records}
    # How the record functions tell the directions apart: the robot's first; when both are
    # there, the client's is what is left, with no test.
    order = [rec for rec in (directions.get(True), directions.get(False)) if rec]
    tests = ["from_robot" if rec["from_robot"] else "!from_robot" for rec in order]
    if len(order) == 2:
        tests[1] = None
    return dict(prefix=prefix, upper=upper, title=m.title, doc=m.doc, ports=m.ports, enums=enums, records=records,
                to_robot=directions.get(False), from_robot=directions.get(True),
                directions=[dict(record=rec, test=test) for rec, test in zip(order, tests)],
                default_release=_release(m.default_release), default_text=ir.version_text(m.default_release),
                runtime="\n\n".join(runtime_section("c", name) for name in RUNTIME))


def render(p: RecordsPlan, banner: list[str]) -> dict[str, str]:
    env = environment("c")
    ctx = dict(banner=banner, **view(p))
    name = p.model.name
    return {f"c/{name}.h": env.get_template("int32_records/records.h.j2").render(**ctx),
            f"c/{name}.c": env.get_template("int32_records/records.c.j2").render(**ctx)}
