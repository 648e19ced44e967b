"""C target: the plan -> a view model of plain data -> templates/c/packages/*.j2 (+ runtime/c/{common,packages}).

Every decision is made here: C types, struct members, the offset, reader and writer of every
member of a fixed run, conditions as terms (a flag, a version bound), the forms of every type
code and the segments of the version axis that choose them. The view model holds data only
(names, numbers, kinds); the templates render each kind with a macro of its own, chosen
through a table (Emboss style), and hold no arithmetic. The output is C99 with no malloc and
no stdio: one header and one source, generated/c/urwire.{h,c}.
"""
from __future__ import annotations

import re

from dataclasses import dataclass, field
from typing import Optional

from ... import ir
from ...comments import field_text, node_text, value_text
from ...emit import environment, runtime_section
from ...errors import Problem, SpecError
from ...lang.c import comment, inline, string
from ...lang.c_pool import Pool
from ...view import Step
from . import model, plan
from .naming import c_enum_const, c_enum_prefix, c_enum_tag, c_member_const, c_table_suffix

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


def visitor_of(s: ir.Scalar) -> str:
    """The visitor callback of a scalar, after its canonical JSON kind (ir.scalar_json_kind):
    on_bool, on_f32, on_f64, and integers signed as int64 (on_int), unsigned as uint64 (on_uint)."""
    kind = ir.scalar_json_kind(s)
    if kind == "int":
        return "on_int" if s.signed else "on_uint"
    return f"on_{kind}"


# Visitor callback for each scalar type.
VISIT = {name: visitor_of(s) for name, s in ir.SCALARS.items()}
C_KEYWORDS = {"auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum",
              "extern", "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return",
              "short", "signed", "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void",
              "volatile", "while", "_Bool"}
# Names the generated decoders, encoders and visitors use for themselves: no member may be
# called so (the struct's own `version` and `extra` are added by the generator).
RESERVED_MEMBERS = {"version", "extra"}
# Value layouts the hand-written value decoder (runtime/c/packages/values.c) knows.
VALUE_ITEMS = {"bool": "URWIRE__ITEM_BOOL", "int32": "URWIRE__ITEM_I32", "float32": "URWIRE__ITEM_F32"}
VALUE_LAYOUTS = {"empty": "URWIRE__LAYOUT_EMPTY", "string": "URWIRE__LAYOUT_STRING", "array": "URWIRE__LAYOUT_ARRAY",
                 "scalar": "URWIRE__LAYOUT_SCALAR", "list": "URWIRE__LAYOUT_LIST", "matrix": "URWIRE__LAYOUT_MATRIX"}
# A bit per sub-package code (urwire_robot_state.present) and per sub-package layout (.layouts).
MASK_BITS = 32


# ---- versions and conditions, as data -----------------------------------------------------

# The largest parts urwire__version_key (runtime/c/packages/private.h) orders exactly: bounds must stay below.
KEY_MAJOR, KEY_PART = 1 << 21, 1 << 20


def version_view(v: ir.Version) -> dict:
    major, minor, bugfix = v
    if not (0 <= major < KEY_MAJOR and 0 <= minor < KEY_PART and 0 <= bugfix < KEY_PART):
        raise SpecError("<spec>", [ir.NOWHERE.problem(f"c target: version {v} is beyond what the C runtime "
                                                      f"compares exactly")])
    return dict(major=major, minor=minor, bugfix=bugfix)


def range_view(r: ir.VersionRange) -> dict:
    """A version range as the initializer of an urwire__versions (runtime/c/packages/private.h) renders it."""
    return dict(low=version_view(r.low) if r.low else None, high=version_view(r.high) if r.high else None)


def condition_view(c: plan.Condition) -> dict:
    """A plan's condition as terms the template joins with &&: a flag field that must be
    nonzero, a lowest and a highest version."""
    terms = []
    if c.flag:
        terms.append(dict(kind="flag", name=c.flag))
    if c.low:
        terms.append(dict(kind="from", **version_view(c.low)))
    if c.high:
        terms.append(dict(kind="until", **version_view(c.high)))
    return dict(terms=terms)


# ---- the view model -----------------------------------------------------------------------

@dataclass
class Member:
    """One member of a C struct: `kind` names the template macro that declares it (scalar:
    `ctype name`, array: `ctype name[count]`, union: one alternative per scalar type)."""

    kind: str
    ctype: str
    name: str
    count: int = 0
    alternatives: list[dict] = field(default_factory=list)
    doc: str = ""
    above: list[str] = field(default_factory=list)   # a long doc, as comment lines above

    def place(self) -> "Member":
        """Short docs stay at the end of the line; long ones go above the member."""
        width = len(self.ctype) + len(self.name) + 8 * len(self.alternatives) + 6
        if width + len(self.doc) > 88:
            self.above, self.doc = comment(self.doc, width=88), ""
        return self


@dataclass
class BitSet:
    tag: str
    field: str
    members: list[dict]


# What a span holds (urwire__span: 8 bytes a field on a 32-bit CPU, 4 without names): an offset
# in a uint16_t, a size and an element's index in a uint8_t each, URWIRE__NO_INDEX (255) for none.
# A repeat row's size is URWIRE__REPEAT (0x80) | its number of elements: a field's size and that
# number stay below 0x80.
SPAN_OFFSET_MAX, NO_INDEX, SPAN_SIZE_MAX = 0xffff, 0xff, 0x7f


def name_text(path: str) -> str:
    """A field's path where an error names it: through URWIRE__NAME, which a build with
    URWIRE_NO_NAMES turns into "", so that a firmware links no field name."""
    return f"URWIRE__NAME({string(path)})"


# A path with one element's index, "joints[3].q_actual": every element's span shares the string
# "joints[].q_actual" and keeps its index apart.
ONE_INDEX = re.compile(r"^([^\[\]]*)\[(\d+)\]([^\[\]]*)$")


@dataclass
class Span:
    path: str
    offset: int
    size: int

    def __post_init__(self):
        if not (0 <= self.offset <= SPAN_OFFSET_MAX and 0 < self.size <= SPAN_SIZE_MAX):
            raise SpecError("<spec>", [ir.NOWHERE.problem(f"c target: field {self.path} at offset {self.offset} "
                                                          f"is beyond the C runtime's span tables")])

    @property
    def template(self) -> str:
        """The path as the span table holds it: an element's index left out ("joints[].q_actual")."""
        m = ONE_INDEX.match(self.path)
        return f"{m.group(1)}[]{m.group(3)}" if m and int(m.group(2)) < NO_INDEX else self.path

    @property
    def row(self) -> dict:
        """The span as a table row (Run.rows)."""
        return dict(path=self.template, path_c=string(self.template), offset=self.offset, size=self.size,
                    size_c=str(self.size), index=self.index, repeat=False)

    @property
    def index(self) -> int:
        """The element's index that goes into the template's "[]", else NO_INDEX."""
        m = ONE_INDEX.match(self.path)
        return int(m.group(2)) if m and int(m.group(2)) < NO_INDEX else NO_INDEX


@dataclass
class Run:
    """The span table of fixed runs (urwire__short_in_run names the field a short run stops in)."""

    table: str
    spans: list[Span]

    @property
    def rows(self) -> list[dict]:
        """The table's rows: each span, except that a group's elements after the first, when they
        repeat element 0's spans at one stride, are one repeat row {NULL, stride, URWIRE__REPEAT |
        elements, rows of element 0} after element 0's (joint data: 9 rows, not 48). `path_c` and
        `size_c` are the row's path and size as C spells them."""
        rows, i = [], 0
        while i < len(self.spans):
            width = 0
            while i + width < len(self.spans) and self.spans[i + width].index == 0:
                width += 1
            count, stride = _repeats(self.spans, i, width)
            block = self.spans[i:i + max(width, 1)]
            rows += [s.row for s in block]
            if count > 1:
                rows.append(dict(path=None, path_c="NULL", offset=stride, size=count,
                                 size_c=f"URWIRE__REPEAT | {count}", index=width, repeat=True))
            i += len(block) * count
        return rows


def _repeats(spans: list[Span], at: int, width: int) -> tuple[int, int]:
    """How many elements repeat the `width` spans of element 0 from `at` (index k, the same
    paths and sizes, offsets k strides on), and the stride: (1, 0) for none."""
    if width == 0 or at + width >= len(spans):
        return 1, 0
    stride, count = spans[at + width].offset - spans[at].offset, 1
    while (at + (count + 1) * width <= len(spans) and count < SPAN_SIZE_MAX and 0 < stride * count <= SPAN_OFFSET_MAX
           and all(_same_field(spans[at + j], spans[at + count * width + j], count, count * stride)
                   for j in range(width))):
        count += 1
    return (count, stride) if count > 1 else (1, 0)


def _same_field(first: Span, other: Span, index: int, shift: int) -> bool:
    return (other.template, other.size, other.index, other.offset) == (first.template, first.size, index,
                                                                       first.offset + shift)


@dataclass
class Decoder:
    """One decoder of a struct: the layout's, which tests its version conditions, or that of one
    form of a layout with several (urwire__decode_<name>_<k>), its version conditions resolved
    when generating (flag conditions stay; the fields the form lacks are zeroed)."""

    name: str             # urwire__decode_masterboard_data_2
    doc: str
    steps: list[Step]
    needs_p: bool
    index: bool
    can_fail: bool


@dataclass
class CStruct:
    name: str             # spec name (robot_mode_data, joint, version)
    ctype: str            # urwire_robot_mode_data
    doc: list[str]
    members: list[Member]
    role: str             # package | subtype | item
    runs: list[Run] = field(default_factory=list)
    decode: list[Step] = field(default_factory=list)
    decoders: list[Decoder] = field(default_factory=list)   # the layout's, or one per form
    encode: list[Step] = field(default_factory=list)
    visit: list[Step] = field(default_factory=list)
    fixed_item: bool = False        # laid out in its parent's fixed run: read/write/visit helpers
    item_members: list[dict] = field(default_factory=list)
    item_size: int = 0
    needs_p: bool = False
    encode_index: bool = False
    visit_index: bool = False
    item_index: bool = False
    bitsets: list = field(default_factory=list)
    to_end_item: bool = False       # items of a to_end group: public iteration function
    code: Optional[int] = None
    code_const: str = ""
    kind_const: str = ""            # subtypes: URWIRE_KIND_<NAME>; packages: URWIRE_LAYOUT_<NAME>

    def decoder(self, suffix: str, doc: str, steps: list[Step]) -> Decoder:
        name = f"urwire__decode_{self.name}{suffix}"
        return Decoder(name, doc, steps, needs_p(steps), uses_index(steps), can_fail(steps))

    def decoder_of(self, forms: list[plan.Variant], v: plan.Variant) -> str:
        """The decoder that reads the form v of this struct's layout (whose forms are `forms`)."""
        if len(self.decoders) == 1:
            return self.decoders[0].name
        return self.decoders[next(k for k, f in enumerate(forms) if f is v)].name


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.structs: list[CStruct] = []
        self.items: dict[int, CStruct] = {}
        self.problems: list[Problem] = []
        # The struct being built: its members by name (each name's widest entry), and the names
        # with several entries (in disjoint version ranges).
        self.public: dict[str, ir.AnyField] = {}
        self.repeated: list[str] = []

    # ---- one struct ----

    def build(self, layout: plan.LayoutPlan, name: str, ctype: str, role: str, doc: list[str],
              forms: Optional[list[plan.Variant]] = None) -> CStruct:
        struct = layout.struct
        for f in struct.fields:
            if isinstance(f, ir.GroupField) and id(f) not in self.items:
                item_plan = self.plan.item_of(f)
                self.items[id(f)] = self.build(item_plan.layout, f.item.name, f"urwire_{f.item.name}", "item",
                                               comment(f.doc) or [f"One entry of {f.name}."])
        cs = CStruct(name, ctype, doc, [], role)
        # One member per name: a name with entries in disjoint version ranges is one member of
        # the widest type (resolve.same_name: they differ in size only), each entry read, written
        # and visited under its own condition.
        self.public = {f.name: f for f in struct.public_fields}
        self.repeated = [n for n in self.public if len(struct.named(n)) > 1]
        for f in struct.public_fields:
            cs.members.append(self.member(f, name, struct).place())
            if isinstance(f, ir.ScalarField) and f.bits:
                prefix = f"URWIRE_{name.upper()}_{f.name.upper()}"
                cs.bitsets.append(BitSet(f"urwire_{name}_{f.name}_bit", f.name,
                                         [dict(const=f"{prefix}_{b.upper()}", bit=k) for k, b in enumerate(f.bits)]))
        if role != "item":
            cs.members.append(Member("scalar", "urwire_sw_version", "version",
                                     doc="The software version it was read in (its form's, when chosen by "
                                         "length): its encoding and visiting follow it.").place())
            cs.members.append(Member("scalar", "urwire_bytes", "extra",
                                     doc="Bytes after the known layout (flagged; kept for encoding)."))
        cs.decode, cs.encode = self.steps(cs, layout.steps)
        if self.repeated:
            cs.decode.insert(0, Step("absent", dict(zero=[self.zero(self.public[n]) for n in self.repeated])))
        cs.visit = self.visit_steps(struct)
        if len(forms or []) > 1:
            # One decoder per form: the form is chosen first, so no version is tested on the way.
            cs.runs = []
            cs.decoders = [self.form_decoder(cs, struct, v, k) for k, v in enumerate(forms)]
        else:
            cs.decoders = [cs.decoder("", inline(*doc), cs.decode)]
        fixed = role == "item" and struct.fixed_item
        if fixed:
            # Read and written inside its parent's checked run.
            cs.fixed_item = True
            cs.item_size = layout.fixed_size
            cs.item_members = [self.run_member(m) for m in layout.runs[0].members]
            cs.item_index = any(m["kind"] != "scalar" for m in cs.item_members)
        elif role == "item":
            cs.to_end_item = True
        cs.encode_index = uses_index(cs.encode)
        cs.visit_index = uses_index(cs.visit)
        cs.needs_p = needs_p(cs.decode)
        self.structs.append(cs)
        return cs

    def form_decoder(self, cs: CStruct, struct: ir.Struct, v: plan.Variant, k: int) -> Decoder:
        """The decoder of the form v of a layout (its k-th): v.plan, which has no version
        conditions; the members of the layout's other forms are zeroed first."""
        layout_repeated, self.repeated = self.repeated, []   # a form has one entry per name
        steps, _ = self.steps(cs, v.plan.steps, f"_{k}")
        self.repeated = layout_repeated
        absent = [self.zero(f) for f in struct.public_fields if not v.plan.struct.named(f.name)]
        if absent:
            steps.insert(0, Step("absent", dict(zero=absent)))
        sizes = " or ".join(map(str, sorted(v.sizes))) if v.sizes is not None else f"at least {v.min_size}"
        return cs.decoder(f"_{k}", f"{cs.name} as {v.describe()} sends it ({sizes} bytes).", steps)

    def item_of(self, f: ir.GroupField) -> CStruct:
        """The struct of a group's items (a form's copy of a group has the same items)."""
        return self.items.get(id(f)) or next(c for c in self.items.values() if c.name == f.item.name)

    def member(self, f: ir.AnyField, owner: str, struct: ir.Struct) -> Member:
        name = f.name
        if name in C_KEYWORDS:
            self.problems.append(f.where.problem(f"c target: field name '{name}' is a C keyword"))
        if name in RESERVED_MEMBERS:
            self.problems.append(f.where.problem(f"c target: field name '{name}' is a member every layout has"))
        entries = struct.named(name)
        doc = inline(field_text(entries, versions=len(entries) == 1))
        if f.present_if:
            doc = inline(doc, f"Present only when {f.present_if} is nonzero (else 0).")
        if len(entries) > 1:
            forms = "; ".join(f"{e.scalar.name} {e.versions.describe()}" for e in entries)
            doc = inline(doc, f"On the wire: {forms} (else 0).")
        if isinstance(f, ir.ScalarField):
            if f.scalar.is_bool:
                doc = inline(doc, "The wire byte: nonzero is true.")
            if f.enum is not None:
                doc = inline(doc, f"See enum urwire_{f.enum.name}.")
            if f.bits:
                doc = inline(doc, f"Masks: enum urwire_{owner}_{f.name}_bit.")
            return Member("scalar", C_TYPES[f.scalar.name], name, doc=doc)
        if isinstance(f, ir.ArrayField):
            return Member("array", C_TYPES[f.scalar.name], name, f.count, doc=doc)
        if isinstance(f, ir.GroupField):
            item = self.items[id(f)]
            if f.count is not None:
                return Member("array", item.ctype, name, f.count, doc=doc)
            return Member("scalar", "urwire_seq", name,
                          doc=inline(doc, f"Iterate with urwire_next_{item.name}() on a copy."))
        if isinstance(f, ir.StringField):
            return Member("scalar", "urwire_bytes", name,
                          doc=inline(doc, "UTF-8 text as sent, a view into the message."))
        if isinstance(f, ir.BytesField):
            return Member("scalar", "urwire_bytes", name, doc=doc)
        if isinstance(f, ir.StringListField):
            return Member("scalar", "urwire_seq", name, doc=inline(doc, "Iterate with urwire_next_text() on a copy."))
        if isinstance(f, ir.ValueListField):
            return Member("scalar", "urwire_seq", name, doc=inline(doc, "Iterate with urwire_next_value() on a copy."))
        assert isinstance(f, ir.SwitchField)
        cases = "; ".join(f"{k}: .{s.name}" for k, s in f.cases.items())
        scalars = sorted({s.name for s in list(f.cases.values()) + [f.default]}, key=list(C_TYPES).index)
        return Member("union", "union", name, alternatives=[dict(ctype=C_TYPES[s], name=s) for s in scalars],
                      doc=inline(doc, f"Chosen by {f.selector.name}: {cases}; otherwise .{f.default.name}."))

    # ---- fixed runs: one entry per member ----

    def run_member(self, m: plan.Member) -> dict:
        """What the template needs to read or write one member of a fixed run at p + offset:
        a scalar, an array of scalars (count, stride) or fixed-size items (read by their
        own helper). A repeated name whose member is wider than this entry is cast."""
        f = m.field
        if isinstance(f, ir.ScalarField):
            member = C_TYPES[self.public[f.name].scalar.name] if f.name in self.public else C_TYPES[f.scalar.name]
            wire = C_TYPES[f.scalar.name]
            cast = wire != member
            return dict(kind="scalar", name=f.name, offset=m.offset, reader=READERS[f.scalar.name],
                        writer=WRITERS[f.scalar.name], into=member if cast else "", out=wire if cast else "")
        if isinstance(f, ir.ArrayField):
            return dict(kind="array", name=f.name, offset=m.offset, count=f.count, stride=f.scalar.size,
                        reader=READERS[f.scalar.name], writer=WRITERS[f.scalar.name])
        return dict(kind="items", name=f.name, offset=m.offset, count=f.count, stride=m.item.layout.fixed_size,
                    item=f.item.name)

    def run_table(self, cs: CStruct, spans: list[Span], name: str) -> str:
        """The span table of a run. A table whose first spans are the run's serves it too (the
        forms of a layout often only add fields at the end): the first field that does not fit
        always lies within the run."""
        for r in cs.runs:
            if r.spans[:len(spans)] == spans:
                return r.table
            if spans[:len(r.spans)] == r.spans:
                r.spans = spans
                return r.table
        cs.runs.append(Run(name, spans))
        return name

    def run_steps(self, cs: CStruct, run: plan.FixedRun, suffix: str) -> tuple[Step, Step]:
        table = self.run_table(cs, [Span(leaf.path, leaf.offset, leaf.scalar.size) for leaf in run.leaves],
                               f"urwire__{cs.name}{suffix}_run{run.index}")
        members = [self.run_member(m) for m in run.members]
        loops = any(m["kind"] != "scalar" for m in members)
        return (Step("run", dict(table=table, size=run.size, loops=loops, members=members)),
                Step("run", dict(size=run.size, loops=loops, members=members)))

    def zero(self, f: ir.AnyField) -> dict:
        """How an absent field is cleared: a scalar is set to 0, anything else memset."""
        return dict(kind="scalar" if isinstance(f, ir.ScalarField) else "whole", name=f.name)

    # ---- decode and encode steps ----

    def steps(self, cs: CStruct, steps: list[plan.Step], suffix: str = "") -> tuple[list[Step], list[Step]]:
        """The decode and encode steps of a plan; `suffix` names the run tables of a form's decoder."""
        dec: list[Step] = []
        enc: list[Step] = []
        for step in steps:
            if isinstance(step, plan.FixedRun):
                d, e = self.run_steps(cs, step, suffix)
            elif isinstance(step, plan.CondGroup):
                inner_d, inner_e = self.steps(cs, step.steps, suffix)
                # A name with entries under other conditions is cleared up front instead, so
                # that this branch never clears what another entry of the name read.
                zero = [self.zero(g) for g in step.fields if g.name not in self.repeated]
                test = condition_view(step.condition)
                d = Step("cond", dict(test=test, steps=inner_d, zero=zero))
                e = Step("cond", dict(test=test, steps=inner_e))
            else:
                d, e = self.dynamic(cs, step.field, step.path)
            dec.append(d)
            enc.append(e)
        return dec, enc

    def dynamic(self, cs: CStruct, f: ir.AnyField, path: str) -> tuple[Step, Step]:
        if isinstance(f, ir.StringField) and f.length is not None:
            s = f.length
            data = dict(name=f.name, path=name_text(path), size=s.size, max=s.max, signed=s.signed)
            return Step("prefixed_text", data), Step("prefixed_text", data)
        if isinstance(f, (ir.StringField, ir.BytesField)):
            return Step("rest", dict(name=f.name)), Step("bytes", dict(name=f.name))
        if isinstance(f, ir.StringListField):
            return (Step("texts", dict(name=f.name, terminator=f.terminator)),
                    Step("seq", dict(name=f.name)))
        if isinstance(f, ir.ValueListField):
            return (Step("values", dict(name=f.name, terminator=f.terminator, path=name_text(path))),
                    Step("seq", dict(name=f.name)))
        if isinstance(f, ir.SwitchField):
            cases = [dict(value=k, size=s.size, reader=READERS[s.name], writer=WRITERS[s.name], member=s.name)
                     for k, s in f.cases.items()]
            d = f.default
            data = dict(name=f.name, selector=f.selector.name, path=name_text(path), cases=cases,
                        default=dict(size=d.size, reader=READERS[d.name], writer=WRITERS[d.name], member=d.name))
            return Step("switch", data), Step("switch", data)
        assert isinstance(f, ir.GroupField)
        item = self.item_of(f)
        return (Step("group_to_end", dict(name=f.name, path=name_text(f.name), item=item.name, ctype=item.ctype)),
                Step("seq", dict(name=f.name)))

    # ---- visiting (the canonical JSON order: one entry per name, in first-seen order) ----

    def visit_steps(self, struct: ir.Struct) -> list[Step]:
        out: list[Step] = []
        for f in struct.public_fields:
            entries = struct.named(f.name)
            # When any entry of the name is on the wire; an unconditional entry: always.
            conds = [] if any(not e.conditional for e in entries) else \
                [condition_view(plan.condition_of(e)) for e in entries]
            out.append(self.visit_one(f, conds))
        return out

    def visit_one(self, f: ir.AnyField, when: list[dict]) -> Step:
        if isinstance(f, ir.ScalarField):
            return Step("scalar", dict(name=f.name, cb=VISIT[f.scalar.name], when=when))
        if isinstance(f, ir.ArrayField):
            return Step("array", dict(name=f.name, cb=VISIT[f.scalar.name], count=f.count, when=when))
        if isinstance(f, ir.GroupField):
            item = self.items[id(f)]
            if f.count is not None:
                return Step("group", dict(name=f.name, item=item.name, count=f.count, when=when))
            return Step("group_to_end", dict(name=f.name, path=name_text(f.name), item=item.name, ctype=item.ctype,
                                             when=when))
        if isinstance(f, ir.StringField):
            return Step("text", dict(name=f.name, when=when))
        if isinstance(f, ir.BytesField):
            return Step("hex", dict(name=f.name, when=when))
        if isinstance(f, ir.StringListField):
            return Step("texts", dict(name=f.name, when=when))
        if isinstance(f, ir.ValueListField):
            return Step("values", dict(name=f.name, when=when))
        assert isinstance(f, ir.SwitchField)
        cases = [dict(value=k, cb=VISIT[s.name], member=s.name) for k, s in f.cases.items()]
        d = f.default
        return Step("switch", dict(name=f.name, selector=f.selector.name, cases=cases, when=when,
                                   default=dict(cb=VISIT[d.name], member=d.name)))


def needs_p(steps: list[Step]) -> bool:
    """A fixed run or a switch reads through p."""
    return any(s.kind in ("run", "switch") or (s.kind == "cond" and needs_p(s.steps)) for s in steps)


def can_fail(steps: list[Step]) -> bool:
    """False when every step of a decoder always succeeds (rest-of-message views only)."""
    return any(s.kind not in ("rest", "texts", "cond", "absent") or (s.kind == "cond" and can_fail(s.steps))
               for s in steps)


def uses_index(steps: list[Step]) -> bool:
    """True when a step loops on i (the template then declares it)."""
    for s in steps:
        if s.kind in ("array", "group") or (s.kind == "run" and s.loops):
            return True
        if s.kind == "cond" and uses_index(s.steps):
            return True
    return False


# ---- enums ----------------------------------------------------------------------------------

def enum_views(p: model.Protocol) -> list[dict]:
    views = []
    for e in p.enums.values():
        tables = []
        for t in e.tables:
            prefix = c_enum_prefix(e, t)
            members = []
            for v in t.values:
                m = Member("scalar", prefix, v.name,
                           doc=inline(value_text(v))).place()
                members.append(dict(const=f"{prefix}_{v.name}", value=v.value, name=v.name, doc=m.doc, above=m.above))
            # Name lookup: one case per distinct value (the first name wins, as in Python).
            seen, cases = set(), []
            for m in members:
                if m["value"] not in seen:
                    seen.add(m["value"])
                    cases.append(m)
            tables.append(dict(versions=t.versions.describe(), members=members, cases=cases, range=range_view(t.versions),
                               tag=c_enum_tag(e, t),
                               names=f"urwire__{e.name}_{c_table_suffix(t).lower()}_name" if e.versioned else ""))
        # Every table's names in one pool of the enum's own, so that a firmware that never names
        # this enum links none of its texts (literals of a file share one section, kept whole).
        pool = Pool(c["name"] for t in tables for c in t["cases"])
        for t in tables:
            for c in t["cases"]:
                c["at"] = pool.offset(c["name"])
        views.append(dict(name=e.name, doc=comment(node_text(e)), wire=C_TYPES[e.scalar.name],
                          versioned=e.versioned, tables=tables, first=tables[-1]["members"][0]["name"],
                          pool=pool.parts))
    return views


def value_views(p: model.Protocol) -> dict:
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
        tables.append(dict(tag=f"urwire__values_{c_table_suffix(t).lower()}", versions=t.versions.describe(),
                           entries=entries, range=range_view(t.versions), min_size=p.value_min_size(t)))
    if problems:
        raise SpecError(p.source, problems)
    arrays = [lay.count for lay in p.value_layouts.values() if lay.layout == "array"]
    return dict(kinds=[dict(const=f"URWIRE_VALUE_{k}", name=k, doc=inline(p.value_layouts[k].doc)) for k in kinds],
                tables=tables, array_max=max(arrays) if arrays else 1, max_depth=p.max_value_depth)


# ---- forms: which layout a type code is read in ---------------------------------------------

# A segment's row marks a form that is the nearest below's (none is sent there) with this bit.
NEAREST_BIT = 0x80
# A form in brief (urwire__package_first_sizes): its first exact size, its least size when it is
# open-ended, or none.
BRIEF = {"exact": "{size}u", "open": "URWIRE__OPEN({size}u)", "none": "URWIRE__NONE"}


def cell_lines(cells: list[str], width: int = 112) -> list[str]:
    """The cells of one row of a C table, ", "-joined and wrapped into lines of at most `width`."""
    lines, line = [], ""
    for text in (c + "," for c in cells):
        if line and len(line) + 1 + len(text) > width:
            lines.append(line)
            line = ""
        line = f"{line} {text}" if line else text
    return lines + [line] if line else lines


class _Forms:
    """The plan's segments of the version axis (within one, every type code sends one form) as C
    tables: a version's form is one lookup (urwire__segment, then the segment's row)."""

    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.source = protocol_plan.protocol.source
        self.segments = protocol_plan.segments
        self.size_slots = max([len(v.sizes or ()) for mp in protocol_plan.messages for vs in mp.variants.values()
                               for v in vs] + [1])

    def bounds(self) -> list[dict]:
        """Where each segment starts, with the versions it holds: the first from key 0."""
        return [dict(kind="version", first=version_view(s.first), versions=s.describe()) if s.first else
                dict(kind="lowest", versions=s.describe()) for s in self.segments]

    def table(self, tag: str, what: str, mp: plan.MessagePlan, enum: ir.Enum, layouts: dict[int, str],
              first_sizes: bool = False, body: bool = False) -> dict:
        """The forms of every code of one type byte (the sub-package types, or a message's
        subtypes), in one list; the forms of each code; and, segment by segment, the form each
        code takes there (its number in the list plus one, 0 for none, NEAREST_BIT when it is the
        nearest below's). A body message's one code (its own type) is row 0 of its table, which
        the runtime reads it at: indexed by the type, each row would hold 22 to 24 unused bytes."""
        base = min(mp.variants) if body else 0
        codes, count, recognised = [], 0, 0
        for code, variants in mp.variants.items():
            forms = []
            for v in variants:
                sizes = sorted(v.sizes) if v.sizes is not None else []
                forms.append(dict(layout=layouts[id(v.layout)], nsizes=len(sizes),
                                  sizes=sizes + [0] * (self.size_slots - len(sizes)), min_size=v.min_size,
                                  rep=version_view(v.rep), versions=v.describe()))
            codes.append(dict(code=code, row=code - base, index="0" if body else c_enum_const(enum, code),
                              first=count, count=len(forms), forms=forms,
                              names=", ".join(c.layout.name for c in mp.choices[code]),
                              layouts=[dict(name=c.layout.name, const=layouts[id(c.layout)])
                                       for c in mp.choices[code]],
                              by_length_cells=cell_lines([f"{{{size}u, {k}}}" for size, k in mp.by_length[code].items()]),
                              by_length_first=recognised, by_length_count=len(mp.by_length[code])))
            count += len(forms)
            recognised += len(mp.by_length[code])
        if count >= NEAREST_BIT:
            raise SpecError(self.source, [mp.message.where.problem(
                "c target: more than 127 forms of one type byte do not fit the form tables")])
        ncodes = max(mp.variants) - base + 1
        rows = []
        for k, segment in enumerate(self.segments):
            row = [0] * ncodes
            first = [dict(kind="none")] * ncodes
            for c in codes:
                sf = mp.by_segment[c["code"]][k]
                row[c["row"]] = (c["first"] + sf.form + 1) | (NEAREST_BIT if sf.nearest else 0)
                if not sf.nearest:
                    f = c["forms"][sf.form]
                    first[c["row"]] = dict(kind="exact", size=f["sizes"][0]) if f["nsizes"] else \
                        dict(kind="open", size=f["min_size"])
            rows.append(dict(forms=row, first=first, versions=segment.describe(),
                             cells=cell_lines(["0x%02x" % n for n in row]),
                             first_cells=cell_lines([BRIEF[n["kind"]].format(size=n.get("size")) for n in first])))
        return dict(tag=tag, what=what, codes=codes, ncodes=ncodes, rows=rows, first_sizes=first_sizes)


def one_form(table: dict) -> bool:
    """Whether every code of a form table has one form, which every segment reads (sent there,
    or the nearest below's): the form of a code is then that one whatever the version and the
    size, and only the nearest mark is left to look up (a pinned build)."""
    return all(c["count"] == 1 and all(row["forms"][c["row"]] & ~NEAREST_BIT == c["first"] + 1 for row in table["rows"])
               for c in table["codes"])


def kind_names(messages: list[dict], packages: list) -> Pool:
    """The names of urwire__message_kinds and urwire__package_kinds in a pool of their own, which
    only those tables read: as literals they would share the file's one literal section, which
    the decoder's run tables keep whole, and be linked by a firmware that only decodes."""
    names = ["unknown"]
    for m in messages:
        names += [m["name"]] if m["kind"] == "packages" else [s.name for s in m["subtypes"]]
    return Pool(names + [s.name for s in packages])


# ---- messages -------------------------------------------------------------------------------

def build(protocol_plan: plan.ProtocolPlan) -> dict:
    b = _Builder(protocol_plan)
    p = protocol_plan.protocol
    axis = _Forms(protocol_plan)
    messages = []
    kinds = []
    packages: list[CStruct] = []
    package_forms: dict = {}
    package_decoders: list[dict] = []
    package_fast: dict = dict(paths=[], of_segment=[], default_segment=0)
    layout_structs: dict[int, CStruct] = {}
    for mp in protocol_plan.messages:
        m = mp.message
        if not mp.is_dispatch:
            for c in mp.layouts:
                pk = c.layout
                if pk.code.value >= MASK_BITS:
                    b.problems.append(pk.where.problem("c target: package codes above 31 do not fit the present bit mask"))
                cs = b.build(c.plan, pk.name, f"urwire_{pk.name}", "package", comment(node_text(pk)),
                             mp.forms_of(pk))
                cs.code = pk.code.value
                cs.code_const = c_member_const(m.package_type, pk.code)
                cs.kind_const = f"URWIRE_LAYOUT_{pk.name.upper()}"
                layout_structs[id(pk)] = cs
                packages.append(cs)
            if len(packages) > MASK_BITS:
                b.problems.append(m.where.problem("c target: more than 32 sub-package layouts do not fit the "
                                                  "layouts bit mask"))
            package_forms = axis.table("urwire__package", "sub-package type", mp, m.package_type,
                                       {id(c.layout): layout_structs[id(c.layout)].kind_const for c in mp.layouts},
                                       first_sizes=True)
            package_decoders = decoder_views(mp, package_forms, layout_structs)
            package_fast = fast_paths(axis, package_forms, package_decoders, p.default_version)
            kinds.append(dict(const=f"URWIRE_KIND_{m.name.upper()}", doc=inline(m.doc)))
            messages.append(dict(kind="packages", name=m.name, code=m.code.value, type_index=len(messages),
                                 code_const=c_member_const(p.message_type_enum, m.code),
                                 kind_const=f"URWIRE_KIND_{m.name.upper()}", doc=comment(node_text(m))))
            continue
        header = [dict(name=slot.field.name, ctype=C_TYPES[slot.field.scalar.name],
                       reader=READERS[slot.field.scalar.name], writer=WRITERS[slot.field.scalar.name],
                       offset=slot.offset, cb=VISIT[slot.field.scalar.name],
                       doc=inline(field_text([slot.field])), subtype=slot.is_subtype)
                  for slot in mp.header]
        subtypes = []
        for c in mp.layouts:
            st = c.layout
            cs = b.build(c.plan, st.name, f"urwire_{st.name}_message", "subtype", comment(node_text(st)))
            cs.code = st.code.value
            cs.code_const = c_member_const(m.subtype_enum, st.code)
            cs.kind_const = f"URWIRE_KIND_{st.name.upper()}"
            layout_structs[id(st)] = cs
            subtypes.append(cs)
            kinds.append(dict(const=cs.kind_const, doc=inline(st.doc)))
        forms = axis.table(f"urwire__{m.name}", f"{m.name} subtype" if m.has_subtype else f"{m.name} message",
                           mp, m.subtype_enum,
                           {id(c.layout): layout_structs[id(c.layout)].kind_const for c in mp.layouts},
                           body=not m.has_subtype)
        messages.append(dict(kind="dispatch" if m.has_subtype else "body", name=m.name, code=m.code.value,
                             type_index=len(messages),
                             code_const=c_member_const(p.message_type_enum, m.code),
                             doc=comment(node_text(m)), header=header, header_table=f"urwire__{m.name}_header",
                             header_spans=[Span(slot.field.name, slot.offset, slot.field.scalar.size)
                                           for slot in mp.header],
                             body_offset=mp.body_offset, subtypes=subtypes,
                             subtype_name=m.subtype.name if m.has_subtype else None,
                             forms=forms))
    lists = [m for m in messages if m["kind"] == "packages"]
    if len(lists) != 1:
        b.problems.append(protocol_plan.protocol.messages[0].where.problem(
            "c target: the C runtime expects exactly one message that is a list of sub-packages"))
    if b.problems:
        raise SpecError(protocol_plan.protocol.source, b.problems)
    vs = protocol_plan.version
    vst = layout_structs[id(vs.layout)]
    vmsg = next(m for m in messages if m["code"] == vs.message_code)
    buffers = framer_buffers(protocol_plan)
    kind_text = kind_names(messages, packages)
    tables = [package_forms] + [m["forms"] for m in messages if m["kind"] != "packages"]
    return dict(buffers=buffers, structs=b.structs, messages=messages, kinds=kinds, packages=packages, package_forms=package_forms,
                one_form=all(map(one_form, tables)),
                kind_text=kind_text.parts, kind_at=kind_text.offsets,
                package_decoders=package_decoders, package_fast=package_fast,
                segment_bounds=axis.bounds(), form_sizes=axis.size_slots,
                framing=framing(p, lists[0], vst, vmsg, vs), known_types=known_types(p))


def framer_buffers(protocol_plan: plan.ProtocolPlan) -> dict:
    """The longest robot state any version sends, by the spec's layouts, and the framer buffer
    the spec gives for what real robots send (protocol.robot_buffer), which must hold it."""
    p = protocol_plan.protocol
    (mp,) = [mp for mp in protocol_plan.messages if not mp.is_dispatch]
    header, package_header = p.message_length.scalar.size + 1, p.package_length.scalar.size + 1
    largest = header + sum(package_header + max(max(v.sizes) if v.sizes else v.min_size for v in variants)
                           for variants in mp.variants.values())
    if p.robot_buffer is not None and p.robot_buffer < largest:
        raise SpecError(p.source, [ir.NOWHERE.problem(
            f"protocol.robot_buffer: {p.robot_buffer} bytes cannot hold the longest robot state, {largest} bytes")])
    return dict(largest_state=largest, robot=p.robot_buffer)


# urwire__package_fast_paths holds each segment's fast path in a uint8_t.
MAX_FAST_PATHS = 255


def fast_paths(axis: _Forms, table: dict, decoders: list[dict], default: ir.Version) -> dict:
    """The robot-state loops, each written out for one row of forms (the form every sub-package
    type sends in a segment of the version axis). The rule: every row that a segment at or after
    the default version's sends gets a loop, the default's row first (every stream read before
    its Version message takes it), the others in the order of the versions. A newer version cuts
    the axis only at and after its own first version: every older version keeps its row, and so
    its loop (its number may change; docs/c.md says what a loop costs). A segment whose every
    form is the nearest below's (between two series) is no version's and gets none. Every
    segment that sends a row with a loop takes it; the others (versions below the default, with
    rows of their own) take the general rule (urwire__decode_general). In such a loop each
    sub-package type is a case that checks the body against one constant size and calls one
    decoder; any other body is left to the general rule."""
    rows = table["rows"]
    default_segment = axis.plan.segment_of(default)
    if default_segment == len(rows) - 1:
        # urwire__segment tries the default's segment first, up to the bound after it.
        raise SpecError(axis.source, [ir.NOWHERE.problem("c target: the default version lies past every form's "
                                                         "versions")])
    paths: list[dict] = []
    by_number = {x["number"]: (c, x) for c in decoders for x in c["forms"]}
    for row in rows[default_segment:]:
        if all(n["kind"] == "none" for n in row["first"]) or any(p["forms"] == row["forms"] for p in paths):
            continue
        cases = []
        for form, first in zip(row["forms"], row["first"]):
            if form == 0 or form & NEAREST_BIT or first["kind"] == "none":
                continue  # no form of its own there: the general rule finds the nearest
            c, x = by_number[form]
            cases.append(dict(type=c["index"], layout=x["layout"], decoder=x["decoder"], member=x["member"],
                              check="any" if first["kind"] == "open" and first["size"] == 0 else first["kind"],
                              size=first["size"], versions=x["versions"]))
        paths.append(dict(number=len(paths) + 1, forms=row["forms"], cases=cases,
                          segments=", ".join(r["versions"] for r in rows if r["forms"] == row["forms"])))
    if len(paths) > MAX_FAST_PATHS:
        raise SpecError(axis.source, [ir.NOWHERE.problem(f"c target: more than {MAX_FAST_PATHS} rows of robot-state "
                                                         "forms from the default version on")])
    of_segment = [next((p["number"] for p in paths if p["forms"] == r["forms"]), 0) for r in rows]
    return dict(paths=paths, of_segment=of_segment, default_segment=default_segment)


def fast_path_change(protocol_plan: plan.ProtocolPlan, a: ir.Version, b: ir.Version) -> str:
    """What `make spec-diff` says of the C robot-state fast paths: whether software `a` and `b`
    take the same loop (the same row of forms), and which."""
    fast = build(protocol_plan)["package_fast"]

    def taken(v: ir.Version) -> str:
        number = fast["of_segment"][protocol_plan.segment_of(v)]
        return f"loop {number} ({fast['paths'][number - 1]['segments']})" if number else "none (the general rule)"

    x, y = taken(a), taken(b)
    return f"C robot-state fast path: {'the same, ' + x if x == y else x + ' -> ' + y}"


def decoder_views(mp: plan.MessagePlan, table: dict, structs: dict[int, CStruct]) -> list[dict]:
    """Per sub-package code, the decoder of each of its forms, by the form's number in the form
    list plus one: what urwire__decode_member and urwire__decode_package switch on. A code whose
    forms all read through one decoder needs no switch on the form."""
    codes = []
    for c, variants in zip(table["codes"], mp.variants.values()):
        forms = []
        for n, v in enumerate(variants):
            cs = structs[id(v.layout)]
            forms.append(dict(number=c["first"] + n + 1, versions=v.describe(), layout=cs.kind_const, member=cs.name,
                              decoder=cs.decoder_of(mp.forms_of(v.layout), v)))
        one = len({f["decoder"] for f in forms}) == 1
        codes.append(dict(index=c["index"], kind="one" if one else "forms", forms=forms))
    return codes


def framing(p: model.Protocol, packages: dict, vst: CStruct, vmsg: dict, vs: plan.VersionSource) -> dict:
    """What the runtime reads of the spec's framing through private macros: where the header
    fields are, which message is the sub-package list, which layout announces the version and
    how to reach its numbers before its layout is chosen."""
    problems = [h.where.problem("c target: a message or sub-package type wider than one byte")
                for h in (p.message_type, p.package_type) if h.scalar.size != 1]
    if vs.major.scalar.size != 1 or vs.minor.scalar.size != 1:
        problems.append(vs.layout.where.problem("c target: the version numbers must be single bytes"))
    if problems:
        raise SpecError(p.source, problems)
    ml, pl = p.message_length.scalar, p.package_length.scalar
    (subtype,) = [h for h in vmsg["header"] if h["subtype"]]
    # An empty C array is not C99: a list with no skips is one skip of nothing.
    skips = [dict(fixed=k.fixed, prefix=k.prefix, signed=k.signed) for k in vs.skips] or \
        [dict(fixed=0, prefix=0, signed=False)]
    return dict(length=dict(reader=READERS[ml.name], writer=WRITERS[ml.name], ctype=C_TYPES[ml.name],
                            scalar=ml.name, size=ml.size),
                package_length=dict(reader=READERS[pl.name], writer=WRITERS[pl.name], ctype=C_TYPES[pl.name],
                                    scalar=pl.name, size=pl.size),
                packages=dict(name=packages["name"], code_const=packages["code_const"],
                              kind_const=packages["kind_const"]),
                version=dict(name=vst.name, ctype=vst.ctype, type_const=vmsg["code_const"], subtype_at=subtype["offset"],
                             subtype_const=vst.code_const, body=vmsg["body_offset"], kind_const=vst.kind_const,
                             major=vs.major.name, minor=vs.minor.name, bugfix=vs.bugfix.name if vs.bugfix else None,
                             skips=skips, tail=vs.tail))


@dataclass
class KnownTypes:
    """The message types a plausible header may carry (the framer resynchronises on the others):
    their names, and a bit each in 32 bytes (type >> 3, bit type & 7), rows of 16 bytes."""
    names: list[str]
    rows: list[str]


def known_types(p: model.Protocol) -> KnownTypes:
    codes = sorted({v.value for v in p.message_type_enum.values})
    bits = [0] * 32
    for code in codes:
        bits[code >> 3] |= 1 << (code & 7)
    rows = [", ".join(f"0x{b:02x}" for b in bits[k:k + 16]) + "," for k in range(0, 32, 16)]
    return KnownTypes([c_enum_const(p.message_type_enum, code) for code in codes], rows)


# The hand-written runtime (runtime/c/), in the order each part is joined to the
# generated ones: public headers around the spec's types, then private code before the layouts
# and, after them, the code that walks their tables.
RUNTIME = {
    "types": ("packages/version.h", "packages/views.h", "packages/errors.h"),
    "value": ("packages/value.h",),
    "api": ("packages/messages.h", "packages/visitor.h", "packages/framer.h"),
    "base": ("common/macros.h", "common/buffer.h", "common/held.h", "common/version_text.h", "packages/private.h",
             "common/loads.h", "common/buffer.c", "common/held.c", "common/version_text.c", "packages/views.c",
             "packages/version.c", "packages/format.c", "packages/errors.c", "packages/text.c", "packages/put.c"),
    "walkers": ("packages/values.c", "packages/kinds.c", "packages/forms.c", "packages/decode.c",
                "packages/encode.c", "packages/visit.c", "packages/framer.c"),
}


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment(FOLDER)
    runtime = {part: "\n\n".join(runtime_section(FOLDER, name) for name in names) for part, names in RUNTIME.items()}
    ctx = dict(banner=banner, p=p, enums=enum_views(p), values=value_views(p), runtime=runtime,
               default_version=version_view(p.default_version), default_text=ir.version_text(p.default_version),
               bugfix_any=ir.BUGFIX_ANY,
               documented=", ".join(ir.version_text(v) for v in p.documented_versions),
               title=p.title, doc=comment(p.doc), **build(protocol_plan))
    return {f"{FOLDER}/urwire.h": env.get_template("packages/urwire.h.j2").render(**ctx),
            f"{FOLDER}/urwire.c": env.get_template("packages/urwire.c.j2").render(**ctx)}
