"""The epan target of an int32-record interface: generated/epan/packet-<name with dashes>.c, a
native Wireshark dissector, the twin of the Lua one (lua.py renders the same dissector model): the
same protocol, fields (a field's label carries its unit, as the Lua field's does, and a scaled
one's raw int32 is a field beside it), tree, Info column, experts and release preference. The
generated part declares the handles, the enums' value_strings and each direction's record layouts by
release; runtime/epan/int32_records*.{h,c}, joined in, frames the TCP stream and walks them."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...comments import value_text
from ...emit import environment, runtime_section
from ...epan_c import development_branch
from ...lang.c import prose, string, value_key
from ...naming import column_name
from .dissector import Dissector, dissector
from .model import FROM_ROBOT, TO_ROBOT
from .plan import RecordsPlan

BLURB_INDENT = " " * 12     # where spread hangs an hf entry's members: a long blurb's lines

RUNTIME_HEAD = [("epan", "int32_records/int32_records_types.h")]    # the table types, before the tables
# the release's text (the C library's reader); the dissector, after the tables
RUNTIME_TAIL = [("c", "common/macros.h"), ("c", "common/version_text.h"), ("c", "common/version_text.c"),
                ("epan", "int32_records/int32_records.c")]


@dataclass
class EpanField:
    hf: str
    items: list[str]             # the header_field_info initializer, member by member
    comment: str = ""


@dataclass
class EpanTable:
    ident: str
    entries: list[tuple[str, str, str]]     # C value, name, comment


@dataclass
class EpanLayout:
    ident: str
    describe: str
    size: int
    slots: list[list[str]]       # each slot's initializer, member by member


@dataclass
class EpanRecord:
    ident: str
    label: str
    starts: list[str]
    layouts: list[EpanLayout]
    items: list[str]             # the int32_records_record initializer, member by member


def _field(hf: str, label: str, abbrev: str, ftype: str, base: str, strings: str, blurb: str,
           comment: str = "") -> EpanField:
    return EpanField(hf, [string(label), string(abbrev), ftype, base, strings, "0x0", prose(blurb, BLURB_INDENT),
                          "HFILL"], comment)


def view(d: Dissector) -> dict:
    m = d.plan.model
    name = m.name
    tables = [EpanTable(f"{name}_{e.name}_vals", [(value_key(v.value), string(v.name), value_text(v))
                                                  for v in e.values])
              for e in d.enums]
    fields = []
    for f in d.fields:
        hf, abbrev = f"hf_{name}_{f.name}", f"{name}.{f.name}"
        if f.scaled:
            fields.append(_field(hf, f.shown_label, abbrev, "FT_DOUBLE", "BASE_NONE", "NULL", f.blurb, f.comment))
            fields.append(_field(hf + "_raw", f"{f.label} (raw int32)", abbrev + "_raw", "FT_INT32", "BASE_DEC", "NULL",
                                 f.raw_blurb))
        else:
            strings = f"VALS({name}_{f.enum}_vals)" if f.enum else "NULL"
            fields.append(_field(hf, f.shown_label, abbrev, "FT_INT32", "BASE_DEC", strings, f.blurb, f.comment))
    records = {}
    for r in d.records:
        ident = f"{name}_{r.name}"
        layouts = []
        for i, lay in enumerate(r.layouts):
            slots = [[f"&hf_{name}_{s.field.name}", f"&hf_{name}_{s.field.name}_raw" if s.scale else "NULL",
                      str(s.index), str(s.count), str(s.scale or 0), string(s.scale_name) if s.scale else "NULL"]
                     for s in lay.slots]
            layouts.append(EpanLayout(f"{ident}_{i}", lay.describe, lay.size, slots))
        starts = [str(s) for s in r.starts]
        items = [string(r.label), f"{ident}_starts" if starts else "NULL",
                 f"array_length({ident}_starts)" if starts else "0", f"{ident}_layouts"]
        records[r.direction] = EpanRecord(ident, r.label, starts, layouts, items)
    runtime = [runtime_section(language, part) for language, part in RUNTIME_HEAD + RUNTIME_TAIL]
    return dict(
        name=name, title=m.title, doc=m.doc, file=f"packet-{name.replace('_', '-')}.c",
        short_name=name.upper(), column=column_name(name), ports=[str(port) for port in m.ports],
        default_release=ir.version_number(m.default_release), default_text=ir.version_text(m.default_release),
        tables=tables, fields=fields, records=records, to_robot=records.get(TO_ROBOT),
        from_robot=records.get(FROM_ROBOT), head=runtime[:len(RUNTIME_HEAD)], tail=runtime[len(RUNTIME_HEAD):])


def render(p: RecordsPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """`upstream`: the copy for Wireshark's tree, in its development branch's style (this dissector
    reads no command line)."""
    context = view(dissector(p))
    env = environment("epan")
    env.filters["c"] = string
    text = env.get_template("int32_records/dissector.c.j2").render(banner=banner, **context)
    return {f"epan/{context['file']}": development_branch(text) if upstream else text}
