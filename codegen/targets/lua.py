"""Lua target: the IR -> plain data -> templates/lua/urwire.lua.j2 + runtime/*.lua, one Wireshark
dissector in one self-contained file.

Every decision is made here: which ProtoField each field becomes, its abbreviation
(`ur.<message_or_package>.<field>`, CONTRACT §4), value strings, the field descriptors each
layout is walked with, the offsets of the Version message's numbers and of the fields the Info
column shows. The builder hands the template data only (dicts and `Step`s); the template writes
each descriptor kind and each ProtoField shape with a macro of its own. The code that walks the
descriptors is hand-written Lua in templates/lua/runtime/, joined after the generated tables.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from .. import ir, plan
from ..emit import TEMPLATES, environment, runtime_source
from ..errors import Problem, SpecError
from ..naming import wireshark_field, words
from ..view import Step

OUT = "lua/urwire.lua"

# The hand-written runtime, in the order it is joined. Each file is a chunk that receives
# (spec, rt): `spec` is the generated data, `rt` what earlier runtime files export.
RUNTIME = ("declare.lua", "bytes.lua", "versions.lua", "walk.lua", "values.lua", "info.lua",
           "messages.lua", "stream.lua", "framing.lua", "register.lua")

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


def version_number(v: Optional[ir.Version]) -> Optional[int]:
    """A version as the runtime compares it: major * 1000 + minor."""
    return None if v is None else v[0] * 1000 + v[1]


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
    vs: Optional[str] = None   # value-string variable
    bits: int = 0              # flag: width of the parent integer
    mask: int = 0              # flag: its bit


@dataclass
class LayoutView:
    var: str                   # Lua local holding the descriptor list
    doc: str
    descriptors: list[Step]


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.problems: list[Problem] = []
        self.fields: list[PField] = []
        self.keys: set[str] = set()
        self.layouts: list[LayoutView] = []
        self.enum_var: dict[str, str] = {}

    # ---- fields ----

    def add_field(self, pf: PField) -> str:
        """Declare a field once (a header layout shared by subtypes names it again); its key."""
        if pf.key not in self.keys:
            self.keys.add(pf.key)
            self.fields.append(pf)
        return pf.key

    def owned_field(self, owner: str, name: str, shape: str, ctor: str, label: str, desc: str, **more) -> str:
        return self.add_field(PField(f"{owner}.{name}", shape, ctor, wireshark_field(owner, name), label, desc,
                                     **more))

    def scalar_field(self, owner: str, name: str, s: ir.Scalar, enum: Optional[ir.Enum], doc: str,
                     label: Optional[str] = None, hex_base: bool = False) -> str:
        label = label or name
        if s.is_float:
            return self.owned_field(owner, name, "float", PROTOFIELD[s.name], label, doc)
        if s.is_bool:
            return self.owned_field(owner, name, "bool", "bool", label, doc)
        return self.owned_field(owner, name, "integer", PROTOFIELD[s.name], label, doc,
                                base="HEX" if hex_base else "DEC",
                                vs=self.enum_var[enum.name] if enum is not None else None)

    def header_field(self, key: str, label: str, h: ir.HeaderField) -> str:
        """ur.length, ur.type, ur.package.*: outside the owner.field scheme."""
        return self.add_field(PField(key, "integer", PROTOFIELD[h.scalar.name], f"ur.{key}", label, h.doc,
                                     base="DEC", vs=self.enum_var[h.enum.name] if h.enum is not None else None))

    def add_item(self, name: str, label: str, doc: str, where: ir.Where) -> str:
        """The subtree field of a package or message: ur.<name>, true when it is present."""
        if name in self.keys:
            self.problems.append(where.problem(f"lua target: the filter name ur.{name} is taken already"))
        return self.add_field(PField(name, "none", "none", f"ur.{name}", label, doc))

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
                out.append(self.descriptor(owner, f, one_line(f.doc, f.field_note), f.name, keep, show.get(f.name)))
        return out

    def descriptor(self, owner: str, f: ir.AnyField, doc: str, path: str, keep: set[str],
                   show: Optional[str]) -> Step:
        """One field's descriptor; `show` is the text the Info column puts before its value."""
        common = dict(path=path, show=show)
        if isinstance(f, ir.ScalarField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, doc, hex_base=bool(f.bits) and not f.scalar.signed)
            data = dict(common, field=key, size=f.scalar.size, signed=f.scalar.signed and not f.scalar.is_float,
                        vs=self.enum_var[f.enum.name] if f.enum is not None else None,
                        keep=f.name if f.name in keep else None)
            if not f.bits:
                return Step("scalar", data)
            bits = [self.owned_field(owner, f"{f.name}.{b}", "flag", "bool", b, f"Bit {i} of {f.name}.",
                                     bits=f.scalar.bits, mask=1 << i)
                    for i, b in enumerate(f.bits)]
            return Step("bits", dict(data, bits=bits))
        if isinstance(f, ir.ArrayField):
            key = self.scalar_field(owner, f.name, f.scalar, f.enum, doc)
            return Step("array", dict(common, field=key, size=f.scalar.size, count=f.count))
        if isinstance(f, ir.GroupField):
            key = self.owned_field(owner, f.name, "none", "none", f.item_label, doc)
            item = self.plan.item_of(f)
            item_var = f"L_{owner}_{f.item.name}"
            self.layouts.append(LayoutView(item_var, one_line(f.doc) or f"One entry of {f.name}.",
                                           self.descriptors(owner, item.layout.steps, keep)))
            return Step("group", dict(common, field=key, label=f.item_label, count=f.count,
                                      size=item.layout.fixed_size if item.fixed else None, item=item_var))
        if isinstance(f, ir.StringField):
            key = self.owned_field(owner, f.name, "text", "string", f.name, doc, base="UNICODE")
            if f.length is None:
                return Step("string", dict(common, field=key))
            return Step("pstring", dict(common, field=key, size=f.length.size, signed=f.length.signed))
        if isinstance(f, ir.StringListField):
            key = self.owned_field(owner, f.name, "text", "string", f.name, doc, base="UNICODE")
            return Step("strings", dict(common, field=key, term=f.terminator))
        if isinstance(f, ir.BytesField):
            key = self.owned_field(owner, f.name, "bytes", "bytes", f.name, doc)
            return Step("bytes", dict(common, field=key))
        if isinstance(f, ir.SwitchField):
            default = dict(field=self.scalar_field(owner, f.name, f.default, None, doc), size=f.default.size)
            cases = []
            for code, s in sorted(f.cases.items()):
                key = self.scalar_field(owner, f"{f.name}_{s.name}", s, None,
                                        one_line(doc, f"(as {s.name}: {f.selector.name} is {code})"), label=f.name)
                cases.append(dict(code=code, field=key, size=s.size))
            return Step("switch", dict(common, sel=f.selector.name, default=default, cases=cases))
        if isinstance(f, ir.ValueListField):
            return Step("values", dict(common, term=f.terminator, **self.value_fields(owner, f)))
        self.problems.append(f.where.problem(f"lua target: no descriptor for a {type(f).__name__}"))
        return Step("bytes", dict(common, field=None))

    def value_fields(self, owner: str, f: ir.ValueListField) -> dict:
        """The fields of typed values: one item per value, its type, and one field per data kind."""
        def add(name: str, shape: str, ctor: str, label: str, desc: str, **more) -> str:
            return self.owned_field(owner, name, shape, ctor, label, desc, **more)

        roles = [
            ("item", add(f.name, "none", "none", f.name, one_line(f.doc))),
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
            kinds.append((kind, self.scalar_field(owner, f"value_{kind}", ir.SCALARS[kind], None,
                                                  f"A value of type {kind}.", label="value")))
        string = add("value_string", "text", "string", "value", "A string value.", base="UNICODE")
        return dict(roles=roles, kinds=kinds, string=string)

    # ---- layouts and messages ----

    def keep_names(self, struct: ir.Struct) -> set[str]:
        out = set()
        for f in struct.fields:
            if f.present_if:
                out.add(f.present_if)
            if isinstance(f, ir.SwitchField):
                out.add(f.selector.name)
        return out

    def layout(self, owner: str, layout: plan.LayoutPlan, doc: str, show: Optional[dict] = None) -> str:
        var = f"L_{owner}"
        self.layouts.append(LayoutView(var, doc, self.descriptors(owner, layout.steps, self.keep_names(layout.struct),
                                                                  show=show)))
        return var

    def header_layout(self, var: str, owner: str, slots: list[plan.HeaderSlot], doc: str) -> str:
        """A message header (a fixed run of scalars), its fields named under `owner`."""
        self.layouts.append(LayoutView(var, doc, [self.descriptor(owner, s.field, one_line(s.field.doc, s.field.field_note),
                                                                  s.field.name, set(), None) for s in slots]))
        return var

    def package_info(self, variants: list[plan.Variant]) -> list[dict]:
        """The spec's summary of a robot-state package: per body size (each form of the code),
        its enum fields and where they start, so the Info column reads them without a walk."""
        out = []
        for v in variants:
            for size, offsets in v.offsets_by_size().items():
                enums = []
                for _, name in v.layout.summary:
                    f = next((g for g in v.layout.struct.named(name) if g.versions.contains(v.rep)), None)
                    if f is None or name not in offsets:
                        continue    # not in this form: the Info column leaves it out
                    if not isinstance(f, ir.ScalarField) or f.enum is None:
                        self.problems.append(v.layout.where.problem(
                            f"lua target: a package summary may only name enum fields, not '{name}'"))
                        continue
                    enums.append(dict(offset=offsets[name], size=f.scalar.size, signed=f.scalar.signed,
                                      vs=self.enum_var[f.enum.name], name=f.name))
                if enums:
                    out.append(dict(size=size, enums=enums))
        return out

    @staticmethod
    def message_show(layout: ir.Layout) -> dict:
        """Fields of a message the Info column shows, each with the text put before it."""
        return {name: before for before, name in layout.summary}

    def package_message(self, mp: plan.MessagePlan) -> Step:
        m = mp.message
        pkgs = []
        for c in mp.layouts:
            pk = c.layout
            label = words(pk.name)
            pkgs.append(dict(code=pk.code.value, name=pk.name, label=label,
                             layout=self.layout(pk.name, c.plan, one_line(pk.doc, pk.field_note)),
                             info=self.package_info([v for v in mp.variants[pk.code.value] if v.layout is pk]),
                             item=self.add_item(pk.name, label, one_line(pk.doc), pk.where)))
        return Step("packages", dict(code=m.code.value, label=words(m.name), doc=one_line(m.doc, m.field_note),
                                     var=f"{m.name.upper()}_PACKAGES", packages=pkgs,
                                     types=self.enum_var[m.package_type.name],
                                     length="package.length", type="package.type"))

    def dispatch_message(self, mp: plan.MessagePlan) -> Step:
        m = mp.message
        sub_field = self.scalar_field(m.name, m.subtype.name, m.subtype.scalar, m.subtype.enum,
                                      one_line(m.subtype.doc, "Subtype of the message."))
        # The header then the subtype: shown as such when the subtype is unknown.
        header = self.header_layout(f"L_{m.name}", m.name, mp.header,
                                    f"Header and subtype of every {words(m.name).lower()}.")
        subtypes = []
        for c in mp.layouts:
            st = c.layout
            # The header fields of a subtype are filterable under its own name (ur.key.timestamp).
            sub_header = self.header_layout(f"L_{st.name}_header", st.name,
                                            [slot for slot in mp.header if not slot.is_subtype],
                                            f"Header of the {st.name} message.")
            body = self.layout(st.name, c.plan, one_line(st.doc, st.field_note), show=self.message_show(st))
            subtypes.append(dict(code=st.code.value, name=st.name, label=words(st.name), header=sub_header,
                                 layout=body, needs_version=st.struct.needs_version,
                                 item=self.add_item(st.name, words(st.name), one_line(st.doc), st.where)))
        return Step("subtypes", dict(code=m.code.value, label=words(m.name), doc=one_line(m.doc, m.field_note),
                                     var=f"{m.name.upper()}_SUBTYPES", body_offset=mp.body_offset,
                                     header=header, subtype_field=sub_field,
                                     subtype_names=self.enum_var[m.subtype_enum.name], subtypes=subtypes))

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
                               versions=t.versions.describe(), kinds=kinds))
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
                    default_ports=",".join(str(x) for x in p.ports),
                    default_version=ir.version_text(p.default_version))

    def build(self) -> dict:
        p = self.p
        enums = []
        for e in p.enums.values():
            if e is p.value_type:
                continue   # value types are named by the runtime, from the version's table
            var = f"VS_{e.name.upper()}"
            self.enum_var[e.name] = var
            # The newest table names the codes (and filters by name use it).
            enums.append(dict(var=var, doc=one_line(e.doc, e.field_note),
                              entries=[(v.value, v.name) for v in e.tables[-1].values]))
        self.header_field("length", "Length", p.message_length)
        self.header_field("type", "Type", p.message_type)
        self.header_field("package.length", "Length", p.package_length)
        self.header_field("package.type", "Type", p.package_type)
        messages = [self.dispatch_message(mp) if mp.is_dispatch else self.package_message(mp)
                    for mp in self.plan.messages]
        # Which fields of a package a filter or column may ask for (TreeItem:referenced).
        for m in messages:
            for pk in m.packages if m.kind == "packages" else []:
                pk["refs"] = [k for k in sorted(self.keys) if k.startswith(pk["name"] + ".")]
        version, constants = self.version_reader(), self.constants()
        if self.problems:
            raise SpecError(p.source, self.problems)
        return dict(enums=enums, fields=self.fields, layouts=self.layouts, messages=messages,
                    version=version, value_tables=self.value_tables(),
                    known_codes=p.known_message_codes, message_type_names=self.enum_var[p.message_type_enum.name],
                    constants=constants)

    def version_reader(self) -> dict:
        """Where the Version message keeps major and minor: fixed bytes and length-prefixed strings."""
        v = self.plan.version
        if any(f.fixed_size != 1 for f in (v.major, v.minor)):
            self.problems.append(v.layout.where.problem("lua target: major and minor versions must be one byte each"))
        steps = [dict(fixed=skip.fixed + (v.body_offset if i == 0 else 0), prefix=skip.prefix, signed=skip.signed)
                 for i, skip in enumerate(v.skips)]
        return dict(message=v.message_code, subtype=v.subtype_code, subtype_offset=v.subtype_offset,
                    steps=steps, tail=v.tail + (0 if v.skips else v.body_offset), rest=v.rest)


def runtime() -> list[dict]:
    """The runtime files in joining order, as joined (standalone-only lines removed)."""
    folder = TEMPLATES / "lua" / "runtime"
    found = sorted(p.name for p in folder.glob("*.lua"))
    if sorted(RUNTIME) != found:
        raise ValueError(f"lua target: runtime files {found} differ from the joining order {list(RUNTIME)}")
    return [dict(name=name, source=runtime_source("lua", name)) for name in RUNTIME]


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment("lua")
    env.filters["lua"] = lua_literal
    model = _Builder(protocol_plan).build()
    ctx = dict(banner=banner, p=p, doc=one_line(p.doc), runtime=runtime(), **model)
    return {OUT: env.get_template("urwire.lua.j2").render(**ctx)}
