"""Python target: the IR -> a view model of decode/encode steps -> templates/python/packages/*.py.j2 ->
the subpackage urwire.generated (generated/python/urwire/generated/): classes, forms and tables
that the hand-written package python/urwire/ imports and walks.

Every decision (struct formats, offsets, expressions, paths) is made here; the templates
only lay the strings out. Fixed runs of fields become one precompiled struct.Struct.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from ... import ir
from ...emit import environment
from ...lang.python import string as py_string, string_or_none as py_string_or_none
from ...errors import Problem, SpecError
from ...comments import field_text, node_text, value_text
from ...view import Step, one_line
from ...naming import words
from . import model, plan
from .naming import (layout_label, py_enum_class, py_item_class, py_layout_class, py_lookup, py_message_class,
                     py_table_class)

# The generated subpackage urwire.generated; the hand-written package is python/urwire/.
PACKAGE = "python/urwire/generated"
STRUCT_CODES = {"bool": "B", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i",
                "uint32": "I", "int64": "q", "uint64": "Q", "float32": "f", "float64": "d"}
RESERVED_LOCALS = {"buf", "pos", "end", "version", "v", "cls", "self", "out", "item", "fmt", "exc", "header"}


@dataclass
class Attr:
    name: str
    annotation: str
    doc: str
    json_kind: str
    optional: bool = False
    metadata: str = "{}"        # dataclasses.field(metadata=...): its label and unit, as Python text


def attr(f: ir.AnyField, annotation: str, optional: bool = False, entries: tuple = ()) -> Attr:
    """An attribute: its docstring starts with the field's label and unit, and its metadata
    holds them for code that shows records to people (human.py, a GUI), and tables (export.py)."""
    unit = py_string_or_none(f.unit)
    metadata = (f'{{"label": {py_string(f.label)}, "unit": {unit}{_wide_wire(f)}'
                f'{_fixed_count(f)}}}')
    return Attr(f.name, annotation, one_line(field_text(entries or [f])), ir.json_kind(f), optional, metadata)


def _wide_wire(f: ir.AnyField) -> str:
    """`"wire": "uint64"` for unsigned 64-bit values: the one integer type whose values pass
    int64's range, so that a typed column (a Parquet table) can be chosen before any value is seen."""
    scalar = getattr(f, "scalar", None)
    return ', "wire": "uint64"' if scalar is not None and scalar.name == "uint64" else ""


def _fixed_count(f: ir.AnyField) -> str:
    """`"count": N` for a list or group of a fixed number of items in every layout, so that a
    table can give each item a column of its own before any record is seen (dataset.py)."""
    count = getattr(f, "count", None) if isinstance(f, (ir.ArrayField, ir.GroupField)) else None
    return f', "count": {count}' if count is not None else ""


@dataclass
class MemberView:
    """One member of a fixed run, as the templates write its decode and encode expressions."""

    name: str
    kind: str            # scalar | array | group
    conv: str            # scalar and array items: plain | enum | bool | f32
    lookup: str = ""     # enum: the module constant mapping wire values to members
    first: str = "0"     # index of its first value in the unpacked tuple
    last: str = "1"      # arrays: index after its last value
    at: str = "pos"      # its byte offset in buf (float32 NaNs are re-read from there)
    count: int = 1       # groups: items
    item: str = ""       # groups: the item class
    width: int = 0       # groups: values per item
    size: int = 0        # groups: bytes per item
    enums: list = field(default_factory=list)   # groups: the versioned enums its items look up


@dataclass
class RunMember:
    """One member of a fixed run as data, for readers other than the generated decoder (the C
    extension's records: RUN_RECIPES in messages.py). Its values are those struct unpacks."""

    name: str
    kind: str            # scalar | array | group
    conv: str            # plain | bool | f32 | enum | venum | item_enum
    lookup: str = "None"  # enum, venum: the table (an expression); item_enum: its index among the item's
    first: int = 0       # index of its first value in the run's (or the item's) unpacked values
    count: int = 1       # arrays: values; groups: items
    item: str = "None"   # groups: the item class
    width: int = 0       # groups: values per item
    size: int = 0        # groups: bytes per item
    enums: list = field(default_factory=list)   # groups: the versioned tables its items look up


@dataclass
class StructConst:
    name: str
    fmt: str
    run: list                     # (path, offset in run, size)
    out_fmt: Optional[str] = None  # encoding format when it differs (float32 packed as bits)


@dataclass
class Codec:
    """The decoder and encoder of one form of a layout (`suffix` names the pair: _decode_1)."""

    suffix: str
    decode: list[Step]
    encode: list[Step]
    versions: str = ""            # the versions that send the form, when a layout has several
    runs: Optional[dict] = None   # a form read by fixed runs alone (fixed_runs), as data


@dataclass
class PyClass:
    name: str
    doc: str
    role: str                      # package | subtype | item
    label: str                     # what people call it: "Robot mode data", "Joint"
    json_type: str
    code: Optional[int]
    attrs: list[Attr]
    header_names: list[str]
    codecs: list["Codec"]          # one decoder and encoder per form (one for most layouts)
    structs: list[StructConst]
    fixed: bool = False            # item laid out in its parent's run
    members: list[MemberView] = field(default_factory=list)  # fixed items: read from the parent's run
    run_members: list[RunMember] = field(default_factory=list)  # fixed items: the same, as data
    sets_version: Optional[tuple[str, str]] = None
    summary: list[str] = field(default_factory=list)
    items: dict[str, str] = field(default_factory=dict)   # group member -> its item class
    encoder_by_segment: str = ""   # several forms: the index of the encoder of each segment

    @property
    def base(self) -> str:
        return {"package": "_kinds.Package", "subtype": "_kinds.Subtype", "item": "_kinds.Item"}[self.role]

    @property
    def field_names(self) -> list[str]:
        return [a.name for a in self.attrs if a.name not in self.header_names]


def annotation(f: ir.AnyField, items: dict[str, str]) -> str:
    if isinstance(f, ir.ScalarField):
        base = scalar_annotation(f.scalar, f.enum)
    elif isinstance(f, ir.ArrayField):
        base = f"list[{scalar_annotation(f.scalar, f.enum)}]"
    elif isinstance(f, ir.GroupField):
        base = f"list[{items[f.name]}]"
    elif isinstance(f, ir.StringField):
        base = "str"
    elif isinstance(f, ir.StringListField):
        base = "list[str]"
    elif isinstance(f, ir.BytesField):
        base = "bytes"
    elif isinstance(f, ir.SwitchField):
        base = "Union[int, float]"
    else:
        base = "list[GlobalValue]"
    return f"Optional[{base}]" if f.conditional else base


def scalar_annotation(s: ir.Scalar, enum: Optional[ir.Enum]) -> str:
    if enum is not None:
        return f"Union[{', '.join(enum_classes(enum))}, int]"
    return "bool" if s.is_bool else "float" if s.is_float else "int"


def enum_classes(enum: ir.Enum) -> list[str]:
    """The classes of an enum's tables, newest first: what an attribute that holds it is annotated
    with, and what messages.py imports from enums.py by name."""
    return [py_table_class(enum, t) for t in reversed(enum.tables)]


def annotated_enum(f: ir.AnyField) -> Optional[ir.Enum]:
    """The enum whose classes a field's annotation names (see annotation)."""
    return f.enum if isinstance(f, (ir.ScalarField, ir.ArrayField)) else None


def conversion(s: ir.Scalar, enum: Optional[ir.Enum]) -> tuple[str, str]:
    """How a value unpacked by struct becomes the attribute: (kind, enum lookup constant).
    float32 keeps the bits of signalling NaNs, which struct quiets, so encoding is lossless.
    An enum whose codes mean other things in other versions is looked up by version."""
    if enum is not None:
        return ("venum" if enum.versioned else "enum"), py_lookup(enum)
    if s.is_bool:
        return "bool", ""
    return ("f32" if _is_f32(s) else "plain"), ""


def out_code(s: ir.Scalar) -> str:
    """struct code for encoding: float32 is packed from its bits."""
    return "I" if s.is_float and s.size == 4 else STRUCT_CODES[s.name]


def index(base: str, k: int) -> str:
    if base == "0":
        return str(k)
    return base if k == 0 else f"{base} + {k}"


class _ClassBuilder:
    """Maps the plan of one layout to Python steps (and, first, of its group items)."""

    def __init__(self, target: "_Target", owner: str, struct: ir.Struct):
        self.target = target
        self.owner = owner
        self.structs: list[StructConst] = []
        # Names with several entries (in disjoint version ranges): one attribute for them all.
        self.repeated = [f.name for f in struct.public_fields if len(struct.named(f.name)) > 1]
        self.item_venums = [f.name for f in struct.fields
                            if isinstance(f, (ir.ScalarField, ir.ArrayField)) and f.enum is not None and f.enum.versioned]

    # ---- fixed runs: what each member of a run is ----

    def member(self, m: plan.Member, values: str, offsets: str) -> MemberView:
        """The view of one member; `values` and `offsets` are the bases its tuple index and byte
        offset count from (`0` and `pos` in a run, `i` and `at` inside a fixed item)."""
        f = m.field
        view = MemberView(f.name, "scalar", "plain", first=index(values, m.first_leaf),
                          last=index(values, m.first_leaf + m.leaf_count), at=index(offsets, m.offset))
        if isinstance(f, ir.GroupField):
            view.kind, view.count, view.item = "group", f.count, self.target.item_classes[f.item.name].name
            view.width, view.size = m.item.leaf_count, m.item.layout.fixed_size
            view.enums = item_enums(f.item)
            return view
        view.kind = "array" if isinstance(f, ir.ArrayField) else "scalar"
        view.conv, view.lookup = conversion(f.scalar, f.enum)
        if view.conv == "venum" and values == "i":
            # Inside a fixed item: the parent looks the table up once for all items.
            view.conv, view.lookup = "item_enum", str(self.item_venums.index(f.name))
        return view

    def run_member(self, m: plan.Member, in_item: bool) -> RunMember:
        """A member of a run as data (RunMember); in_item: inside a fixed item's values."""
        f = m.field
        if isinstance(f, ir.GroupField):
            return RunMember(f.name, "group", "plain", first=m.first_leaf, count=f.count,
                             item=self.target.item_classes[f.item.name].name, width=m.item.leaf_count,
                             size=m.item.layout.fixed_size, enums=["_e." + e for e in item_enums(f.item)])
        conv, lookup = conversion(f.scalar, f.enum)
        if conv == "venum" and in_item:
            conv, lookup = "item_enum", str(self.item_venums.index(f.name))
        elif conv in ("enum", "venum"):
            lookup = "_e." + lookup
        else:
            lookup = "None"
        kind = "array" if isinstance(f, ir.ArrayField) else "scalar"
        return RunMember(f.name, kind, conv, lookup, m.first_leaf, m.leaf_count)

    def run_step(self, run: plan.FixedRun) -> tuple[Step, Step]:
        const = f"_{self.owner.upper()}_{run.index}"
        fmt = ">" + "".join(STRUCT_CODES[leaf.scalar.name] for leaf in run.leaves)
        ofmt = ">" + "".join(out_code(leaf.scalar) for leaf in run.leaves)
        entries = [(leaf.path, leaf.offset, leaf.scalar.size) for leaf in run.leaves]
        members = [self.member(m, "0", "pos") for m in run.members]
        self.structs.append(StructConst(const, fmt, entries, ofmt if ofmt != fmt else None))
        # One plain value: unpack straight into its name, then convert it in place if needed.
        single = len(run.leaves) == 1 and members[0].conv != "f32"
        decode = Step("run", dict(const=const, size=run.size, members=members, single=single,
                                  run_members=[self.run_member(m, False) for m in run.members]))
        encode = Step("run", dict(const=const if ofmt == fmt else const + "_OUT", members=members))
        return decode, encode

    # ---- steps ----

    def steps(self, steps: list[plan.Step]) -> tuple[list[Step], list[Step]]:
        decode: list[Step] = []
        encode: list[Step] = []
        for step in steps:
            if isinstance(step, plan.FixedRun):
                d, e = self.run_step(step)
            elif isinstance(step, plan.CondGroup):
                inner_d, inner_e = self.steps(step.steps)
                # A name with entries in other conditions is set to None up front instead.
                absent = [f.name for f in step.fields if f.name not in self.repeated]
                d = Step("cond", dict(condition=step.condition, steps=inner_d, names=absent))
                e = Step("cond", dict(condition=step.condition, steps=inner_e))
            else:
                d, e = self.var_step(step)
            decode.append(d)
            encode.append(e)
        return decode, encode

    def var_step(self, step: plan.VarField) -> tuple[Step, Step]:
        f, path = step.field, step.path
        if isinstance(f, ir.StringField) and f.length is not None:
            prefix = self.target.prefix_const(f.length)
            return (Step("prefixed_text", dict(name=f.name, prefix=prefix, path=path)),
                    Step("prefixed_text", dict(name=f.name, prefix=prefix)))
        if isinstance(f, ir.StringField):
            return Step("rest_text", dict(name=f.name)), Step("rest_text", dict(name=f.name))
        if isinstance(f, ir.BytesField):
            return Step("rest_bytes", dict(name=f.name)), Step("rest_bytes", dict(name=f.name))
        if isinstance(f, ir.StringListField):
            data = dict(name=f.name, terminator=f"0x{f.terminator:02x}")
            return Step("texts", data), Step("texts", data)
        if isinstance(f, ir.ValueListField):
            return (Step("values", dict(name=f.name, terminator=f"0x{f.terminator:02x}", path=path)),
                    Step("values", dict(name=f.name, terminator=f"0x{f.terminator:02x}")))
        if isinstance(f, ir.SwitchField):
            const = f"_{self.owner.upper()}_{f.name.upper()}_BY_{f.selector.name.upper()}"
            cases = {k: self.target.prefix_const(s) for k, s in f.cases.items()}
            self.target.switches.append((const, cases))
            default = self.target.prefix_const(f.default)
            data = dict(name=f.name, const=const, default=default, selector=f.selector.name, path=path)
            return Step("switch", data), Step("switch", data)
        assert isinstance(f, ir.GroupField)
        item = self.target.item_classes[f.item.name]
        return (Step("group_to_end", dict(name=f.name, item=item.name, path=path)),
                Step("group_to_end", dict(name=f.name)))


def fixed_runs(decode: list[Step]) -> Optional[dict]:
    """A form whose decoder reads fixed runs one after the other, some only when an earlier field
    is nonzero (its other steps set absent attributes to None): each run's struct, its members
    as data, its flag and the attributes it leaves None when skipped, and those absent; else None.
    Names are quoted."""
    runs, absent = [], []
    for s in decode:
        if s.kind == "absent":
            absent += [py_string(name) for name in s.names]
        elif s.kind == "run":
            runs.append(dict(const=s.const, members=s.run_members, flag="None", skipped=[]))
        elif (s.kind == "cond" and s.condition.flag and s.condition.low is None and s.condition.high is None
              and [inner.kind for inner in s.steps] == ["run"]):
            (inner,) = s.steps
            runs.append(dict(const=inner.const, members=inner.run_members, flag=py_string(s.condition.flag),
                             skipped=[py_string(name) for name in s.names]))
        else:
            return None
    return dict(runs=runs, absent=absent) if runs else None


def item_enums(item: ir.Struct) -> list[str]:
    """The lookups of the versioned enums a fixed item's fields use, in field order."""
    return [py_lookup(f.enum) for f in item.fields
            if isinstance(f, (ir.ScalarField, ir.ArrayField)) and f.enum is not None and f.enum.versioned]


def _is_f32(s: ir.Scalar) -> bool:
    return s.is_float and s.size == 4


class _Target:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.item_classes: dict[int, PyClass] = {}
        self.classes: list[PyClass] = []
        self.prefixes: dict[str, str] = {}
        self.switches: list[tuple[str, dict]] = []
        self.problems: list[Problem] = []
        self.enum_imports: set[str] = set()   # the enum classes the attributes are annotated with

    def prefix_const(self, s: ir.Scalar) -> str:
        """Module constant: a struct of one scalar (length prefixes, switch cases)."""
        name = f"_{s.name.upper()}"
        self.prefixes[name] = ">" + STRUCT_CODES[s.name]
        return name

    def check_names(self, struct: ir.Struct) -> None:
        for f in struct.fields:
            if f.name in RESERVED_LOCALS:
                self.problems.append(f.where.problem(
                    f"python target: field name '{f.name}' clashes with a local of the generated decoder"))

    def build_class(self, layout: plan.LayoutPlan, name: str, role: str, json_type: str, code: Optional[int],
                    doc: str, header: Optional[list[plan.HeaderSlot]] = None,
                    sets_version: Optional[tuple[str, str]] = None,
                    summary: Optional[list[tuple[str, str]]] = None,
                    forms: Optional[list[plan.Variant]] = None, label: Optional[str] = None) -> PyClass:
        struct = layout.struct
        self.check_names(struct)
        # Group items first, so the parent can refer to them.
        for f in struct.fields:
            if isinstance(f, ir.GroupField):
                item = self.plan.item_of(f)
                self.item_classes[f.item.name] = self.build_class(
                    item.layout, py_item_class(f), "item", f.item.name, None,
                    one_line(f.doc) or f"One entry of {f.name}.", label=f.item_label)
        builder = _ClassBuilder(self, json_type, struct)
        structs: list[StructConst] = []
        if len(forms or []) > 1:
            # One flat decoder per form: no version test on the way (the form is chosen first).
            codecs = []
            for k, v in enumerate(forms):
                form_builder = _ClassBuilder(self, f"{json_type}_{k}", v.plan.struct)
                decode, encode = form_builder.steps(v.plan.steps)
                absent = [f.name for f in struct.public_fields if not v.plan.struct.named(f.name)]
                if absent:
                    decode.insert(0, Step("absent", dict(names=absent)))
                codecs.append(Codec(f"_{k}", decode, encode, v.describe(), fixed_runs(decode)))
                structs += form_builder.structs
        else:
            decode, encode = builder.steps(layout.steps)
            if builder.repeated:
                decode.insert(0, Step("absent", dict(names=builder.repeated)))
            codecs = [Codec("", decode, encode, runs=fixed_runs(decode))]
            structs = builder.structs
        items = {f.name: self.item_classes[f.item.name].name for f in struct.fields if isinstance(f, ir.GroupField)}
        header_fields = [slot.field for slot in header or [] if not slot.is_subtype]
        attrs = [attr(f, annotation(f, {})) for f in header_fields]
        attrs += [attr(f, annotation(f, items), f.conditional, struct.named(f.name)) for f in struct.public_fields]
        for f in [*header_fields, *struct.public_fields]:
            if annotated_enum(f) is not None:
                self.enum_imports.update(enum_classes(annotated_enum(f)))
        cls = PyClass(name, doc, role, label or words(json_type), json_type, code, attrs,
                      [f.name for f in header_fields], codecs, structs, sets_version=sets_version)
        if role == "item" and struct.fixed_item:
            # A fixed item is read inside its parent's run: from the parent's values and offset.
            cls.fixed = True
            cls.members = [builder.member(m, "i", "at") for m in layout.runs[0].members]
            cls.run_members = [builder.run_member(m, True) for m in layout.runs[0].members]
        cls.summary = [field_name for _, field_name in summary or []]
        cls.items = items
        self.classes.append(cls)
        return cls

    def forms(self, mp: plan.MessagePlan, classes: dict[int, PyClass]) -> dict:
        """The tables of the forms of a message's type codes (see plan.Variant and
        plan.MessagePlan.by_segment): per code, its forms (class, decoder, sizes, the version
        it stands for); per segment, each code's form; per code, the sizes that recognise one."""
        forms = []
        for code, variants in mp.variants.items():
            forms.append((code, [dict(cls=classes[id(v.layout)].name, decode=self.decoder_of(classes[id(v.layout)], mp, v),
                                      sizes=f"frozenset({{{', '.join(map(str, sorted(v.sizes)))}}})"
                                      if v.sizes is not None else "None",
                                      min_size=v.min_size, rep=v.rep, versions=v.describe())
                                 for v in variants]))
        rows = [dict(versions=s.describe(),
                     cells=", ".join(f"~{c[k].form}" if c[k].nearest else str(c[k].form) for c in mp.by_segment.values())
                     + ("," if len(mp.by_segment) == 1 else ""))   # a tuple of one
                for k, s in enumerate(self.plan.segments)]
        by_length = [(code, ", ".join(f"{size}: {k}" for size, k in sizes.items())) for code, sizes in mp.by_length.items()]
        return dict(forms=forms, rows=rows, by_length=by_length, codes=", ".join(map(str, mp.by_segment)))

    def set_encoders(self, mp: plan.MessagePlan, classes: dict[int, PyClass]) -> None:
        for c in mp.layouts:
            if len(mp.forms_of(c.layout)) > 1:
                classes[id(c.layout)].encoder_by_segment = self.encoder_by_segment(mp, c.layout)

    @staticmethod
    def encoder_by_segment(mp: plan.MessagePlan, layout: model.Layout) -> str:
        """For a layout of several forms: the index of its encoder in each segment (that of the
        form its code takes there; where that is another layout's form, its last)."""
        forms = mp.forms_of(layout)
        variants = mp.variants[layout.code.value]
        out = []
        for sf in mp.by_segment[layout.code.value]:
            v = variants[sf.form]
            out.append(next((k for k, f in enumerate(forms) if f is v), len(forms) - 1))
        return ", ".join(map(str, out)) + ","

    @staticmethod
    def decoder_of(cls: PyClass, mp: plan.MessagePlan, v: plan.Variant) -> str:
        forms = mp.forms_of(v.layout)
        suffix = f"_{forms.index(v)}" if len(forms) > 1 else ""
        return f"{cls.name}._decode{suffix}"

    def build(self) -> dict:
        messages = []
        for mp in self.plan.messages:
            m = mp.message
            if not mp.is_dispatch:
                classes = {id(c.layout): self.build_class(c.plan, py_layout_class(c.layout, False), "package",
                                                          c.layout.name, c.layout.code.value,
                                                          one_line(node_text(c.layout)),
                                                          summary=c.layout.summary, forms=mp.forms_of(c.layout),
                                                          label=layout_label(c.layout))
                           for c in mp.layouts}
                self.set_encoders(mp, classes)
                messages.append(dict(kind="packages", name=m.name, cls=py_message_class(m), code=m.code.value,
                                     code_name=m.code.name, doc=one_line(node_text(m)), label=words(m.name),
                                     layouts=list(classes.values()), body_offset=mp.body_offset,
                                     **self.forms(mp, classes)))
                continue
            fields = [slot.field for slot in mp.header if not slot.is_subtype]
            # A body message has no subtype byte: its one layout's code is the message type.
            subtype = m.subtype.name if m.has_subtype else None
            # Header values that need converting after the unpack: enums, looked up by the runtime.
            converts = []
            for i, f in enumerate(fields):
                conv, lookup = conversion(f.scalar, f.enum)
                if conv in ("enum", "venum"):
                    converts.append(dict(index=i, lookup=lookup, by_version=conv == "venum"))
                elif conv != "plain":
                    self.problems.append(f.where.problem(
                        f"python target: header field '{f.name}' must be an integer or an enum"))
            classes = {id(c.layout): self.build_class(c.plan, py_layout_class(c.layout, True), "subtype",
                                                      c.layout.name, c.layout.code.value,
                                                      one_line(node_text(c.layout)), mp.header,
                                                      c.layout.sets_version, c.layout.summary,
                                                      forms=mp.forms_of(c.layout),
                                                      label=layout_label(c.layout)) for c in mp.layouts}
            self.set_encoders(mp, classes)
            layouts = list(classes.values())
            announces = self.plan.version.subtype_code if self.plan.version.message_code == m.code.value else None
            messages.append(dict(
                kind="dispatch", name=m.name, code=m.code.value, code_name=m.code.name,
                doc=one_line(node_text(m)), layouts=layouts,
                header_fmt=">" + "".join(STRUCT_CODES[slot.field.scalar.name] for slot in mp.header),
                header_run=[(slot.field.name, slot.offset, slot.field.scalar.size) for slot in mp.header],
                header_offset=mp.header[0].offset if mp.header else mp.body_offset,
                header_names=[f.name for f in fields], header_converts=converts,
                subtype=py_string_or_none(subtype),
                body_offset=mp.body_offset, announces=announces, **self.forms(mp, classes)))
        if self.problems:
            raise SpecError(self.p.source, self.problems)
        p = self.p
        v = self.plan.version
        skips = [dict(fixed=k.fixed, prefix=self.prefix_const(ir.SCALARS[("int" if k.signed else "uint") + str(8 * k.prefix)]))
                 for k in v.skips]
        return dict(messages=messages, classes=self.classes, prefixes=self.prefixes, switches=self.switches,
                    enum_imports=sorted(self.enum_imports),
                    version=dict(skips=skips, tail=v.tail), package_header_size=self.plan.package_header_size,
                    segments=[dict(first=s.first, versions=s.describe()) for s in self.plan.segments if s.first],
                    type_offset=p.message_length.scalar.size,
                    header_fmt=">" + STRUCT_CODES[p.message_length.scalar.name] + STRUCT_CODES[p.message_type.scalar.name],
                    package_header_fmt=">" + STRUCT_CODES[p.package_length.scalar.name]
                    + STRUCT_CODES[p.package_type.scalar.name])


def enum_views(p: model.Protocol) -> list[dict]:
    views = []
    for e in p.enums.values():
        tables = []
        for t in e.tables:
            tables.append(dict(cls=py_table_class(e, t), versions=t.versions.describe(), low=t.versions.low,
                               high=t.versions.high,
                               members=[dict(name=v.name, value=v.value,
                                            doc=one_line(value_text(v)))
                                       for v in t.values]))
        views.append(dict(name=e.name, cls=py_enum_class(e), lookup=py_lookup(e), doc=one_line(node_text(e)),
                          wire=e.scalar.name, versioned=e.versioned, tables=tables))
    return views


def value_kind_views(p: model.Protocol) -> list[dict]:
    """Per value-type table: code -> (name, layout, struct format, is bool), and the fewest bytes a value takes."""
    out = []
    for t in p.value_type.tables:
        kinds = []
        for v in t.values:
            lay = p.value_layouts[v.name]
            if lay.layout in ("scalar", "array"):
                fmt = ">" + STRUCT_CODES[lay.item.name] * (lay.count if lay.layout == "array" else 1)
            elif lay.layout == "matrix":
                fmt = ">" + STRUCT_CODES[lay.length.name] * 2
            elif lay.layout in ("string", "list"):
                fmt = ">" + STRUCT_CODES[lay.length.name]
            else:
                fmt = None
            kinds.append(dict(code=v.value, name=v.name, layout=lay.layout, fmt=fmt,
                              is_bool=bool(lay.item and lay.item.is_bool and lay.layout == "scalar")))
        out.append(dict(low=t.versions.low, high=t.versions.high, versions=t.versions.describe(), kinds=kinds,
                        min_size=p.value_min_size(t), cls=py_table_class(p.value_type, t)))
    return out


def render(protocol_plan: plan.ProtocolPlan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment("python")
    model = _Target(protocol_plan).build()
    ctx = dict(banner=banner, p=p, enums=enum_views(p), value_tables=value_kind_views(p),
               version_text=ir.version_text, bugfix_any=ir.BUGFIX_ANY, **model)
    return {f"{PACKAGE}/{name[:-3]}": env.get_template(f"packages/{name}").render(**ctx)
            for name in ("enums.py.j2", "messages.py.j2", "spec.py.j2", "__init__.py.j2")}
