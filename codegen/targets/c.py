"""C target: the IR -> a view model of C declarations and statements -> templates/c/*.j2.

Every decision is made here: C types, struct members, offsets inside fixed runs, the statement
text of each read, write and visit. The templates only lay these strings out (Emboss style).
The output is C99 with no malloc and no stdio: one header and one source, generated/c/urwire.{h,c}.
"""
from __future__ import annotations

import textwrap
from dataclasses import dataclass, field
from typing import Optional

from .. import ir, plan
from ..emit import environment, runtime_source
from ..errors import Problem, SpecError
from ..view import Step

FOLDER = "c"
C_TYPES = {"bool": "uint8_t", "int8": "int8_t", "uint8": "uint8_t", "int16": "int16_t", "uint16": "uint16_t",
           "int32": "int32_t", "uint32": "uint32_t", "int64": "int64_t", "uint64": "uint64_t",
           "float32": "float", "float64": "double"}
READERS = {"bool": "urwire__u8", "int8": "urwire__i8", "uint8": "urwire__u8", "int16": "urwire__i16",
           "uint16": "urwire__u16", "int32": "urwire__i32", "uint32": "urwire__u32", "int64": "urwire__i64",
           "uint64": "urwire__u64", "float32": "urwire__f32", "float64": "urwire__f64"}
WRITERS = {"bool": "urwire__put_u8", "int8": "urwire__put_i8", "uint8": "urwire__put_u8", "int16": "urwire__put_i16",
           "uint16": "urwire__put_u16", "int32": "urwire__put_i32", "uint32": "urwire__put_u32",
           "int64": "urwire__put_i64", "uint64": "urwire__put_u64", "float32": "urwire__put_f32",
           "float64": "urwire__put_f64"}
# Visitor callback for each scalar: signed integers as int64, unsigned as uint64.
VISIT = {"bool": "on_bool", "int8": "on_int", "int16": "on_int", "int32": "on_int", "int64": "on_int",
         "uint8": "on_uint", "uint16": "on_uint", "uint32": "on_uint", "uint64": "on_uint",
         "float32": "on_f32", "float64": "on_f64"}
C_KEYWORDS = {"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum",
              "extern", "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return",
              "short", "signed", "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void",
              "volatile", "while", "_Bool"}
# Value layouts the hand-written value decoder (templates/c/runtime/values.c) knows.
VALUE_ITEMS = {"bool": "URWIRE__ITEM_BOOL", "int32": "URWIRE__ITEM_I32", "float32": "URWIRE__ITEM_F32"}
VALUE_LAYOUTS = {"empty": "URWIRE__LAYOUT_EMPTY", "string": "URWIRE__LAYOUT_STRING", "array": "URWIRE__LAYOUT_ARRAY",
                 "scalar": "URWIRE__LAYOUT_SCALAR", "list": "URWIRE__LAYOUT_LIST", "matrix": "URWIRE__LAYOUT_MATRIX"}


def comment(*texts: str, width: int = 92) -> list[str]:
    """Doc strings as the lines of a C comment body (no delimiters), wrapped."""
    text = " ".join(t.strip() for t in texts if t and t.strip()).replace("*/", "* /")
    return textwrap.wrap(text, width) if text else []


def inline(*texts: str) -> str:
    return " ".join(t.strip() for t in texts if t and t.strip()).replace("*/", "* /")


def plus(base: str, k: int) -> str:
    return base if k == 0 else f"{base} + {k}"


@dataclass
class Member:
    decl: str
    doc: str = ""
    above: list[str] = field(default_factory=list)   # a long doc, as comment lines above

    def place(self) -> "Member":
        """Short docs stay at the end of the line; long ones go above the member."""
        if len(self.decl) + len(self.doc) > 88:
            self.above, self.doc = comment(self.doc, width=88), ""
        return self


@dataclass
class BitSet:
    tag: str
    field: str
    members: list[dict]


@dataclass
class Span:
    path: str
    offset: int
    size: int


@dataclass
class Run:
    table: str
    size: int
    spans: list[Span]


@dataclass
class CStruct:
    name: str             # spec name (robot_mode_data, joint, version)
    ctype: str            # urwire_robot_mode_data
    doc: list[str]
    members: list[Member]
    role: str             # package | subtype | item
    runs: list[Run] = field(default_factory=list)
    decode: list[Step] = field(default_factory=list)
    encode: list[Step] = field(default_factory=list)
    visit: list[Step] = field(default_factory=list)
    fixed_item: bool = False        # laid out in its parent's fixed run: read/write/visit helpers
    item_reads: list[str] = field(default_factory=list)
    item_writes: list[str] = field(default_factory=list)
    item_size: int = 0
    needs_index: bool = False
    needs_p: bool = False
    decode_index: bool = False
    encode_index: bool = False
    visit_index: bool = False
    item_index: bool = False
    can_fail: bool = True
    bitsets: list = field(default_factory=list)

    def indent(self, verb: str, ret: str) -> str:
        """Spaces that align a wrapped parameter list under `static <ret> urwire__<verb>_<name>(`."""
        return " " * len(f"static {ret} urwire__{verb}_{self.name}(")

    @property
    def decode_indent(self) -> str:
        return self.indent("decode", "inline bool")

    @property
    def encode_indent(self) -> str:
        return self.indent("encode", "bool")

    @property
    def visit_indent(self) -> str:
        return self.indent("visit", "void")
    to_end_item: bool = False       # items of a to_end group: public iteration function
    code: Optional[int] = None
    code_const: str = ""
    kind_const: str = ""
    sets_version: Optional[tuple[str, str]] = None


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.structs: list[CStruct] = []
        self.items: dict[int, CStruct] = {}
        self.problems: list[Problem] = []

    # ---- one struct ----

    def build(self, layout: plan.LayoutPlan, name: str, ctype: str, role: str, doc: list[str]) -> CStruct:
        struct = layout.struct
        for f in struct.fields:
            if isinstance(f, ir.GroupField):
                item_plan = self.plan.item_of(f)
                item = self.build(item_plan.layout, f.item.name, f"urwire_{f.item.name}", "item",
                                  comment(f.doc) or [f"One entry of {f.name}."])
                self.items[id(f)] = item
        cs = CStruct(name, ctype, doc, [], role)
        for f in struct.fields:
            cs.members.append(self.member(f, name).place())
            if isinstance(f, ir.ScalarField) and f.bits:
                prefix = f"URWIRE_{name.upper()}_{f.name.upper()}"
                cs.bitsets.append(BitSet(f"urwire_{name}_{f.name}_bit", f.name,
                                         [dict(const=f"{prefix}_{b.upper()}", bit=k) for k, b in enumerate(f.bits)]))
        if role != "item":
            cs.members.append(Member("urwire_bytes extra", "Bytes after the known layout (flagged; kept for encoding)."))
        cs.decode, cs.encode = self.steps(cs, layout.steps)
        cs.visit = self.visit_steps(cs, struct.fields)
        fixed = role == "item" and any(it.layout is layout and it.fixed for it in self.plan.items)
        if fixed:
            # Read and written inside its parent's checked run.
            cs.fixed_item = True
            cs.item_size = layout.fixed_size
            for m in layout.runs[0].members:
                cs.item_reads.append(self.read_line(m, "out->"))
                cs.item_writes.append(self.write_line(m, "in->"))
            cs.item_index = any(_loops(m) for m in layout.runs[0].members)
        elif role == "item":
            cs.to_end_item = True
        cs.decode_index = uses_index(cs.decode)
        cs.encode_index = uses_index(cs.encode)
        cs.visit_index = uses_index(cs.visit)
        cs.needs_p = has_run(cs.decode)
        cs.can_fail = can_fail(cs.decode)
        self.structs.append(cs)
        return cs

    def member(self, f: ir.AnyField, owner: str) -> Member:
        name = f.name
        if name in C_KEYWORDS:
            self.problems.append(f.where.problem(f"c target: field name '{name}' is a C keyword"))
        doc = inline(f.doc, f.field_note)
        if f.present_if:
            doc = inline(doc, f"Present only when {f.present_if} is nonzero (else 0).")
        if isinstance(f, ir.ScalarField):
            if f.scalar.is_bool:
                doc = inline(doc, "The wire byte: nonzero is true.")
            if f.enum is not None:
                doc = inline(doc, f"See enum urwire_{f.enum.name}.")
            if f.bits:
                doc = inline(doc, f"Masks: enum urwire_{owner}_{f.name}_bit.")
            return Member(f"{C_TYPES[f.scalar.name]} {name}", doc)
        if isinstance(f, ir.ArrayField):
            return Member(f"{C_TYPES[f.scalar.name]} {name}[{f.count}]", doc)
        if isinstance(f, ir.GroupField):
            item = self.items[id(f)]
            if f.count is not None:
                return Member(f"{item.ctype} {name}[{f.count}]", doc)
            return Member(f"urwire_seq {name}",
                          inline(doc, f"Iterate with urwire_next_{item.name}() on a copy."))
        if isinstance(f, ir.StringField):
            return Member(f"urwire_bytes {name}", inline(doc, "UTF-8 text as sent, a view into the message."))
        if isinstance(f, ir.BytesField):
            return Member(f"urwire_bytes {name}", doc)
        if isinstance(f, ir.StringListField):
            return Member(f"urwire_seq {name}", inline(doc, "Iterate with urwire_next_text() on a copy."))
        if isinstance(f, ir.ValueListField):
            return Member(f"urwire_seq {name}", inline(doc, "Iterate with urwire_next_value() on a copy."))
        assert isinstance(f, ir.SwitchField)
        cases = "; ".join(f"{k}: .{s.name}" for k, s in f.cases.items())
        scalars = sorted({s.name for s in list(f.cases.values()) + [f.default]}, key=list(C_TYPES).index)
        body = " ".join(f"{C_TYPES[s]} {s};" for s in scalars)
        return Member(f"union {{ {body} }} {name}",
                      inline(doc, f"Chosen by {f.selector.name}: {cases}; otherwise .{f.default.name}."))

    # ---- fixed runs: one statement per member ----

    def read_line(self, m: plan.Member, ref: str) -> str:
        f, at = m.field, plus("p", m.offset)
        if isinstance(f, ir.ScalarField):
            return f"{ref}{f.name} = {READERS[f.scalar.name]}({at});"
        if isinstance(f, ir.ArrayField):
            return (f"for (i = 0; i < {f.count}; i++) {ref}{f.name}[i] = "
                    f"{READERS[f.scalar.name]}({at} + {f.scalar.size} * i);")
        return (f"for (i = 0; i < {f.count}; i++) urwire__read_{f.item.name}({at} + "
                f"{m.item.layout.fixed_size} * i, &{ref}{f.name}[i]);")

    def write_line(self, m: plan.Member, ref: str) -> str:
        f, at = m.field, plus("p", m.offset)
        if isinstance(f, ir.ScalarField):
            return f"{WRITERS[f.scalar.name]}({at}, {ref}{f.name});"
        if isinstance(f, ir.ArrayField):
            return (f"for (i = 0; i < {f.count}; i++) {WRITERS[f.scalar.name]}({at} + "
                    f"{f.scalar.size} * i, {ref}{f.name}[i]);")
        return (f"for (i = 0; i < {f.count}; i++) urwire__write_{f.item.name}({at} + "
                f"{m.item.layout.fixed_size} * i, &{ref}{f.name}[i]);")

    def run_steps(self, cs: CStruct, run: plan.FixedRun) -> tuple[Step, Step]:
        table = f"urwire__{cs.name}_run{run.index}"
        cs.runs.append(Run(table, run.size, [Span(leaf.path, leaf.offset, leaf.scalar.size) for leaf in run.leaves]))
        loops = any(_loops(m) for m in run.members)
        return (Step("run", dict(table=table, size=run.size, loops=loops,
                                 lines=[self.read_line(m, "out->") for m in run.members])),
                Step("run", dict(size=run.size, loops=loops, lines=[self.write_line(m, "in->") for m in run.members])))

    # ---- decode and encode steps ----

    def steps(self, cs: CStruct, steps: list[plan.Step]) -> tuple[list[Step], list[Step]]:
        dec: list[Step] = []
        enc: list[Step] = []
        for step in steps:
            if isinstance(step, plan.FixedRun):
                d, e = self.run_steps(cs, step)
            elif isinstance(step, plan.CondGroup):
                inner_d, inner_e = self.steps(cs, step.steps)
                zero = [f"out->{g.name} = 0;" if isinstance(g, ir.ScalarField) else
                        f"memset(&out->{g.name}, 0, sizeof out->{g.name});" for g in step.fields]
                d = Step("cond", dict(test=condition(step.condition, "out->"), steps=inner_d, zero=zero))
                e = Step("cond", dict(test=condition(step.condition, "in->"), steps=inner_e))
            else:
                d, e = self.dynamic(cs, step.field, step.path)
            dec.append(d)
            enc.append(e)
        return dec, enc

    def dynamic(self, cs: CStruct, f: ir.AnyField, path: str) -> tuple[Step, Step]:
        if isinstance(f, ir.StringField) and f.length is not None:
            s = f.length
            data = dict(name=f.name, path=path, size=s.size, reader=READERS[s.name],
                        max=f"{s.max}u" if not s.signed else str(s.max), signed=s.signed)
            return Step("prefixed_text", data), Step("prefixed_text", data)
        if isinstance(f, (ir.StringField, ir.BytesField)):
            return Step("rest", dict(name=f.name)), Step("bytes", dict(name=f.name))
        if isinstance(f, ir.StringListField):
            return (Step("texts", dict(name=f.name, terminator=f"0x{f.terminator:02x}")),
                    Step("seq", dict(name=f.name)))
        if isinstance(f, ir.ValueListField):
            return (Step("values", dict(name=f.name, terminator=f"0x{f.terminator:02x}", path=path)),
                    Step("seq", dict(name=f.name)))
        if isinstance(f, ir.SwitchField):
            cases = [dict(value=k, size=s.size, reader=READERS[s.name], writer=WRITERS[s.name], member=s.name)
                     for k, s in f.cases.items()]
            d = f.default
            data = dict(name=f.name, selector=f.selector.name, path=path, cases=cases,
                        default=dict(size=d.size, reader=READERS[d.name], writer=WRITERS[d.name], member=d.name))
            cs.needs_p = True
            return Step("switch", data), Step("switch", data)
        assert isinstance(f, ir.GroupField)
        item = self.items[id(f)]
        return (Step("group_to_end", dict(name=f.name, item=item.name, ctype=item.ctype)),
                Step("seq", dict(name=f.name)))

    # ---- visiting (the canonical JSON order: spec order) ----

    def visit_steps(self, cs: CStruct, fields: list[ir.AnyField]) -> list[Step]:
        out: list[Step] = []
        for f in fields:
            out.append(self.visit_one(cs, f))
        return out

    def visit_one(self, cs: CStruct, f: ir.AnyField) -> Step:
        cond = plan.condition_of(f)
        test = condition(cond, "in->") if cond else ""
        if isinstance(f, ir.ScalarField):
            return Step("scalar", dict(name=f.name, cb=VISIT[f.scalar.name], test=test,
                                       arg=visit_arg(f.scalar, f"in->{f.name}")))
        if isinstance(f, ir.ArrayField):
            return Step("array", dict(name=f.name, cb=VISIT[f.scalar.name], count=f.count, test=test,
                                      arg=visit_arg(f.scalar, f"in->{f.name}[i]")))
        if isinstance(f, ir.GroupField):
            item = self.items[id(f)]
            if f.count is not None:
                return Step("group", dict(name=f.name, item=item.name, count=f.count, test=test))
            return Step("group_to_end", dict(name=f.name, item=item.name, ctype=item.ctype, test=test))
        if isinstance(f, ir.StringField):
            return Step("text", dict(name=f.name, test=test))
        if isinstance(f, ir.BytesField):
            return Step("hex", dict(name=f.name, test=test))
        if isinstance(f, ir.StringListField):
            return Step("texts", dict(name=f.name, test=test))
        if isinstance(f, ir.ValueListField):
            return Step("values", dict(name=f.name, test=test))
        assert isinstance(f, ir.SwitchField)
        cases = [dict(value=k, cb=VISIT[s.name], arg=visit_arg(s, f"in->{f.name}.{s.name}"))
                 for k, s in f.cases.items()]
        d = f.default
        return Step("switch", dict(name=f.name, selector=f.selector.name, cases=cases, test=test,
                                   default=dict(cb=VISIT[d.name], arg=visit_arg(d, f"in->{f.name}.{d.name}"))))


def visit_arg(s: ir.Scalar, ref: str) -> str:
    cb = VISIT[s.name]
    if cb == "on_int":
        return f"(int64_t){ref}"
    if cb == "on_uint":
        return f"(uint64_t){ref}"
    if cb == "on_bool":
        return f"{ref} != 0"
    return ref


def condition(c: plan.Condition, ref: str) -> str:
    """A plan's condition as a C test; `ref` is where field values live (out-> or in->)."""
    tests = []
    if c.flag:
        tests.append(f"{ref}{c.flag} != 0")
    if c.low:
        tests.append(f"urwire__version_cmp(version, {c.low[0]}, {c.low[1]}) >= 0")
    if c.high:
        tests.append(f"urwire__version_cmp(version, {c.high[0]}, {c.high[1]}) <= 0")
    return " && ".join(tests)


def _loops(m: plan.Member) -> bool:
    """A member read or written in a loop on i (arrays and fixed-count groups)."""
    return not isinstance(m.field, ir.ScalarField)


def has_run(steps: list[Step]) -> bool:
    return any(s.kind == "run" or (s.kind == "cond" and has_run(s.steps)) for s in steps)


def can_fail(steps: list[Step]) -> bool:
    """False when every step of a decoder always succeeds (rest-of-message views only)."""
    return any(s.kind not in ("rest", "texts", "cond") or (s.kind == "cond" and can_fail(s.steps)) for s in steps)


def uses_index(steps: list[Step]) -> bool:
    """True when a step loops on i (the template then declares it)."""
    for s in steps:
        if s.kind in ("array", "group") or (s.kind == "run" and s.loops):
            return True
        if s.kind == "cond" and uses_index(s.steps):
            return True
    return False


# ---- enums ----------------------------------------------------------------------------------

def table_suffix(t: ir.EnumTable) -> str:
    r = t.versions
    low = f"{r.low[0]}_{r.low[1]}" if r.low else ""
    high = f"{r.high[0]}_{r.high[1]}" if r.high else ""
    if low and high:
        return f"{low}_TO_{high}"
    return f"{low}_ON" if low else f"UP_TO_{high}"


def enum_views(p: ir.Protocol) -> list[dict]:
    views = []
    for e in p.enums.values():
        tables = []
        for t in e.tables:
            prefix = f"URWIRE_{e.name.upper()}" + (f"_{table_suffix(t)}" if e.versioned else "")
            members = []
            for v in t.values:
                m = Member(f"{prefix}_{v.name} = {v.value}",
                           inline(v.doc, "(undocumented)" if v.undocumented else "",
                                  f"(from {v.versions.describe()})" if not v.versions.unbounded else "")).place()
                members.append(dict(const=f"{prefix}_{v.name}", value=v.value, name=v.name, doc=m.doc, above=m.above))
            tables.append(dict(versions=t.versions.describe(), members=members,
                               low=t.versions.low, high=t.versions.high,
                               tag=f"urwire_{e.name}_{table_suffix(t).lower()}" if e.versioned else f"urwire_{e.name}"))
        # Name lookup: one case per distinct value (first name wins, as in the document's table).
        seen, cases = set(), []
        for v in e.values:
            if v.value not in seen:
                seen.add(v.value)
                cases.append(dict(value=v.value, name=v.name))
        views.append(dict(name=e.name, doc=comment(e.doc, e.field_note), wire=C_TYPES[e.scalar.name],
                          versioned=e.versioned, tables=tables, cases=cases))
    return views


def value_views(p: ir.Protocol) -> dict:
    problems: list[Problem] = []
    kinds = list(p.value_layouts)
    tables = []
    for t in p.value_type.tables:
        entries = []
        for v in t.values:
            lay = p.value_layouts[v.name]
            if lay.layout in ("string", "list", "matrix") and lay.length.name != "int16":
                problems.append(lay.where.problem(
                    f"c target: the value decoder reads int16 lengths, not {lay.length.name}"))
            item = VALUE_ITEMS[lay.item.name] if lay.item is not None else "URWIRE__ITEM_NONE"
            entries.append(dict(code=v.value, name=v.name, kind=f"URWIRE_VALUE_{v.name}",
                                layout=VALUE_LAYOUTS[lay.layout], item=item,
                                count=lay.count if lay.layout == "array" else 1))
        tables.append(dict(tag=f"urwire__values_{table_suffix(t).lower()}", versions=t.versions.describe(),
                           entries=entries, range=versions_init(t.versions)))
    if problems:
        raise SpecError(p.source, problems)
    arrays = [lay.count for lay in p.value_layouts.values() if lay.layout == "array"]
    return dict(kinds=[dict(const=f"URWIRE_VALUE_{k}", name=k, doc=inline(p.value_layouts[k].doc)) for k in kinds],
                tables=tables, array_max=max(arrays) if arrays else 1, max_depth=p.max_value_depth)


def versions_init(r: ir.VersionRange) -> str:
    """A version range as the initializer of an urwire__versions (runtime/private.h)."""
    def bound(v: Optional[ir.Version]) -> str:
        return f"true, {{{v[0]}, {v[1]}}}" if v else "false, {0, 0}"
    return f"{{{bound(r.low)}, {bound(r.high)}}}"


# ---- messages -------------------------------------------------------------------------------

def build(protocol_plan: plan.ProtocolPlan) -> dict:
    b = _Builder(protocol_plan)
    messages = []
    kinds = []
    packages = []
    layout_structs: dict[int, CStruct] = {}
    for mp in protocol_plan.messages:
        m = mp.message
        if not mp.is_dispatch:
            for c in mp.layouts:
                pk = c.layout
                if pk.code.value > 31:
                    b.problems.append(pk.where.problem("c target: package codes above 31 do not fit the present bit mask"))
                cs = b.build(c.plan, pk.name, f"urwire_{pk.name}", "package", comment(pk.doc, pk.field_note))
                cs.code = pk.code.value
                cs.code_const = f"URWIRE_{m.package_type.name.upper()}_{pk.code.name}"
                packages.append(cs)
            kinds.append(dict(const=f"URWIRE_KIND_{m.name.upper()}", doc=inline(m.doc)))
            messages.append(dict(kind="packages", name=m.name, code=m.code.value,
                                 code_const=f"URWIRE_MESSAGE_TYPE_{m.code.name}",
                                 kind_const=f"URWIRE_KIND_{m.name.upper()}", doc=comment(m.doc, m.field_note)))
            continue
        header = [dict(name=slot.field.name, ctype=C_TYPES[slot.field.scalar.name],
                       reader=READERS[slot.field.scalar.name], writer=WRITERS[slot.field.scalar.name],
                       offset=slot.offset, cb=VISIT[slot.field.scalar.name],
                       cast="(int64_t)" if VISIT[slot.field.scalar.name] == "on_int" else "(uint64_t)",
                       doc=inline(slot.field.doc, slot.field.field_note), subtype=slot.is_subtype)
                  for slot in mp.header]
        subtypes = []
        for c in mp.layouts:
            st = c.layout
            cs = b.build(c.plan, st.name, f"urwire_{st.name}_message", "subtype", comment(st.doc, st.field_note))
            cs.code = st.code.value
            cs.code_const = f"URWIRE_{m.subtype_enum.name.upper()}_{st.code.name}"
            cs.kind_const = f"URWIRE_KIND_{st.name.upper()}"
            cs.sets_version = st.sets_version
            layout_structs[id(st)] = cs
            subtypes.append(cs)
            kinds.append(dict(const=cs.kind_const, doc=inline(st.doc)))
        messages.append(dict(kind="dispatch", name=m.name, code=m.code.value,
                             code_const=f"URWIRE_MESSAGE_TYPE_{m.code.name}",
                             doc=comment(m.doc, m.field_note), header=header, header_table=f"urwire__{m.name}_header",
                             header_spans=[Span(slot.field.name, slot.offset, slot.field.scalar.size)
                                           for slot in mp.header],
                             body_offset=mp.body_offset, subtypes=subtypes, subtype_name=m.subtype.name))
    lists = [m for m in messages if m["kind"] == "packages"]
    if len(lists) != 1:
        b.problems.append(protocol_plan.protocol.messages[0].where.problem(
            "c target: the C runtime expects exactly one message that is a list of sub-packages"))
    if b.problems:
        raise SpecError(protocol_plan.protocol.source, b.problems)
    vs = protocol_plan.version
    vst = layout_structs[id(vs.layout)]
    vmsg = next(m for m in messages if m["code"] == vs.message_code)
    return dict(structs=b.structs, messages=messages, kinds=kinds, packages=packages,
                numbers=protocol_numbers(protocol_plan.protocol, lists[0], vst, vmsg),
                known_types=known_types(protocol_plan.protocol), **kind_tables(messages, packages))


def protocol_numbers(p: ir.Protocol, packages: dict, vst: CStruct, vmsg: dict) -> list[dict]:
    """The private macros through which the runtime reads the spec's framing: where the header
    fields are, which message is the sub-package list, which layout announces the version."""
    problems = [h.where.problem("c target: a message or sub-package type wider than one byte")
                for h in (p.message_type, p.package_type) if h.scalar.size != 1]
    if problems:
        raise SpecError(p.source, problems)
    ml, pl = p.message_length.scalar, p.package_length.scalar
    (subtype,) = [h for h in vmsg["header"] if h["subtype"]]
    return [
        dict(name="URWIRE__LENGTH(p)", value=f"{READERS[ml.name]}(p)",
             doc=f"message header: {ml.name} length, then the type"),
        dict(name="URWIRE__PUT_LENGTH(p, n)", value=f"{WRITERS[ml.name]}((p), ({C_TYPES[ml.name]})(n))", doc=""),
        dict(name="URWIRE__TYPE_AT", value=f"{ml.size}u", doc=""),
        dict(name="URWIRE__PACKAGE_LENGTH(p)", value=f"{READERS[pl.name]}(p)",
             doc=f"sub-package header: {pl.name} length, then the type"),
        dict(name="URWIRE__PUT_PACKAGE_LENGTH(p, n)", value=f"{WRITERS[pl.name]}((p), ({C_TYPES[pl.name]})(n))",
             doc=""),
        dict(name="URWIRE__PACKAGE_TYPE_AT", value=f"{pl.size}u", doc=""),
        dict(name="URWIRE__PACKAGES_TYPE", value=packages["code_const"], doc=f"{packages['name']}: the sub-package list"),
        dict(name="URWIRE__PACKAGES_KIND", value=packages["kind_const"], doc=""),
        dict(name="URWIRE__VERSION_TYPE", value=vmsg["code_const"],
             doc=f"{vst.name}: the layout that announces the software version"),
        dict(name="URWIRE__VERSION_SUBTYPE_AT", value=f"{subtype['offset']}u", doc=""),
        dict(name="URWIRE__VERSION_SUBTYPE", value=vst.code_const, doc=""),
        dict(name="URWIRE__VERSION_BODY", value=f"{vmsg['body_offset']}u", doc=""),
        dict(name="URWIRE__VERSION_KIND", value=vst.kind_const, doc=""),
        dict(name="URWIRE__VERSION_MAJOR(m)", value=f"((m)->as.{vst.name}.{vst.sets_version[0]})", doc=""),
        dict(name="URWIRE__VERSION_MINOR(m)", value=f"((m)->as.{vst.name}.{vst.sets_version[1]})", doc=""),
    ]


def known_types(p: ir.Protocol) -> list[str]:
    """The message types a plausible header may carry (the framer resynchronises on the others)."""
    seen: dict[int, str] = {}
    for v in p.message_type_enum.values:
        seen.setdefault(v.value, f"URWIRE_{p.message_type_enum.name.upper()}_{v.name}")
    return [seen[k] for k in sorted(seen)]


def kind_tables(messages: list[dict], packages: list[CStruct]) -> dict:
    """The rows of the tables the runtime walks (runtime/private.h), each a list of (member,
    initializer) pairs; a member left out is NULL or 0: urwire__package_kinds (by sub-package
    code; decoded through the generated switches instead), urwire__message_types (one per
    laid-out message type) and urwire__message_kinds (by urwire_message_kind)."""
    def functions(name: str) -> list[tuple[str, str]]:
        return [(verb, f"urwire__{verb}_{name}") for verb in ("decode", "encode", "visit")]

    package_rows = [dict(index=s.code_const, fields=[("name", f'"{s.name}"'), *functions(s.name)[1:]])
                    for s in packages]
    types, kinds = [], [dict(index="URWIRE_KIND_UNKNOWN_MESSAGE", fields=[("name", '"unknown"')])]
    for i, m in enumerate(messages):
        ref = ("type", f"&urwire__message_types[{i}]")
        if m["kind"] == "packages":
            types.append([("code", m["code_const"]), ("packages", "true"), ("body", "URWIRE_HEADER_SIZE")])
            kinds.append(dict(index=m["kind_const"], fields=[("name", f'"{m["name"]}"'), ref]))
            continue
        types.append([("code", m["code_const"]), ("body", f"{m['body_offset']}u"), ("header", m["header_table"]),
                      *[(f"{verb}_header", f"urwire__{verb}_{m['name']}_header") for verb in ("read", "visit", "put")]])
        for s in m["subtypes"]:
            kinds.append(dict(index=s.kind_const, fields=[("name", f'"{s.name}"'), ref, ("subtype", s.code_const),
                                                          *functions(s.name)]))
    kinds.append(dict(index="URWIRE_KIND_UNKNOWN_SUBTYPE", fields=[("name", '"unknown"')]))
    return dict(package_kinds=package_rows, message_types=types, message_kinds=kinds)


# The hand-written runtime (templates/c/runtime/), in the order each part is joined to the
# generated ones: public headers around the spec's types, then private code before the layouts
# and, after them, the code that walks their tables.
RUNTIME = {
    "types": ("version.h", "views.h", "errors.h"),
    "value": ("value.h",),
    "api": ("messages.h", "visitor.h", "framer.h"),
    "base": ("private.h", "loads.h", "views.c", "version.c", "format.c", "errors.c", "text.c", "put.c"),
    "walkers": ("values.c", "kinds.c", "decode.c", "encode.c", "visit.c", "framer.c"),
}


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment(FOLDER)
    runtime = {part: "\n".join(runtime_source(FOLDER, name) for name in names) for part, names in RUNTIME.items()}
    ctx = dict(banner=banner, p=p, enums=enum_views(p), values=value_views(p), runtime=runtime,
               default_version=p.default_version,
               documented=", ".join(ir.version_text(v) for v in p.documented_versions),
               title=p.title, doc=comment(p.doc), **build(protocol_plan))
    return {f"{FOLDER}/urwire.h": env.get_template("urwire.h.j2").render(**ctx),
            f"{FOLDER}/urwire.c": env.get_template("urwire.c.j2").render(**ctx)}
