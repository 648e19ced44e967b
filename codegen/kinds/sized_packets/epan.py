"""epan target of a sized-packets interface: the plan -> a view model ->
generated/epan/packet-<name with dashes>.c, a native Wireshark dissector, the twin of the Lua one
(kinds/sized_packets/lua.py): the same protocol, fields, tree, Info column, experts and
preferences. The generated part declares the handles, one double field per spec field (its unit
shown by a label function: epan_c.UnitLabel), the enum names as value_strings, the layouts' slots
and the forms by size; the hand-written runtime (runtime/epan/sized_packets/<name>_*, joined in) frames the TCP
stream and walks them."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import field_text, node_text, value_text
from ...emit import environment, runtime_section
from ...epan_c import c_string, unit_label, value_literal
from .plan import SizedPlan

RUNTIME_HEAD = ["types.h"]      # runtime/epan/sized_packets/<name>_types.h: the table types, before the tables
RUNTIME_TAIL = ["dissect.c"]    # runtime/epan/sized_packets/<name>_dissect.c: after the tables it walks
# runtime/c/common/version_text.{h,c}: reads the version preference, before the tail
SHARED = ["common/macros.h", "common/version_text.h", "common/version_text.c"]
INFO_FIELD = "robot_mode"       # the field whose name the Info column shows beside the layout's


@dataclass
class EpanField:
    hf: str
    label: str
    abbrev: str
    display: str
    strings: str
    comment: str


@dataclass
class EpanTable:
    ident: str
    entries: list[tuple[str, str, str]]     # C value, name, comment


@dataclass
class EpanLayout:
    ident: str
    name: str
    comment: str
    slots: list[list[str]]                   # each slot's C initializer, member by member
    info_at: int
    info_names: str


@dataclass
class EpanForm:
    versions: str
    low: int
    high: int
    layout: int                              # index into the layouts
    names: list[str]                         # per enum: its value_string or NULL


def _fields(name: str, catalogue: list[ir.AnyField]) -> list[EpanField]:
    return [EpanField(f"hf_{name}_{f.name}", f.label, f"{name}.{f.name}",
                      "BASE_CUSTOM" if f.unit else "BASE_NONE",
                      f"CF_FUNC({unit_label(name, f.unit).ident})" if f.unit else "NULL",
                      field_text([f], versions=False))
            for f in catalogue]


def _tables(name: str, enums: list[ir.Enum]) -> dict[tuple[str, int], EpanTable]:
    """Each enum's names, one value_string per version range of its codes."""
    return {(e.name, i): EpanTable(f"{name}_{e.name}_{i}", [(value_literal(v.value), c_string(v.name), value_text(v))
                                                            for v in table.values])
            for e in enums for i, table in enumerate(e.tables)}


def _layout(name: str, lp, enum_ids: dict[str, str]) -> EpanLayout:
    """A layout's slots in packet order, and where it sends the field the Info column names."""
    slots, info_at, info_names = [], -1, "-1"
    for s in lp.slots:
        f = s.field
        names = enum_ids[s.enum.name] if s.enum is not None else "-1"
        if isinstance(f, ir.ArrayField):
            group = f.label + (f" ({f.unit})" if f.unit else "")
            slots.append([f"&hf_{name}_{f.name}", f"&ett_{name}_{f.name}", c_string(group), str(s.offset),
                          str(s.count), names])
        else:
            slots.append([f"&hf_{name}_{f.name}", "NULL", "NULL", str(s.offset), "1", names])
        if f.name == INFO_FIELD:
            info_at, info_names = s.offset, names
    layout = lp.layout
    return EpanLayout(f"{name}_{layout.name}", layout.name, f"{layout.label}: sent by software {layout.describe()}.",
                      slots, info_at, info_names)


def _forms(planned: SizedPlan, tables: dict) -> tuple[list[EpanForm], list[tuple[int, int, int]]]:
    """The forms in the order the same-size rule tries them, and each size's first form and count."""
    forms, sizes = [], []
    for size in planned.sizes:
        sizes.append((size, len(forms), len(planned.by_size[size])))
        for index in planned.by_size[size]:
            form = planned.forms[index]
            names = [tables[(e.name, e.tables.index(form.tables[e.name]))].ident if e.name in form.tables else "NULL"
                     for e in planned.enums]
            forms.append(EpanForm(f"{size} bytes, {form.describe()}", form.low, form.high, form.layout, names))
    return forms, sizes


def render(planned: SizedPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """`upstream` (the copy for Wireshark's tree) changes nothing: this dissector reads no command line."""
    protocol = planned.protocol
    name = protocol.name
    upper = name.upper()
    size_field = protocol.size_field
    arrays = [f for f in protocol.catalogue if isinstance(f, ir.ArrayField)]
    enum_ids = {e.name: f"{upper}_NAMES_{e.name.upper()}" for e in planned.enums}
    tables = _tables(name, planned.enums)
    forms, sizes = _forms(planned, tables)
    runtime = ([runtime_section("epan", f"sized_packets/{name}_{part}") for part in RUNTIME_HEAD]
               + [runtime_section("c", file) for file in SHARED]
               + [runtime_section("epan", f"sized_packets/{name}_{part}") for part in RUNTIME_TAIL])
    context = dict(
        banner=banner, protocol=protocol, name=name, upper=upper, file=f"packet-{name.replace('_', '-')}.c",
        short_name=upper, doc=node_text(protocol), ports=",".join(str(p) for p in protocol.ports),
        size_field=EpanField(f"hf_{name}_{size_field.name}", size_field.label, f"{name}.{size_field.name}",
                             "BASE_DEC", "NULL", field_text([size_field], versions=False)),
        fields=_fields(name, protocol.catalogue), etts=[f"ett_{name}"] + [f"ett_{name}_{f.name}" for f in arrays],
        labels=list(dict.fromkeys(unit_label(name, f.unit) for f in protocol.catalogue if f.unit)),
        enums=[(enum_ids[e.name], node_text(e) or e.name) for e in planned.enums], tables=list(tables.values()),
        layouts=[_layout(name, lp, enum_ids) for lp in planned.layouts], forms=forms, sizes=sizes,
        same_size=protocol.same_size, size_bytes=protocol.size_field_bytes,
        min_size=protocol.size_field_bytes + 8, max_size=protocol.max_message_size,
        head=runtime[:len(RUNTIME_HEAD)], tail=runtime[len(RUNTIME_HEAD):])
    text = environment("epan").get_template("sized_packets/dissector.c.j2").render(**context)
    return {f"epan/{context['file']}": text}
