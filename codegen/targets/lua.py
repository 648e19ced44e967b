"""Lua target: the IR -> plain data -> templates/lua/urwire.lua.j2 + runtime/*.lua, one Wireshark
dissector in one self-contained file.

Every decision is made here: which ProtoField each field becomes (one per name, of the widest
type among the name's entries in every version), its abbreviation
(`ur.<message_or_package>.<field>`, docs/contract.md#what-every-target-keeps), value strings
(one per version table of an enum), the field descriptors each layout is walked with, the forms each type code takes across
software versions (plan.Variant), where the Version message keeps its numbers, and which fields
the Info column shows. Versions reach the runtime as ir.version_number integers. The builder hands the template data only (dicts and `Step`s); the template writes
each descriptor kind and each ProtoField shape with a macro of its own. The code that walks the
descriptors is hand-written Lua in runtime/lua/, joined after the generated tables.
"""
from __future__ import annotations

import textwrap

from dataclasses import dataclass
from typing import Optional

from .. import ir, plan, wrap
from ..comments import node_text
from ..emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ..errors import Problem, SpecError
from ..naming import layout_label, table_suffix, wireshark_field, words
from ..view import Step

OUT = "lua/urwire.lua"

# The hand-written runtime, in the order it is joined. Each file is a chunk that receives
# (spec, rt): `spec` is the generated data, `rt` what earlier runtime files export.
RUNTIME = ("declare.lua", "bytes.lua", "versions.lua", "items.lua", "collector.lua", "walk.lua", "values.lua",
           "info.lua", "messages.lua", "wanted.lua", "carry.lua", "stream.lua", "framing.lua", "register.lua")

# The most tree items one message shows in Wireshark (runtime/items.lua); an expert note says
# how many more it holds. Wireshark itself stops a packet at a million items.
MAX_TREE_ITEMS = 10_000

# ProtoField constructor per scalar (integers take base and value strings, floats do not).
PROTOFIELD = {"bool": "bool", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double"}


def lua_str(text: str) -> str:
    """A Lua double-quoted string literal."""
    out = []
    for ch in text:
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch == "\n":
            out.append("\\n")
        elif ord(ch) < 32:
            out.append(f"\\{ord(ch)}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def lua_text(text: str, indent: str = "", column: int = 0) -> str:
    """A long Lua string literal over several lines: each line but the last ends in a space and
    `\\z`, which makes Lua skip the line break and the next line's indentation, so the value is
    the text exactly. It breaks only before a word (never before a space the text keeps)."""
    words = text.split(" ")
    lines, line = [], []
    for word in words:
        width = (wrap.PROSE - column if not lines else wrap.PROSE - len(indent)) - 4
        if line and word and len(lua_str(" ".join(line + [word]))) > width:
            lines.append(" ".join(line))
            line = [word]
        else:
            line.append(word)
    lines.append(" ".join(line))
    literals = [lua_str(piece)[1:-1] for piece in lines]
    return '"' + (" \\z\n" + indent).join(literals) + '"'


def lua_field(call: str, key: str, text: str, indent: str = "    ") -> str:
    """One entry of the field table, `[key] = ProtoField.x(..., text),` where `call` is the
    constructor up to its last argument, the description `text`, one argument a line: on one
    line when it fits, else the description (wrapped by lua_text) on the lines under it, and the
    constructor under the key when even that is long."""
    args = "\n".join(a.strip() for a in call.splitlines() if a.strip())
    flat = args.replace("\n", " ")
    one = f"{indent}[{key}] = {flat}, {lua_str(text)}),"
    if len(one) <= wrap.LIMIT:
        return one
    inner = indent + "    "
    head = f"{indent}[{key}] = {flat},"
    if len(head) <= wrap.LIMIT:
        lines = [head]
    else:
        lines = [f"{indent}[{key}] ="] + [inner + line for line in wrap.pack(args, len(inner), 4).split("\n")]
        lines[-1] += ","
    return "\n".join(lines + [inner + lua_text(text, inner, len(inner)) + "),"])


def lua_literal(value) -> str:
    """The template's `lua` filter: a Python value as a Lua literal (None is nil)."""
    if value is None:
        return "nil"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return lua_str(value)
    raise TypeError(f"lua target: no Lua literal for {value!r}")


def one_line(*texts: str) -> str:
    return " ".join(t.strip() for t in texts if t and t.strip())


def describe(f: ir.Field, sent: str = "") -> str:
    """A field's description (its blurb: `tshark -G fields`, the display-filter dialog): the
    spec's doc, else its label; its unit; the versions that send it (`sent`, see sent_by)."""
    return one_line(f.doc or f.label + ".", f"In {f.unit}." if f.unit else "",
                    f"Sent by software {sent}." if sent else "")


def sent_by(struct: ir.Struct, owner: str, out: dict) -> None:
    """Which versions send each field of a layout, by its key: "3.0 and later", or "" for every
    version. The plan's forms hold fields with their version ranges already applied."""
    for name in dict.fromkeys(f.name for f in struct.fields):
        entries = struct.named(name)
        ranges = [] if any(e.versions.unbounded for e in entries) else [e.versions.describe() for e in entries]
        out[f"{owner}.{name}"] = ", ".join(ranges)
        for e in entries:
            if isinstance(e, ir.GroupField):
                sent_by(e.item, owner, out)


def unit_text(unit: Optional[str]) -> Optional[str]:
    """What follows a value in the tree: " rad"."""
    return f" {unit}" if unit else None


def version_number(v: Optional[ir.Version]) -> Optional[int]:
    """A version as the runtime compares it: ir.version_number (5.25.1 is 5025001); None stays nil."""
    return None if v is None else ir.version_number(v)


# Descriptor kinds the Info column can step over on its way to a summary field, and the kinds it
# can show (runtime/info.lua).
STEPS_OVER = {"scalar", "bits", "array", "pstring", "string"}
SHOWS = {"scalar", "bits", "pstring", "string"}

@dataclass
class PField:
    """One ProtoField declaration. `shape` names the template macro that writes it:
    integer, float, bool, flag (one bit of an integer), none (a subtree), text, bytes."""

    key: str                   # key in the F table: "<owner>.<name>"
    shape: str
    ctor: str                  # ProtoField.<ctor>
    abbr: str                  # filter name
    label: str
    desc: str
    base: str = "NONE"         # base.<base>
    vs: Optional[str] = None   # value string (Lua expression)
    bits: int = 0              # flag: width of the parent integer
    mask: int = 0              # flag: its bit
    parent: Optional[str] = None   # flag: the key of its integer
    unit: Optional[str] = None     # integer or float: its spec unit ("rad"), for targets that register it
    enum: Optional[str] = None     # integer: the name of its enum (its newest table names it)


@dataclass
class LayoutView:
    var: str                   # Lua expression holding the descriptor list (L.<name>)
    doc: str
    descriptors: list[Step]


SCALAR_SHAPES = {"integer", "float", "bool"}


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.problems: list[Problem] = []
        self.fields: list[PField] = []
        self.by_key: dict[str, PField] = {}
        self.layouts: list[LayoutView] = []
        self.names: set[str] = set()          # L.<name> and PART.<name> taken
        self.enum_var: dict[str, str] = {}    # enum -> its newest value string (VS.<NAME>)
        self.enum_tables: dict[str, str] = {} # versioned enum -> its names by version (NAMES.<NAME>)
        # Every scalar entry of a field key (a name may repeat in other versions, with another
        # wire type): the ProtoField takes the widest; narrower reads add their value explicitly.
        self.entries: dict[str, list[tuple[ir.Scalar, ir.Where, Optional[ir.Enum]]]] = {}
        self.reads: list[tuple[dict, str, ir.Scalar]] = []
        self.wide: dict[str, ir.Scalar] = {}
        self.sent: dict[str, str] = {}        # field key -> the versions that send it (sent_by)

    # ---- fields ----

    def add_field(self, pf: PField, where: ir.Where = ir.NOWHERE) -> str:
        """Declare a field once (a header layout shared by subtypes names it again, a name may
        repeat in another version's entry); its key."""
        known = self.by_key.get(pf.key)
        if known is None:
            self.by_key[pf.key] = pf
            self.fields.append(pf)
        elif known.shape != pf.shape and not {known.shape, pf.shape} <= SCALAR_SHAPES:
            self.problems.append(where.problem(
                f"lua target: {pf.abbr} would be both a {known.shape} and a {pf.shape} field: "
                "a Wireshark filter name has one type, give one of them a name of its own"))
        elif known.shape == "flag" and known.mask != pf.mask:
            self.problems.append(where.problem(f"lua target: the bit {pf.abbr} stands at two places"))
        elif pf.desc:
            known.desc = pf.desc   # a name's later entry is its newer form: its doc describes it
        return pf.key

    def owned_field(self, owner: str, name: str, shape: str, ctor: str, label: str, desc: str,
                    where: ir.Where = ir.NOWHERE, **more) -> str:
        return self.add_field(PField(f"{owner}.{name}", shape, ctor, wireshark_field(owner, name), label, desc,
                                     **more), where)

    def scalar_field(self, owner: str, name: str, s: ir.Scalar, enum: Optional[ir.Enum], label: str, doc: str,
                     where: ir.Where = ir.NOWHERE, unit: Optional[str] = None, hex_base: bool = False) -> str:
        """An integer's unit is its ProtoField's unit string (base.UNIT_STRING), which every
        Wireshark shows; a float's is appended by the runtime (d.unit), as Wireshark 4.0 shows no
        unit string of a float field."""
        self.entries.setdefault(f"{owner}.{name}", []).append((s, where, enum))
        if s.is_float:
            return self.owned_field(owner, name, "float", PROTOFIELD[s.name], label, doc, where, unit=unit)
        if s.is_bool:
            return self.owned_field(owner, name, "bool", "bool", label, doc, where)
        if unit:
            return self.owned_field(owner, name, "integer", PROTOFIELD[s.name], label, doc, where,
                                    base="UNIT_STRING", vs="{ " + lua_str(unit_text(unit)) + " }", unit=unit)
        return self.owned_field(owner, name, "integer", PROTOFIELD[s.name], label, doc, where,
                                base="HEX" if hex_base else "DEC",
                                vs=self.enum_var[enum.name] if enum is not None else None,
                                enum=enum.name if enum is not None else None)

    def read(self, data: dict, key: str, s: ir.Scalar) -> dict:
        """A descriptor that reads a scalar into field `key`: told after every layout is built
        whether its wire type is narrower than the field's (settle)."""
        self.reads.append((data, key, s))
        data["float"] = s.is_float
        return data

    def settle(self) -> None:
        """One ProtoField per key, of the widest type among its entries (a filter name has one
        type: docs/contract.md#names-across-versions; resolve.same_name lets the entries of a name
        differ in size only); narrower reads then add their value explicitly."""
        for key, entries in self.entries.items():
            scalars = list({s.name: s for s, _, _ in entries}.values())
            if len(scalars) == 1:
                continue
            wide = max(scalars, key=lambda s: s.size)
            self.wide[key] = wide
            pf = self.by_key[key]
            pf.ctor = PROTOFIELD[wide.name]
            for flag in self.fields:
                if flag.parent == key:
                    flag.bits = wide.bits
        for data, key, s in self.reads:
            wide = self.wide.get(key, s)
            data["value"] = s.name != wide.name

    def header_field(self, key: str, h: ir.HeaderField) -> str:
        """ur.length, ur.type, ur.package.*: outside the owner.field scheme."""
        return self.add_field(PField(key, "integer", PROTOFIELD[h.scalar.name], f"ur.{key}", h.label, h.doc,
                                     base="DEC", vs=self.enum_var[h.enum.name] if h.enum is not None else None,
                                     enum=h.enum.name if h.enum is not None else None),
                              h.where)

    def add_item(self, name: str, label: str, doc: str, where: ir.Where) -> str:
        """The subtree field of a package or message: ur.<name>, true when it is present."""
        if name in self.by_key:
            self.problems.append(where.problem(f"lua target: the filter name ur.{name} is taken already"))
        return self.add_field(PField(name, "none", "none", f"ur.{name}", label, doc), where)

    def names_of(self, enum: Optional[ir.Enum], label: str) -> dict:
        """How a field of this enum is named: by the version's table when its codes depend on it."""
        if enum is not None and enum.name in self.enum_tables:
            return dict(tables=self.enum_tables[enum.name], label=label)
        return dict(tables=None, label=None)

    def unique(self, table: str, name: str) -> str:
        """A Lua name in table L or PART, once (two group items may share a name in other versions)."""
        var, n = f"{table}.{name}", 2
        while var in self.names:
            var, n = f"{table}.{name}_{n}", n + 1
        self.names.add(var)
        return var

    # ---- descriptors: what the runtime walks, one per field ----

    def descriptors(self, owner: str, steps: list[plan.Step], keep: set[str], show: Optional[dict] = None) -> list[Step]:
        """The descriptors of a layout's plan, in wire order: one per field, and a `cond`
        descriptor around the fields of each condition group."""
        out = []
        show = show or {}
        for step in steps:
            if isinstance(step, plan.CondGroup):
                c = step.condition
                out.append(Step("cond", dict(present_if=c.flag, low=version_number(c.low), high=version_number(c.high),
                                             fields=self.descriptors(owner, step.steps, keep, show))))
                continue
            for f in step.fields if isinstance(step, plan.FixedRun) else [step.field]:
                out.append(self.descriptor(owner, f, describe(f, self.sent.get(f"{owner}.{f.name}", "")), f.name,
                                           keep, show.get(f.name)))
        return out

    def descriptor(self, owner: str, f: ir.AnyField, doc: str, path: str, keep: set[str],
                   show: Optional[str]) -> Step:
        """One field's descriptor; `show` is the text the Info column puts before its value."""
        common = dict(path=path, show=show)
        # A float's unit follows its value in the tree (see scalar_field).
        unit = unit_text(f.unit) if isinstance(f, (ir.ScalarField, ir.ArrayField)) and f.scalar.is_float else None
        if isinstance(f, ir.ScalarField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, f.label, doc, f.where, unit=f.unit,
                                    hex_base=bool(f.bits) and not f.scalar.signed)
            data = self.read(dict(common, field=key, size=f.scalar.size, signed=f.scalar.signed and not f.scalar.is_float,
                                  vs=self.enum_var[f.enum.name] if f.enum is not None else None, unit=unit,
                                  keep=f.name if f.name in keep else None, **self.names_of(f.enum, f.label)),
                             key, f.scalar)
            if not f.bits:
                return Step("scalar", data)
            bits = [self.owned_field(owner, f"{f.name}.{b}", "flag", "bool", label, f"Bit {i} of {f.label}: {label}.",
                                     f.where, bits=f.scalar.bits, mask=1 << i, parent=key)
                    for i, (b, label) in enumerate(zip(f.bits, f.bit_labels))]
            data["bits"] = bits
            return Step("bits", data)
        if isinstance(f, ir.ArrayField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, f.label, doc, f.where, unit=f.unit)
            return Step("array", self.read(dict(common, field=key, size=f.scalar.size, count=f.count,
                                                signed=f.scalar.signed and not f.scalar.is_float, unit=unit,
                                                **self.names_of(f.enum, f.label)), key, f.scalar))
        if isinstance(f, ir.GroupField):
            key = self.owned_field(owner, f.name, "none", "none", f.item_label, doc, f.where)
            item = self.plan.item_of(f)
            item_var = self.unique("L", f"{owner}_{f.item.name}")
            self.layouts.append(LayoutView(item_var, one_line(f.doc) or f"One entry of {f.name}.",
                                           self.descriptors(owner, item.layout.steps, keep)))
            return Step("group", dict(common, field=key, label=f.item_label, count=f.count,
                                      size=item.layout.fixed_size if item.fixed else None, item=item_var))
        if isinstance(f, ir.StringField):
            key = self.owned_field(owner, f.name, "text", "string", f.label, doc, f.where, base="UNICODE")
            if f.length is None:
                return Step("string", dict(common, field=key))
            return Step("pstring", dict(common, field=key, size=f.length.size, signed=f.length.signed))
        if isinstance(f, ir.StringListField):
            key = self.owned_field(owner, f.name, "text", "string", f.item_label, doc, f.where, base="UNICODE")
            return Step("strings", dict(common, field=key, term=f.terminator))
        if isinstance(f, ir.BytesField):
            key = self.owned_field(owner, f.name, "bytes", "bytes", f.label, doc, f.where)
            return Step("bytes", dict(common, field=key))
        if isinstance(f, ir.SwitchField):
            default = dict(field=self.scalar_field(owner, f.name, f.default, None, f.label, doc, f.where, unit=f.unit),
                           size=f.default.size, unit=unit_text(f.unit) if f.default.is_float else None)
            cases = []
            for code, s in sorted(f.cases.items()):
                key = self.scalar_field(owner, f"{f.name}_{s.name}", s, None, f.label,
                                        one_line(doc, f"(as {s.name}: {f.selector.name} is {code})"), f.where,
                                        unit=f.unit)
                cases.append(dict(code=code, field=key, size=s.size, unit=unit_text(f.unit) if s.is_float else None))
            return Step("switch", dict(common, sel=f.selector.name, default=default, cases=cases))
        if isinstance(f, ir.ValueListField):
            return Step("values", dict(common, term=f.terminator, **self.value_fields(owner, f)))
        self.problems.append(f.where.problem(f"lua target: no descriptor for a {type(f).__name__}"))
        return Step("bytes", dict(common, field=None))

    def value_fields(self, owner: str, f: ir.ValueListField) -> dict:
        """The fields of typed values: one item per value, its type, and one field per data kind."""
        def add(name: str, shape: str, ctor: str, label: str, desc: str, **more) -> str:
            return self.owned_field(owner, name, shape, ctor, label, desc, f.where, **more)

        roles = [
            ("item", add(f.name, "none", "none", f.item_label, describe(f))),
            ("type", add("type", "text", "string", "Type",
                         "Value type name, from the table of the stream's software version.", base="ASCII")),
            ("code", add("type_code", "integer", "uint8", "Type code", "Value type byte.", base="DEC")),
            ("count", add("length", "integer", "int16", "Length", "Items of a LIST, or bytes of a string.",
                          base="DEC")),
            ("rows", add("rows", "integer", "int16", "Rows", "Rows of a MATRIX.", base="DEC")),
            ("cols", add("columns", "integer", "int16", "Columns", "Columns of a MATRIX.", base="DEC")),
            ("row", add("row", "none", "none", "Row", "One row of a MATRIX.")),
        ]
        kinds = []
        for kind in sorted({lay.item.name for lay in self.p.value_layouts.values() if lay.item is not None}):
            kinds.append((kind, self.scalar_field(owner, f"value_{kind}", ir.SCALARS[kind], None, "Value",
                                                  f"A value of type {kind}.", f.where)))
        string = add("value_string", "text", "string", "Value", "A string value.", base="UNICODE")
        return dict(roles=roles, kinds=kinds, string=string, label=f.item_label)

    # ---- layouts and messages ----

    def keep_names(self, struct: ir.Struct) -> set[str]:
        out = set()
        for f in struct.fields:
            if f.present_if:
                out.add(f.present_if)
            if isinstance(f, ir.SwitchField):
                out.add(f.selector.name)
        return out

    def layout(self, owner: str, layout: plan.LayoutPlan, doc: str, show: dict) -> LayoutView:
        view = LayoutView(self.unique("L", owner), doc,
                          self.descriptors(owner, layout.steps, self.keep_names(layout.struct), show=show))
        self.layouts.append(view)
        return view

    def header_layout(self, name: str, owner: str, slots: list[plan.HeaderSlot], doc: str) -> str:
        """A message header (a fixed run of scalars), its fields named under `owner`."""
        var = self.unique("L", name)
        self.layouts.append(LayoutView(var, doc, [self.descriptor(owner, s.field, describe(s.field),
                                                                  s.field.name, set(), None) for s in slots]))
        return var

    def check_summary(self, layout: ir.Layout, descriptors: list[Step], show: dict) -> None:
        """The Info column reads a summary from the raw bytes (runtime/info.lua): each field must
        be one it can show, after fields it can step over (fixed ones, texts, version-gated parts)."""
        missing = set(show)

        def check(steps: list[Step]) -> bool:
            """False where the Info column stops: at a field it cannot step over, or when every
            summary field is found."""
            for d in steps:
                if d.kind == "cond" and d.present_if is None:
                    if not check(d.fields):
                        return False
                    continue
                if d.path in missing:
                    is_float = d.kind in ("scalar", "bits") and d.float
                    if d.kind not in SHOWS or is_float:
                        self.problems.append(layout.where.problem(
                            f"lua target: the summary cannot show '{d.path}', a {'float' if is_float else d.kind} field"))
                    missing.discard(d.path)
                if not missing:
                    return False
                if d.kind not in STEPS_OVER and not (d.kind == "group" and d.count is not None and d.size is not None):
                    return False
            return True

        check(descriptors)
        for name in sorted(missing):
            self.problems.append(layout.where.problem(
                f"lua target: the summary's field '{name}' comes after a field the Info column cannot step over"))

    def shown_layout(self, lay: ir.Layout, choice_plan: plan.LayoutPlan) -> tuple[str, bool]:
        """The descriptor list of a package or subtype, its summary fields marked `show` with the
        text put before each; and whether it has a summary."""
        show = {name: before for before, name in lay.summary}
        sent_by(lay.struct, lay.name, self.sent)
        view = self.layout(lay.name, choice_plan, node_text(lay), show)
        if show:
            self.check_summary(lay, view.descriptors, show)
        return view.var, bool(show)

    def forms(self, mp: plan.MessagePlan, parts: dict[int, str]) -> list[dict]:
        """Per type code, the forms it takes (plan.Variant): its layout's data, its body sizes,
        the version it stands for when its length alone chose it, the versions that send it; and
        the plan's tables: the form of each segment (MessagePlan.by_segment: 1-based, negative
        for the nearest below's) and the sizes that recognise one form (by_length)."""
        out = []
        for code, variants in sorted(mp.variants.items()):
            forms = [dict(part=parts[id(v.layout)], sizes=sorted(v.sizes) if v.sizes is not None else None,
                          min=v.min_size, rep=ir.version_text(v.rep), versions=v.describe())
                     for v in variants]
            rows = mp.by_segment[code]
            single = len(variants) == 1 and not any(sf.nearest for sf in rows)
            segments = [-(sf.form + 1) if sf.nearest else sf.form + 1 for sf in rows]
            by_length = [dict(size=size, form=k + 1) for size, k in mp.by_length[code].items()]
            out.append(dict(code=code, single=single, forms=forms, segments=segments, by_length=by_length))
        return out

    @staticmethod
    def version_dependent(mp: plan.MessagePlan, lay: ir.Layout) -> bool:
        """True when reading this layout, or choosing it, depends on the software version."""
        return lay.struct.needs_version or not lay.versions.unbounded or len(mp.variants[lay.code.value]) > 1

    def code_names(self, enum: ir.Enum) -> Optional[str]:
        return self.enum_tables.get(enum.name)

    def package_message(self, mp: plan.MessagePlan) -> Step:
        m = mp.message
        parts, summaries, parts_of = [], {}, {}
        for c in mp.layouts:
            pk = c.layout
            label = layout_label(pk)
            layout, summary = self.shown_layout(pk, c.plan)
            var = self.unique("PART", pk.name)
            parts_of[id(pk)] = var
            summaries[var] = summary
            parts.append(dict(var=var, name=pk.name, label=label, layout=layout, summary=summary,
                              item=self.add_item(pk.name, label, one_line(pk.doc), pk.where)))
        codes = self.forms(mp, parts_of)
        for code in codes:
            code["summary"] = any(summaries[f["part"]] for f in code["forms"])
        return Step("packages", dict(code=m.code.value, label=words(m.name), doc=node_text(m),
                                     var=f"{m.name.upper()}_PACKAGES", parts=parts, codes=codes,
                                     types=self.enum_var[m.package_type.name],
                                     type_tables=self.code_names(m.package_type),
                                     needs_version=any(self.version_dependent(mp, c.layout) for c in mp.layouts),
                                     length="package.length", type="package.type"))

    def dispatch_message(self, mp: plan.MessagePlan) -> Step:
        m = mp.message
        sub_field = self.scalar_field(m.name, m.subtype.name, m.subtype.scalar, m.subtype.enum, m.subtype.label,
                                      one_line(m.subtype.doc, "Subtype of the message."), m.subtype.where)
        # The header then the subtype: shown as such when the subtype is unknown.
        header = self.header_layout(m.name, m.name, mp.header, f"Header and subtype of every {words(m.name).lower()}.")
        parts, parts_of = [], {}
        for c in mp.layouts:
            st = c.layout
            # The header fields of a subtype are filterable under its own name (ur.key.timestamp).
            sub_header = self.header_layout(f"{st.name}_header", st.name,
                                            [slot for slot in mp.header if not slot.is_subtype],
                                            f"Header of the {st.name} message.")
            body, _ = self.shown_layout(st, c.plan)
            var = self.unique("PART", st.name)
            parts_of[id(st)] = var
            label = layout_label(st)
            parts.append(dict(var=var, name=st.name, label=label, header=sub_header, layout=body,
                              needs_version=self.version_dependent(mp, st),
                              item=self.add_item(st.name, label, one_line(st.doc), st.where)))
        return Step("subtypes", dict(code=m.code.value, label=words(m.name), doc=node_text(m),
                                     var=f"{m.name.upper()}_SUBTYPES", body_offset=mp.body_offset,
                                     header=header, subtype_field=sub_field, subtype_label=m.subtype.label,
                                     subtype_names=self.enum_var[m.subtype_enum.name],
                                     subtype_tables=self.code_names(m.subtype_enum),
                                     parts=parts, codes=self.forms(mp, parts_of)))

    def body_message(self, mp: plan.MessagePlan) -> Step:
        """A message that is one layout right after the message header (no subtype byte)."""
        m = mp.message
        (lay,) = {id(c.layout): c.layout for c in mp.layouts}.values()
        body, _ = self.shown_layout(lay, mp.layouts[0].plan)
        var = self.unique("PART", lay.name)
        label = layout_label(lay)
        part = dict(var=var, name=lay.name, label=label, layout=body, needs_version=self.version_dependent(mp, lay),
                    item=self.add_item(lay.name, label, one_line(lay.doc), lay.where))
        return Step("body", dict(code=m.code.value, label=label, doc=node_text(m), var=f"{m.name.upper()}_FORMS",
                                 body_offset=mp.body_offset, parts=[part], codes=self.forms(mp, {id(lay): var})))

    def value_tables(self) -> list[dict]:
        """The value-type codes of each software-version range, with how each type is laid out."""
        p = self.p
        tables = []
        for t in p.value_type.tables:
            kinds = []
            for v in t.values:
                lay = p.value_layouts[v.name]
                kinds.append(dict(code=v.value, name=v.name, layout=lay.layout,
                                  item=lay.item.name if lay.item else None,
                                  size=lay.item.size if lay.item else 0,
                                  count=lay.count if lay.layout == "array" else 1,
                                  length=lay.length.size if lay.length else 0))
            tables.append(dict(low=version_number(t.versions.low), high=version_number(t.versions.high),
                               versions=t.versions.describe(), kinds=kinds, min_size=self.p.value_min_size(t)))
        return tables

    def constants(self) -> dict:
        """Sizes and defaults the runtime reads from `spec`."""
        p = self.p
        for what, h in (("message type", p.message_type), ("package type", p.package_type)):
            if h.scalar.size != 1:
                self.problems.append(h.where.problem(
                    f"lua target: the {what} must be one byte (the runtime reads it with string.byte)"))
        return dict(title=p.title, header_size=p.header_size, length_size=p.message_length.scalar.size,
                    package_header_size=p.package_header_size, package_length_size=p.package_length.scalar.size,
                    max_message_length=p.max_message_length, max_value_depth=p.max_value_depth,
                    max_tree_items=MAX_TREE_ITEMS,
                    default_ports=",".join(str(x) for x in p.ports),
                    default_version=ir.version_text(p.default_version))

    def enums(self) -> list[dict]:
        """Every enum's value strings: one per version table (the newest is VS.<NAME>, the
        field's value string, so filters by name follow today's firmware), and for an enum whose
        codes depend on the version, the tables by version (NAMES.<NAME>)."""
        out = []
        for e in self.p.enums.values():
            if e is self.p.value_type:
                continue   # value types are named by the runtime, from the version's table
            upper = e.name.upper()
            self.enum_var[e.name] = f"VS.{upper}"
            tables = []
            for t in e.tables:
                var = f"VS.{upper}" if t is e.tables[-1] else f"VS.{upper}_{table_suffix(t)}"
                tables.append(dict(var=var, versions=t.versions.describe(), low=version_number(t.versions.low),
                                   high=version_number(t.versions.high),
                                   entries=[(v.value, v.name) for v in t.values]))
            if e.versioned:
                self.enum_tables[e.name] = f"NAMES.{upper}"
            out.append(dict(name=e.name, upper=upper, doc=node_text(e), tables=tables,
                            versioned=e.versioned, newest=f"VS.{upper}"))
        return out

    def build(self) -> dict:
        p = self.p
        enums = self.enums()
        self.header_field("length", p.message_length)
        self.header_field("type", p.message_type)
        self.header_field("package.length", p.package_length)
        self.header_field("package.type", p.package_type)
        messages = [(self.dispatch_message(mp) if mp.message.has_subtype else self.body_message(mp))
                    if mp.is_dispatch else self.package_message(mp) for mp in self.plan.messages]
        self.settle()
        # Which fields of a package a filter or column may ask for (TreeItem:referenced).
        for m in messages:
            for pk in m.parts if m.kind == "packages" else []:
                pk["refs"] = [pf.key for pf in sorted(self.fields, key=lambda pf: pf.key)
                              if pf.key.startswith(pk["name"] + ".")]
        version, constants = self.version_reader(), self.constants()
        if self.problems:
            raise SpecError(p.source, self.problems)
        return dict(enums=enums, fields=self.fields, layouts=self.layouts, messages=messages,
                    version=version, value_tables=self.value_tables(),
                    known_codes=p.known_message_codes, message_type_names=self.enum_var[p.message_type_enum.name],
                    message_type_tables=self.code_names(p.message_type_enum), constants=constants,
                    segment_lines=textwrap.wrap(", ".join(f'"{ir.version_text(s.first)}"' for s in self.plan.segments
                                                          if s.first), 100))

    def version_reader(self) -> dict:
        """Where the Version message keeps its numbers: fixed bytes and length-prefixed strings,
        then major and minor, then (in the versions its range gives) the bugfix number."""
        v = self.plan.version
        if any(f.fixed_size != 1 for f in (v.major, v.minor)):
            self.problems.append(v.layout.where.problem("lua target: major and minor versions must be one byte each"))
        bugfix = None
        if v.bugfix is not None:
            s = v.bugfix.scalar
            if s.is_float or s.is_bool or s.size > 4:
                self.problems.append(v.bugfix.where.problem(
                    "lua target: the bugfix number must be an integer of at most 4 bytes"))
            bugfix = dict(size=s.size, signed=s.signed, low=version_number(v.bugfix.versions.low),
                          high=version_number(v.bugfix.versions.high))
        steps = [dict(fixed=skip.fixed + (v.body_offset if i == 0 else 0), prefix=skip.prefix, signed=skip.signed)
                 for i, skip in enumerate(v.skips)]
        return dict(message=v.message_code, subtype=v.subtype_code, subtype_offset=v.subtype_offset,
                    steps=steps, tail=v.tail + (0 if v.skips else v.body_offset), rest=v.rest, bugfix=bugfix)


def view_model(protocol_plan: plan.ProtocolPlan) -> dict:
    """The dissector's model: fields, value strings, layouts (descriptors), messages and their forms.
    The native dissector (targets/epan.py) renders the same model, so that the two stay twins."""
    return _Builder(protocol_plan).build()


def runtime() -> list[str]:
    """The runtime files in joining order, as joined (emit.runtime_section)."""
    folder = RUNTIME_FOLDER / "lua"
    # runtime/lua/<interface>_<part>.lua belongs to another interface's dissector, not to this one.
    found = sorted(p.name for p in folder.glob("*.lua") if "_" not in p.stem)
    if sorted(RUNTIME) != found:
        raise ValueError(f"lua target: runtime files {found} differ from the joining order {list(RUNTIME)}")
    return [runtime_section("lua", name) for name in RUNTIME]


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment("lua")
    env.filters["lua"] = lua_literal
    env.filters["lua_text"] = lua_text
    env.filters["lua_field"] = lua_field
    model = view_model(protocol_plan)
    ctx = dict(banner=banner, p=p, doc=one_line(p.doc), runtime=runtime(), **model)
    return {OUT: env.get_template("urwire.lua.j2").render(**ctx)}
