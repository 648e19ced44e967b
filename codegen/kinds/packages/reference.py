"""What the spec says per software version, for people: `python -m codegen diff 3.15 5.11`
prints what changed between two versions, and `python -m codegen reference` writes the
protocol reference (docs/protocol.md). Both read the plan's variants (plan.Variant), so they
show exactly what the decoders do."""
from __future__ import annotations

import re
from typing import Optional

from ... import ir
from ...naming import words
from ...version_diff import Form, enum_changes, field_type, form_changes
from . import model, plan


def sizes_text(v: plan.Variant, header: int) -> str:
    """Whole sizes, header included, as a reader of the document counts them."""
    if v.sizes is None:
        return f"at least {v.min_size + header}"
    flags = sorted({f.present_if for f in v.layout.struct.fields if f.present_if and _present(f, v)})
    sizes = sorted(s + header for s in v.sizes)
    if len(sizes) == 1:
        return str(sizes[0])
    return f"{sizes[0]}, or {' / '.join(map(str, sizes[1:]))} with {', '.join(flags)}"


def _present(f: ir.AnyField, v: plan.Variant) -> bool:
    lo = v.ranges[0][0]
    return f.versions.contains(ir.version_of_number(lo))


def _header_size(p: plan.ProtocolPlan, mp: plan.MessagePlan) -> int:
    return p.package_header_size if not mp.is_dispatch else mp.body_offset


def forms_at(p: plan.ProtocolPlan, version: ir.Version) -> dict[tuple[str, int], Form]:
    """Every type code's form for one software version."""
    number = ir.version_number(version)
    out = {}
    for mp in p.messages:
        for code, variants in mp.variants.items():
            for v in variants:
                if any(lo <= number <= hi for lo, hi in v.ranges):
                    fields = [(f.name, field_type(f)) for f in v.layout.struct.fields if _present(f, v)]
                    out[(mp.message.name, code)] = Form(f"{mp.message.name} {code}", v.layout.name, fields,
                                                        sizes_text(v, _header_size(p, mp)))
    return out


def diff(p: plan.ProtocolPlan, a: ir.Version, b: ir.Version) -> list[str]:
    """What changes from software `a` to software `b`: layouts, fields, sizes, enum members."""
    return form_changes(forms_at(p, a), forms_at(p, b)) + enum_changes(p.protocol.enums.values(), a, b)


# A citation of the project's own docs in a spec text: docs/firmware-history.md#masterboard-data.
_DOC_CITATION = re.compile(r"docs/((?:firmware-history|contract|canonical-json)\.md#[a-z0-9-]+)")


def _linked(text: str) -> str:
    """A spec text with its citations of docs/ as links relative to docs/protocol.md."""
    return _DOC_CITATION.sub(lambda m: f"[{m.group(1)}]({m.group(1)})", text)


def _citations(*texts: str) -> list[str]:
    """The docs/ entries the texts cite, each once, in order."""
    return list(dict.fromkeys(c for t in texts if t for c in _DOC_CITATION.findall(t)))


def _gated(v: plan.Variant) -> list[ir.AnyField]:
    """The fields of a form that not every version sends: what tells it from the others."""
    return [f for f in v.layout.struct.fields if _present(f, v) and not f.versions.unbounded]


def _form_sources(v: plan.Variant) -> str:
    """Where a form comes from: the docs/ entries its layout and its gated fields cite."""
    cited = _citations(v.layout.field_note, *(f.field_note for f in _gated(v)))
    return ", ".join(f"[{c.split('#')[1]}]({c})" for c in cited) or "the 5.9 document"


def _notes(lay: model.Layout) -> list[str]:
    """The layout's and its fields' field_note texts (sources and confidence), as a list."""
    rows = [f"- {_one_line(_linked(lay.field_note))}"] if lay.field_note else []
    for f in lay.struct.fields:
        if f.field_note:
            when = "" if f.versions.unbounded else f" ({f.versions.describe()})"
            rows.append(f"- `{f.name}`{when}: {_one_line(_linked(f.field_note))}")
    return rows


def protocol_markdown(p: plan.ProtocolPlan, spec_path: str) -> str:
    """The protocol reference: every message and sub-package, its forms by software version with
    their sizes, fields and sources, and every enum table. What the spec's field_note texts say
    (sources, confidence) is shown here and in no generated code."""
    proto = p.protocol
    out = [f"# {proto.title}: protocol reference", "",
           f"Written by `make generate` from `{spec_path}`; do not edit. Sizes count the whole package "
           "or message, header included. Each type code lists the forms it takes by software version: "
           "the decoders use the stream's version's form when it fits the declared length, else the one "
           "form whose size matches it ([contract.md#choosing-a-layout](contract.md#choosing-a-layout)). "
           "Each form links to its entries in the firmware history ([firmware-history.md](firmware-history.md)), "
           "which give the public sources it rests on and how sure they are.", ""]
    for mp in p.messages:
        m = mp.message
        out += [f"## {words(m.name)} (message type {m.code.value})", ""]
        if not mp.is_dispatch or m.has_subtype:
            # A body message is its one layout: its text follows under the layout.
            out += [_one_line(m.doc, _linked(m.field_note)), ""]
        header = _header_size(p, mp)
        for code, variants in mp.variants.items():
            names = sorted({_marked(v.layout) for v in variants}, key=[_marked(v.layout) for v in variants].index)
            out += [f"### {code}: {' / '.join(names)}", ""]
            layouts = list({id(v.layout): v.layout for v in variants}.values())
            for lay in layouts:
                out += [_one_line(lay.doc), ""]
            out += ["| software | size | fields | history |", "|---|---|---|---|"]
            for v in variants:
                fields = ", ".join(f"`{f.name}` {field_type(f)}" for f in v.layout.struct.fields if _present(f, v))
                out.append(f"| {v.describe()} | {sizes_text(v, header)} | {fields} | {_form_sources(v)} |")
            out.append("")
            notes = [row for lay in layouts for row in _notes(lay)]
            if notes:
                out += ["Sources:", ""] + notes + [""]
            out += ["| field | label | unit | description |", "|---|---|---|---|"]
            for lay in {id(v.layout): v.layout for v in variants}.values():
                out += _field_rows(lay.struct, "")
            out.append("")
    out += ["## Enums", ""]
    for e in proto.enums.values():
        out += [f"### {e.name} ({e.scalar.name})", "", _one_line(e.doc), ""]
        if e.field_note:
            out += [f"Sources: {_one_line(_linked(e.field_note))}", ""]
        for t in e.tables:
            if e.versioned:
                out += [f"Software {t.versions.describe()}:", ""]
            out += ["| code | name | note |", "|---|---|---|"]
            out += [f"| {v.value} | {v.name} | {_one_line(v.doc, _linked(v.field_note))} |" for v in t.values]
            out.append("")
    return "\n".join(out).rstrip() + "\n"


def _marked(layout: model.Layout) -> str:
    """A layout's name and its marks: "payload_info (undocumented, inferred)"."""
    return f"{layout.name} ({', '.join(layout.marks)})" if layout.marks else layout.name


def _field_rows(struct: ir.Struct, prefix: str) -> list[str]:
    """One row per field name (in any version), with what people read: its label, unit and doc;
    a group's fields follow it as `group[].field`."""
    rows = []
    for f in struct.public_fields:
        rows.append(f"| `{prefix}{f.name}` | {f.label} | {f.unit or ''} | {_one_line(f.doc)} |")
        if isinstance(f, ir.GroupField):
            rows += _field_rows(f.item, f"{prefix}{f.name}[].")
    return rows


def _one_line(*texts: Optional[str]) -> str:
    return " ".join(t.strip().replace("\n", " ").replace("|", "\\|") for t in texts if t and t.strip())
