"""Python target: the IR -> a view model of decode/encode steps -> templates/python/*.py.j2.

Every decision (struct formats, offsets, expressions, paths) is made here; the templates
only lay the strings out. Fixed runs of fields become one precompiled struct.Struct.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from .. import ir
from ..emit import environment, runtime_files
from ..view import Step, one_line
from ..naming import (camel, py_enum_class, py_item_class, py_layout_class, py_lookup,
                      py_message_class, py_table_class)

PACKAGE = "python/urwire"
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


@dataclass
class StructConst:
    name: str
    fmt: str
    run: list                     # (path, offset in run, size)
    out_fmt: Optional[str] = None  # encoding format when it differs (float32 packed as bits)


@dataclass
class PyClass:
    name: str
    doc: str
    role: str                      # package | subtype | item
    json_type: str
    code: Optional[int]
    attrs: list[Attr]
    header_names: list[str]
    decode_steps: list[Step]
    encode_steps: list[Step]
    structs: list[StructConst]
    fixed: bool = False            # item laid out in its parent's run
    from_exprs: list[str] = field(default_factory=list)    # fixed items: v[i + k] expressions
    values_exprs: list[str] = field(default_factory=list)  # fixed items: encode expressions
    sets_version: Optional[tuple[str, str]] = None
    summary: list[str] = field(default_factory=list)

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
        return f"Union[{py_enum_class(enum)}, int]"
    return "bool" if s.is_bool else "float" if s.is_float else "int"


def json_kind(f: ir.AnyField) -> str:
    def scalar_kind(s: ir.Scalar) -> str:
        return "bool" if s.is_bool else ("f32" if s.size == 4 else "f64") if s.is_float else "int"

    if isinstance(f, ir.ScalarField):
        return scalar_kind(f.scalar)
    if isinstance(f, ir.ArrayField):
        return "list:" + scalar_kind(f.scalar)
    if isinstance(f, ir.GroupField):
        return "items"
    if isinstance(f, ir.StringField):
        return "text"
    if isinstance(f, ir.StringListField):
        return "texts"
    if isinstance(f, ir.BytesField):
        return "hex"
    if isinstance(f, ir.SwitchField):
        floats = [s for s in list(f.cases.values()) + [f.default] if s.is_float]
        return scalar_kind(floats[0]) if floats else "int"
    return "values"


def leaf_expr(s: ir.Scalar, enum: Optional[ir.Enum], ref: str, at: str = "") -> str:
    """Decode expression of one scalar read as `ref`; `at` is its byte offset (for float32 NaNs)."""
    if enum is not None:
        return f"_e.{py_lookup(enum)}.get({ref}, {ref})"
    if s.is_bool:
        return f"_BOOL[{ref}]"
    if s.is_float and s.size == 4 and at:
        # struct quiets signalling NaNs of float32; keep their bits so encoding is lossless.
        return f"({ref} if {ref} == {ref} else _rt.f32_nan(buf, {at}))"
    return ref


def encode_expr(s: ir.Scalar, ref: str) -> str:
    """Encode argument of one scalar; float32 goes out as its bits (see leaf_expr)."""
    return f"_rt.f32_bits({ref})" if s.is_float and s.size == 4 else ref


def out_code(s: ir.Scalar) -> str:
    """struct code for encoding: float32 is packed from its bits."""
    return "I" if s.is_float and s.size == 4 else STRUCT_CODES[s.name]


def index(base: str, k: int) -> str:
    if base == "0":
        return str(k)
    return base if k == 0 else f"{base} + {k}"


class _ClassBuilder:
    """Builds the PyClass of one struct (and, first, of its group items)."""

    def __init__(self, target: "_Target", owner: str):
        self.target = target
        self.owner = owner
        self.structs: list[StructConst] = []

    # ---- fixed runs ----

    def run_leaves(self, f: ir.AnyField, path: str, base: int):
        """For one fixed field: (decode fmt, encode fmt, run entries, decode expr(v, i, at),
        encode args, number of values). `at` is the expression of the field's byte offset."""
        if isinstance(f, ir.ScalarField):
            return (STRUCT_CODES[f.scalar.name], out_code(f.scalar), [(path, base, f.scalar.size)],
                    lambda v, i, at: leaf_expr(f.scalar, f.enum, f"{v}[{i}]", at),
                    [encode_expr(f.scalar, f"self.{f.name}")], 1)
        if isinstance(f, ir.ArrayField):
            n, size = f.count, f.scalar.size
            entries = [(f"{path}[{k}]", base + k * size, size) for k in range(n)]

            def array_expr(v, i, at, f=f, n=n):
                ref = f"{v}[{i}:{i} + {n}]" if not i.isdigit() else f"{v}[{i}:{int(i) + n}]"
                if f.scalar.is_float and f.scalar.size == 4:
                    return f"_rt.f32_list({ref}, buf, {at})"
                if f.enum is None and not f.scalar.is_bool:
                    return f"list({ref})"
                return f"[{leaf_expr(f.scalar, f.enum, 'x')} for x in {ref}]"
            enc = (f"*map(_rt.f32_bits, self.{f.name})" if f.scalar.is_float and f.scalar.size == 4
                   else f"*self.{f.name}")
            return (STRUCT_CODES[f.scalar.name] * n, out_code(f.scalar) * n, entries, array_expr, [enc], n)
        assert isinstance(f, ir.GroupField) and f.count is not None
        item_cls = self.target.item_classes[id(f)]
        fmt, ofmt, entries, width, offset = "", "", [], 0, base
        for k in range(f.count):
            for g in f.item.fields:
                gfmt, gofmt, gentries, _, _, gwidth = self.run_leaves(g, f"{path}[{k}].{g.name}", offset)
                fmt += gfmt
                ofmt += gofmt
                entries += gentries
                offset += g.fixed_size or 0
                if k == 0:
                    width += gwidth
        item_size = f.item.fixed_size

        def group_expr(v, i, at, cls=item_cls.name, n=f.count, width=width, item_size=item_size):
            first = f"{i} + j * {width}" if i != "0" else f"j * {width}"
            return f"[{cls}._from({v}, {first}, buf, {at} + j * {item_size}) for j in range({n})]"
        return fmt, ofmt, entries, group_expr, [f"*[x for item in self.{f.name} for x in item._values()]"], width * f.count

    def flush_run(self, run: list[ir.AnyField], decode: list[Step], encode: list[Step], prefix: str) -> None:
        if not run:
            return
        const = f"_{self.owner.upper()}_{len(self.structs)}"
        fmt, ofmt, entries, assigns, args, index_ = ">", ">", [], [], [], 0
        offset = 0
        for f in run:
            ffmt, fofmt, fentries, expr, fargs, width = self.run_leaves(f, prefix + f.name, offset)
            fmt += ffmt
            ofmt += fofmt
            entries += fentries
            assigns.append((f.name, expr("v", str(index_), f"pos + {offset}" if offset else "pos")))
            args += fargs
            index_ += width
            offset += f.fixed_size or 0
        out_const = const if ofmt == fmt else const + "_OUT"
        self.structs.append(StructConst(const, fmt, entries, ofmt if ofmt != fmt else None))
        # One plain value: unpack straight into its name, then convert it in place if needed.
        single = index_ == 1 and "f32_nan" not in assigns[0][1]
        name = assigns[0][0]
        convert = assigns[0][1].replace("v[0]", name) if single and assigns[0][1] != "v[0]" else None
        decode.append(Step("run", dict(const=const, size=offset, assigns=assigns, single=single, name=name,
                                       convert=convert)))
        encode.append(Step("run", dict(const=out_const, args=args)))
        run.clear()

    # ---- steps ----

    def steps(self, fields: list[ir.AnyField], prefix: str) -> tuple[list[Step], list[Step]]:
        decode: list[Step] = []
        encode: list[Step] = []
        run: list[ir.AnyField] = []
        i = 0
        while i < len(fields):
            f = fields[i]
            if f.name in RESERVED_LOCALS:
                raise ValueError(f"field name '{f.name}' clashes with a local of the generated Python")
            if f.conditional:
                self.flush_run(run, decode, encode, prefix)
                group = [f]
                while i + 1 < len(fields) and (fields[i + 1].present_if, fields[i + 1].versions) == (f.present_if, f.versions):
                    i += 1
                    group.append(fields[i])
                inner_d, inner_e = self.steps([_unconditional(g) for g in group], prefix)
                decode.append(Step("cond", dict(test=self.condition(f, ""), steps=inner_d,
                                                names=[g.name for g in group])))
                encode.append(Step("cond", dict(test=self.condition(f, "self."), steps=inner_e)))
            elif f.fixed_size is not None and not isinstance(f, ir.SwitchField):
                run.append(f)
            else:
                self.flush_run(run, decode, encode, prefix)
                d, e = self.dynamic_step(f, prefix + f.name)
                decode.append(d)
                encode.append(e)
            i += 1
        self.flush_run(run, decode, encode, prefix)
        return decode, encode

    def condition(self, f: ir.AnyField, ref: str) -> str:
        tests = []
        if f.present_if:
            tests.append(f"{ref}{f.present_if}")
        if f.versions.low:
            tests.append(f"version >= {f.versions.low}")
        if f.versions.high:
            tests.append(f"version <= {f.versions.high}")
        return " and ".join(tests)

    def dynamic_step(self, f: ir.AnyField, path: str) -> tuple[Step, Step]:
        if isinstance(f, ir.StringField) and f.length is not None:
            prefix = self.target.prefix_const(f.length)
            return (Step("prefixed_text", dict(name=f.name, prefix=prefix, path=path)),
                    Step("prefixed_text", dict(name=f.name, prefix=prefix)))
        if isinstance(f, ir.StringField):
            return Step("rest_text", dict(name=f.name)), Step("rest_text", dict(name=f.name))
        if isinstance(f, ir.BytesField):
            return Step("rest_bytes", dict(name=f.name)), Step("rest_bytes", dict(name=f.name))
        if isinstance(f, ir.StringListField):
            return (Step("texts", dict(name=f.name, terminator=f"0x{f.terminator:02x}")),
                    Step("texts", dict(name=f.name, terminator=f"0x{f.terminator:02x}")))
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
        item = self.target.item_classes[id(f)]
        if f.count is not None:
            raise NotImplementedError("a fixed-count group of variable-size items")
        return (Step("group_to_end", dict(name=f.name, item=item.name, path=path)),
                Step("group_to_end", dict(name=f.name)))


def _unconditional(f: ir.AnyField) -> ir.AnyField:
    import copy
    g = copy.copy(f)
    g.present_if = None
    g.versions = ir.ALL_VERSIONS
    return g


class _Target:
    def __init__(self, protocol: ir.Protocol):
        self.p = protocol
        self.item_classes: dict[int, PyClass] = {}
        self.classes: list[PyClass] = []
        self.prefixes: dict[str, str] = {}
        self.switches: list[tuple[str, dict]] = []

    def prefix_const(self, s: ir.Scalar) -> str:
        """Module constant: a struct of one scalar (length prefixes, switch cases)."""
        name = f"_{s.name.upper()}"
        self.prefixes[name] = ">" + STRUCT_CODES[s.name]
        return name

    def build_class(self, struct: ir.Struct, name: str, role: str, json_type: str, code: Optional[int],
                    doc: str, header: Optional[ir.Struct] = None,
                    sets_version: Optional[tuple[str, str]] = None,
                    summary: Optional[list[tuple[str, str]]] = None) -> PyClass:
        # Group items first, so the parent can refer to them.
        for f in struct.fields:
            if isinstance(f, ir.GroupField):
                item = self.build_class(f.item, py_item_class(f), "item", f.item.name, None,
                                        one_line(f.doc) or f"One entry of {f.name}.")
                self.item_classes[id(f)] = item
        builder = _ClassBuilder(self, json_type)
        decode, encode = builder.steps(struct.fields, "")
        items = {f.name: self.item_classes[id(f)].name for f in struct.fields if isinstance(f, ir.GroupField)}
        attrs = []
        header_names = []
        if header is not None:
            for f in header.fields:
                attrs.append(Attr(f.name, annotation(f, {}), one_line(f.doc, f.field_note), json_kind(f)))
                header_names.append(f.name)
        for f in struct.fields:
            attrs.append(Attr(f.name, annotation(f, items), one_line(f.doc, f.field_note), json_kind(f), f.conditional))
        cls = PyClass(name, doc, role, json_type, code, attrs, header_names, decode, encode, builder.structs,
                      sets_version=sets_version)
        summary = summary or []
        if role == "item" and struct.fixed_size is not None:
            cls.fixed = True
            k, offset = 0, 0
            for f in struct.fields:
                _, _, _, expr, args, width = builder.run_leaves(f, f.name, 0)
                cls.from_exprs.append(expr("v", index("i", k), index("at", offset)))
                cls.values_exprs += args
                k += width
                offset += f.fixed_size or 0
        cls.summary = [name for _, name in summary]
        self.classes.append(cls)
        return cls

    def build(self) -> dict:
        messages = []
        for m in self.p.messages:
            if isinstance(m, ir.PackageListMessage):
                layouts = [self.build_class(pk.struct, py_layout_class(pk, False), "package", pk.name,
                                            pk.code.value, one_line(pk.doc, pk.field_note), summary=pk.summary)
                           for pk in m.packages]
                messages.append(dict(kind="packages", name=m.name, cls=py_message_class(m), code=m.code.value,
                                     code_name=m.code.name, doc=one_line(m.doc, m.field_note), layouts=layouts))
            else:
                hdr_fmt = ">" + "".join(STRUCT_CODES[f.scalar.name] for f in m.header.fields) \
                    + STRUCT_CODES[m.subtype.scalar.name]
                run, off = [], self.p.header_size
                for f in list(m.header.fields) + [m.subtype]:
                    run.append((f.name, off, f.scalar.size))
                    off += f.scalar.size
                # Header values that need converting after the unpack (enums): (name, expression).
                header_converts = [(f.name, leaf_expr(f.scalar, f.enum, f.name, str(self.p.header_size)))
                                   for f in m.header.fields]
                header_converts = [(n, e) for n, e in header_converts if n != e]
                names = [f.name for f in m.header.fields]
                layouts = [self.build_class(st.struct, py_layout_class(st, True), "subtype", st.name,
                                            st.code.value, one_line(st.doc, st.field_note), m.header,
                                            st.sets_version, st.summary) for st in m.subtypes]
                messages.append(dict(
                    kind="dispatch", name=m.name, code=m.code.value, code_name=m.code.name,
                    doc=one_line(m.doc, m.field_note), layouts=layouts, header_fmt=hdr_fmt, header_run=run,
                    header_names=names, header_converts=header_converts, subtype=m.subtype.name,
                    body_offset=off, source_arg="source" if "source" in names else "None"))
        return dict(messages=messages, classes=self.classes, prefixes=self.prefixes, switches=self.switches)


def enum_views(p: ir.Protocol) -> list[dict]:
    views = []
    for e in p.enums.values():
        tables = []
        for t in e.tables:
            cls = py_enum_class(e) if not e.versioned else py_table_class(e, t)
            tables.append(dict(cls=cls, versions=t.versions.describe(), low=t.versions.low, high=t.versions.high,
                               members=[dict(name=v.name, value=v.value,
                                            doc=one_line(v.doc, "(undocumented)" if v.undocumented else "",
                                                         f"(from {v.versions.describe()})" if not v.versions.unbounded else ""))
                                       for v in t.values]))
        views.append(dict(name=e.name, cls=py_enum_class(e), lookup=py_lookup(e), doc=one_line(e.doc, e.field_note),
                          wire=e.scalar.name, versioned=e.versioned, tables=tables))
    return views


def value_kind_views(p: ir.Protocol) -> list[dict]:
    """Per value-type table: code -> (name, layout, struct format, is bool)."""
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
                        cls=py_table_class(p.value_type, t)))
    return out


def render(p: ir.Protocol, banner: list[str]) -> dict[str, str]:
    env = environment("python")
    model = _Target(p).build()
    ctx = dict(banner=banner, p=p, enums=enum_views(p), value_tables=value_kind_views(p),
               version_text=ir.version_text, **model)
    out = {f"{PACKAGE}/{name[:-3]}": env.get_template(name).render(**ctx)
           for name in ("enums.py.j2", "messages.py.j2", "spec.py.j2", "__init__.py.j2")}
    for name, text in runtime_files("python").items():
        out[f"{PACKAGE}/{name}"] = text
    out[f"{PACKAGE}/py.typed"] = ""
    return out
