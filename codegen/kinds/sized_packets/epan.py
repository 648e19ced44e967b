"""epan target of a sized-packets interface: the dissector model (dissector.py) -> a view model ->
generated/epan/packet-<name with dashes>.c, a native Wireshark dissector, the twin of the Lua one
(lua.py renders the same model): the same protocol, fields, tree, Info column, experts and
preferences. The generated part declares the handles, one double field per spec field (its unit
shown by a label function: epan_c.UnitLabel), the enum names as value_strings, the layouts' slots
and the forms by size; the hand-written runtime (runtime/epan/sized_packets/<name>_*, joined in) frames the TCP
stream and walks them."""
from __future__ import annotations

from dataclasses import dataclass

from ...comments import node_text
from ...emit import environment, runtime_section
from ...epan_c import development_branch, unit_label
from ...lang.c import prose, string, value_key
from .dissector import Dissector, Field, Layout, dissector, item_blurb
from .plan import SizedPlan

BLURB_INDENT = " " * 12     # where spread hangs an hf entry's members: a long blurb's lines

RUNTIME_HEAD = ["types.h"]      # runtime/epan/sized_packets/<name>_types.h: the table types, before the tables
RUNTIME_TAIL = ["dissect.c"]    # runtime/epan/sized_packets/<name>_dissect.c: after the tables it walks
# runtime/c/common/version_text.{h,c}: reads the version preference, before the tail
SHARED = ["common/macros.h", "common/version_text.h", "common/version_text.c"]


@dataclass
class EpanField:
    """The handles of a field: one variable, or an array of `count` (its named items or flags)."""
    hf: str
    comment: str
    registered: tuple[tuple[str, list[str]], ...]   # each handle and its hf_register_info members
    count: int = 0


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


def _double(name: str, hf: str, label: str, abbrev: str, unit, blurb: str) -> tuple[str, list[str]]:
    """The hf_register_info entry of a double, its unit shown by a label function."""
    return hf, [string(label), string(abbrev), "FT_DOUBLE", "BASE_CUSTOM" if unit else "BASE_NONE",
                f"CF_FUNC({unit_label(name, unit).ident})" if unit else "NULL", "0x0", prose(blurb, BLURB_INDENT), "HFILL"]


def _field(name: str, f: Field) -> EpanField:
    """A field's handle: one, or one per named item (filtered by the vector's name)."""
    hf, abbrev = f"hf_{name}_{f.name}", f"{name}.{f.name}"
    if f.items:
        return EpanField(hf, f.comment, tuple(_double(name, f"{hf}[{k}]", i.label, abbrev, i.unit, item_blurb(f, i))
                                              for k, i in enumerate(f.items)), len(f.items))
    return EpanField(hf, f.comment, (_double(name, hf, f.label, abbrev, f.unit, f.doc),))


def _size_field(name: str, f: Field) -> EpanField:
    hf = f"hf_{name}_{f.name}"
    return EpanField(hf, f.comment, ((hf, [string(f.label), string(f"{name}.{f.name}"), "FT_INT32", "BASE_DEC",
                                           "NULL", "0x0", prose(f.doc, BLURB_INDENT), "HFILL"]),))


def _flags(name: str, f: Field) -> EpanField:
    """The flag handles of a double whose whole value carries bits."""
    hf = f"hf_{name}_{f.name}_flags"
    width = f.flag_width // 4
    return EpanField(hf, f"The flags of {f.name}.", tuple(
        (f"{hf}[{k}]", [string(g.label), string(f"{name}.{f.name}.{g.name}"), "FT_BOOLEAN", str(f.flag_width),
                        "NULL", f"0x{g.mask:0{width}x}", prose(g.comment, BLURB_INDENT), "HFILL"]) for k, g in enumerate(f.flags)),
        len(f.flags))


def _layout(name: str, layout: Layout, enum_ids: dict[str, str]) -> EpanLayout:
    """A layout's slots in packet order, and where it sends the field the Info column names."""
    slots = []
    for s in layout.slots:
        f = s.field
        names = enum_ids[f.enum] if f.enum is not None else "-1"
        hf = f"hf_{name}_{f.name}" if f.items else f"&hf_{name}_{f.name}"
        flags = [f"hf_{name}_{f.name}_flags", str(len(f.flags)), f"&ett_{name}_{f.name}"] if f.flags \
            else ["NULL", "0", "NULL"]
        if f.is_array:
            slots.append([hf, "TRUE" if f.items else "FALSE", f"&ett_{name}_{f.name}", string(f.group),
                          str(s.offset), str(s.count), names, *flags])
        else:
            slots.append([hf, "FALSE", "NULL", "NULL", str(s.offset), "1", names, *flags])
    info = layout.info
    return EpanLayout(f"{name}_{layout.name}", layout.name, f"{layout.label}: sent by software {layout.versions}.",
                      slots, info.offset if info else -1,
                      enum_ids[info.field.enum] if info and info.field.enum is not None else "-1")


def view(d: Dissector) -> dict:
    protocol = d.plan.protocol
    name = protocol.name
    upper = name.upper()
    enum_ids = {e.name: f"{upper}_NAMES_{e.name.upper()}" for e in d.enums}
    tables = [EpanTable(f"{name}_{t.ident}", [(value_key(value), string(text), comment)
                                              for value, text, comment in t.entries]) for t in d.tables]
    forms, sizes = [], []
    for size, row in d.by_size:
        sizes.append((size, len(forms), len(row)))
        forms += [EpanForm(f"{size} bytes, {f.versions}", f.low, f.high, f.layout,
                           [f"{name}_{t.ident}" if t is not None else "NULL" for t in f.tables]) for f in row]
    runtime = ([runtime_section("epan", f"sized_packets/{name}_{part}") for part in RUNTIME_HEAD]
               + [runtime_section("c", file) for file in SHARED]
               + [runtime_section("epan", f"sized_packets/{name}_{part}") for part in RUNTIME_TAIL])
    return dict(
        protocol=protocol, name=name, upper=upper, file=f"packet-{name.replace('_', '-')}.c",
        short_name=upper, doc=node_text(protocol), ports=",".join(str(p) for p in protocol.ports),
        size_field=_size_field(name, d.size_field),
        fields=[_field(name, f) for f in d.fields] + [_flags(name, f) for f in d.fields if f.flags],
        etts=[f"ett_{name}"] + [f"ett_{name}_{f.name}" for f in d.fields if f.is_array or f.flags],
        labels=list(dict.fromkeys(unit_label(name, unit) for f in d.fields
                                  for unit in ([i.unit for i in f.items] if f.items else [f.unit]) if unit)),
        enums=[(enum_ids[e.name], e.doc) for e in d.enums], tables=tables,
        layouts=[_layout(name, lay, enum_ids) for lay in d.layouts], forms=forms, sizes=sizes,
        same_size=protocol.same_size, size_bytes=protocol.size_field_bytes,
        min_size=protocol.size_field_bytes + 8, max_size=protocol.max_message_size,
        head=runtime[:len(RUNTIME_HEAD)], tail=runtime[len(RUNTIME_HEAD):])


def render(planned: SizedPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """`upstream`: the copy for Wireshark's tree, in its development branch's style (this dissector
    reads no command line)."""
    context = view(dissector(planned))
    env = environment("epan")
    env.filters["c"] = string
    text = env.get_template("sized_packets/dissector.c.j2").render(banner=banner, **context)
    return {f"epan/{context['file']}": development_branch(text) if upstream else text}
