"""C target of a sized-packets interface: the plan -> a view model -> generated/c/<name>.{h,c}.

One struct holds every field any layout sends; its `layout` says which it holds (the layout's
slots, in packet order, are what a JSON writer walks). Each layout gets a straight-line decoder
at the offsets of the plan; the forms table renders the same_size rule, and the hand-written
runtime (runtime/c/sized_packets/<name>_*.c) frames, chooses and dispatches."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import field_text, node_text, value_text
from ...emit import environment, runtime_section
from .plan import SizedPlan

RUNTIME_HEAD = ["common/macros.h", "common/loads.h"]   # before the generated decoders, which read with them
RUNTIME_TAIL = ["decode.c"]     # after the tables they walk


@dataclass
class CMember:
    name: str
    const: str
    declarator: str          # "q_target[6]" or "time"
    comment: str
    label: str
    unit: str                # "" when none
    count: int
    enum_id: str


@dataclass
class CRead:
    member: str
    offset: int
    count: int


@dataclass
class CLayout:
    name: str
    const: str
    label: str
    comment: str
    decoder: str
    slots: list[tuple[str, int, int]]   # field constant, offset, count
    reads: list[CRead]


@dataclass
class CTable:
    ident: str
    entries: list[tuple[int, str, str]]


@dataclass
class CForm:
    size: int
    low: int
    high: int
    layout_const: str
    versions: str
    names: list[str]                    # per enum id: "{table, count}"


def _section(prefix: str, name: str) -> str:
    return runtime_section("c", name if name.startswith("common/") else f"sized_packets/{prefix}_{name}")


def render(planned: SizedPlan, banner: list[str]) -> dict[str, str]:
    protocol = planned.protocol
    prefix = protocol.name
    upper = prefix.upper()
    enums = planned.enums
    enum_ids = {e.name: f"{upper}_ENUM_{e.name.upper()}" for e in enums}
    members = []
    for f in protocol.catalogue:
        count = f.count if isinstance(f, ir.ArrayField) else 1
        members.append(CMember(f.name, f"{upper}_F_{f.name.upper()}",
                               f"{f.name}[{count}]" if isinstance(f, ir.ArrayField) else f.name,
                               field_text([f], versions=False), f.label, f.unit or "", count,
                               enum_ids[f.enum.name] if getattr(f, "enum", None) else "-1"))
    const_of = {m.name: m.const for m in members}
    layouts = []
    for lp in planned.layouts:
        layout = lp.layout
        comment = f"{layout.label}: sent by software {layout.describe()}."
        if node_text(layout):
            comment += " " + node_text(layout)
        layouts.append(CLayout(layout.name, f"{upper}_{layout.name.upper()}", layout.label, comment,
                               f"{prefix}__decode_{layout.name}",
                               [(const_of[s.field.name], s.offset, s.count) for s in lp.slots],
                               [CRead(s.field.name, s.offset, s.count) for s in lp.slots]))
    tables = {}
    for e in enums:
        for i, table in enumerate(e.tables):
            tables[(e.name, i)] = CTable(f"{prefix}__{e.name}_names_{i}",
                                         [(v.value, v.name, value_text(v)) for v in table.values])
    forms = []
    for size in planned.sizes:
        for index in planned.by_size[size]:
            form = planned.forms[index]
            names = []
            for e in enums:
                if e.name in form.tables:
                    t = tables[(e.name, e.tables.index(form.tables[e.name]))]
                    names.append(f"{{{t.ident}, {len(t.entries)}}}")
                else:
                    names.append("{NULL, 0}")
            forms.append(CForm(size, form.low, form.high, layouts[form.layout].const, form.describe(), names))
    env = environment("c")
    context = dict(banner=banner, protocol=protocol, prefix=prefix, upper=upper, members=members,
                   layouts=layouts, enums=[(enum_ids[e.name], e.name, node_text(e)) for e in enums],
                   tables=list(tables.values()), forms=forms, size_bytes=protocol.size_field_bytes,
                   min_size=protocol.size_field_bytes + 8, same_size=protocol.same_size,
                   head="\n\n".join(_section(prefix, n) for n in RUNTIME_HEAD),
                   tail="\n\n".join(_section(prefix, n) for n in RUNTIME_TAIL))
    return {f"c/{prefix}.h": env.get_template("sized_packets/header.h.j2").render(**context),
            f"c/{prefix}.c": env.get_template("sized_packets/source.c.j2").render(**context)}
