"""Lua target: the IR -> a view model -> templates/lua/urwire.lua.j2, one Wireshark dissector.

Every decision is made here: which ProtoField each field becomes, its abbreviation
(`ur.<message_or_package>.<field>`, CONTRACT §4), value strings, the field descriptors each
layout is walked with, the offsets of the Version message's numbers and of the fields the Info
column shows. The template only lays these strings out; the walking code in it is generic.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from .. import ir
from ..emit import environment
from ..naming import wireshark_field, words

OUT = "lua/urwire.lua"

# ProtoField constructor per scalar (integers take base and value strings, floats do not).
PROTOFIELD = {"bool": "bool", "int8": "int8", "uint8": "uint8", "int16": "int16", "uint16": "uint16",
              "int32": "int32", "uint32": "uint32", "int64": "int64", "uint64": "uint64",
              "float32": "float", "float64": "double"}

# What the Info column shows per layout: enum fields read at a fixed offset, and text fields.
# (The spec has no summary hint yet; these names are checked against it at generation time.)
# Robot-state packages: enum fields at a fixed offset. Messages: (field, text before it); by
# default their enum fields, then title and text.
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


def one_line(*texts: str) -> str:
    return " ".join(t.strip() for t in texts if t and t.strip())


def lua_version(v: Optional[ir.Version]) -> str:
    return "nil" if v is None else f"{v[0] * 1000 + v[1]}"


@dataclass
class PField:
    """One ProtoField declaration."""

    key: str            # key in the F table: "<owner>.<name>"
    ctor: str           # the whole ProtoField.xxx(...) expression


@dataclass
class LayoutView:
    var: str                      # Lua local holding the descriptor list
    doc: str
    lines: list[str]              # descriptor lines, already indented for the template
    code: Optional[int] = None
    name: str = ""
    label: str = ""


@dataclass
class DispatchView:
    name: str
    code: int
    label: str
    doc: str
    body_offset: int
    subtype_field: str
    header_layout: str
    subtype_vs: str
    subtypes: list = field(default_factory=list)   # (code, json name, label, header var, body var)


class _Builder:
    def __init__(self, p: ir.Protocol):
        self.p = p
        self.fields: list[PField] = []
        self.keys: set[str] = set()
        self.layouts: list[LayoutView] = []
        self.enum_var: dict[str, str] = {}

    # ---- fields ----

    def add_field(self, owner: str, name: str, ctor: str, args: str) -> str:
        key = f"{owner}.{name}"
        if key in self.keys:
            return f'F["{key}"]'
        self.keys.add(key)
        self.fields.append(PField(key, f"ProtoField.{ctor}({lua_str(wireshark_field(owner, name))}, {args})"))
        return f'F["{key}"]'

    def scalar_field(self, owner: str, name: str, s: ir.Scalar, enum: Optional[ir.Enum], doc: str,
                     label: Optional[str] = None, hex_base: bool = False) -> str:
        label = lua_str(label or name)
        desc = lua_str(doc)
        if s.is_float:
            return self.add_field(owner, name, PROTOFIELD[s.name], f"{label}, {desc}")
        if s.is_bool:
            return self.add_field(owner, name, "bool", f"{label}, base.NONE, nil, nil, {desc}")
        vs = self.enum_var[enum.name] if enum is not None else "nil"
        base = "base.HEX" if hex_base else "base.DEC"
        return self.add_field(owner, name, PROTOFIELD[s.name], f"{label}, {base}, {vs}, nil, {desc}")

    # ---- descriptors ----

    def descriptors(self, owner: str, struct: ir.Struct, keep: set[str], indent: str,
                    prefix: str = "", show: Optional[dict] = None) -> list[str]:
        lines = []
        show = show or {}
        for f in struct.fields:
            doc = one_line(f.doc, f.field_note)
            path = prefix + f.name
            if f.conditional:
                inner = self.descriptors(owner, _unconditional(f), keep, indent + "    ", prefix)
                cond = [f"k = \"cond\""]
                cond.append(f"present_if = {lua_str(f.present_if) if f.present_if else 'nil'}")
                cond.append(f"low = {lua_version(f.versions.low)}, high = {lua_version(f.versions.high)}")
                lines.append(f"{indent}{{ {', '.join(cond)}, fields = {{")
                lines += inner
                lines.append(f"{indent}}} }},")
                continue
            more = self.descriptor(owner, f, doc, path, keep, indent)
            if f.name in show:
                more[-1] = more[-1][:-3] + f", show = {lua_str(show[f.name])} }},"
            lines += more
        return lines

    def descriptor(self, owner: str, f: ir.AnyField, doc: str, path: str, keep: set[str], indent: str) -> list[str]:
        if isinstance(f, ir.ScalarField):
            pf = self.scalar_field(owner, f.name, f.scalar, f.enum, doc, hex_base=bool(f.bits) and not f.scalar.signed)
            extra = f", signed = {str(f.scalar.signed and not f.scalar.is_float).lower()}"
            if f.enum is not None:
                extra += f", vs = {self.enum_var[f.enum.name]}"
            if f.name in keep:
                extra += f", keep = {lua_str(f.name)}"
            if f.bits:
                bits = []
                for i, b in enumerate(f.bits):
                    bits.append(self.add_field(owner, f"{f.name}.{b}", "bool",
                                               f"{lua_str(b)}, {f.scalar.bits}, nil, 0x{1 << i:x}, "
                                               f"{lua_str(f'Bit {i} of {f.name}.')}"))
                return [f"{indent}{{ k = \"bits\", f = {pf}, n = {f.scalar.size}, path = {lua_str(path)}{extra}, "
                        f"bits = {{ {', '.join(bits)} }} }},"]
            return [f"{indent}{{ k = \"scalar\", f = {pf}, n = {f.scalar.size}, path = {lua_str(path)}{extra} }},"]
        if isinstance(f, ir.ArrayField):
            pf = self.scalar_field(owner, f.name, f.scalar, f.enum, doc)
            return [f"{indent}{{ k = \"array\", f = {pf}, n = {f.scalar.size}, count = {f.count}, "
                    f"path = {lua_str(path)} }},"]
        if isinstance(f, ir.GroupField):
            pf = self.add_field(owner, f.name, "none", f"{lua_str(f.item_label)}, {lua_str(doc)}")
            item_var = f"L_{owner}_{f.item.name}"
            item_lines = self.descriptors(owner, f.item, keep, "    ")
            self.layouts.append(LayoutView(item_var, one_line(f.doc) or f"One entry of {f.name}.", item_lines))
            count = str(f.count) if f.count is not None else "nil"
            size = str(f.item.fixed_size) if f.item.fixed_size is not None else "nil"
            return [f"{indent}{{ k = \"group\", f = {pf}, label = {lua_str(f.item_label)}, count = {count}, "
                    f"size = {size}, item = {item_var}, path = {lua_str(path)} }},"]
        if isinstance(f, ir.StringField):
            pf = self.add_field(owner, f.name, "string", f"{lua_str(f.name)}, base.UNICODE, {lua_str(doc)}")
            if f.length is None:
                return [f"{indent}{{ k = \"string\", f = {pf}, path = {lua_str(path)} }},"]
            return [f"{indent}{{ k = \"pstring\", f = {pf}, n = {f.length.size}, "
                    f"signed = {str(f.length.signed).lower()}, path = {lua_str(path)} }},"]
        if isinstance(f, ir.StringListField):
            pf = self.add_field(owner, f.name, "string", f"{lua_str(f.name)}, base.UNICODE, {lua_str(doc)}")
            return [f"{indent}{{ k = \"strings\", f = {pf}, term = {f.terminator}, path = {lua_str(path)} }},"]
        if isinstance(f, ir.BytesField):
            pf = self.add_field(owner, f.name, "bytes", f"{lua_str(f.name)}, base.NONE, {lua_str(doc)}")
            return [f"{indent}{{ k = \"bytes\", f = {pf}, path = {lua_str(path)} }},"]
        if isinstance(f, ir.SwitchField):
            default = self.scalar_field(owner, f.name, f.default, None, doc)
            cases = []
            for code, s in sorted(f.cases.items()):
                pf = self.scalar_field(owner, f"{f.name}_{s.name}", s, None,
                                       one_line(doc, f"(as {s.name}: {f.selector.name} is {code})"), label=f.name)
                cases.append(f"[{code}] = {{ f = {pf}, n = {s.size} }}")
            return [f"{indent}{{ k = \"switch\", sel = {lua_str(f.selector.name)}, path = {lua_str(path)}, "
                    f"default = {{ f = {default}, n = {f.default.size} }}, cases = {{ {', '.join(cases)} }} }},"]
        assert isinstance(f, ir.ValueListField)
        vf = self.value_fields(owner, f)
        return [f"{indent}{{ k = \"values\", term = {f.terminator}, path = {lua_str(path)}, vf = {vf} }},"]

    def value_fields(self, owner: str, f: ir.ValueListField) -> str:
        """The fields of typed values: one item per value, its type, and one field per data kind."""
        def add(key: str, name: str, ctor: str, label: str, rest: str) -> str:
            return f"{key} = " + self.add_field(owner, name, ctor, f"{lua_str(label)}, {rest}")

        parts = [
            add("item", f.name, "none", f.name, lua_str(one_line(f.doc))),
            add("type", "type", "string", "Type",
                "base.ASCII, " + lua_str("Value type name, from the table of the stream's software version.")),
            add("code", "type_code", "uint8", "Type code", "base.DEC, nil, nil, " + lua_str("Value type byte.")),
            add("count", "length", "int16", "Length",
                "base.DEC, nil, nil, " + lua_str("Items of a LIST, or bytes of a string.")),
            add("rows", "rows", "int16", "Rows", "base.DEC, nil, nil, " + lua_str("Rows of a MATRIX.")),
            add("cols", "columns", "int16", "Columns", "base.DEC, nil, nil, " + lua_str("Columns of a MATRIX.")),
            add("row", "row", "none", "Row", lua_str("One row of a MATRIX.")),
        ]
        for kind in sorted({lay.item.name for lay in self.p.value_layouts.values() if lay.item is not None}):
            pf = self.scalar_field(owner, f"value_{kind}", ir.SCALARS[kind], None, f"A value of type {kind}.",
                                   label="value")
            parts.append(f"[{lua_str(kind)}] = {pf}")
        parts.append(add("string", "value_string", "string", "value", "base.UNICODE, " + lua_str("A string value.")))
        return "{ " + ", ".join(parts) + " }"

    # ---- layouts and messages ----

    def keep_names(self, struct: ir.Struct) -> set[str]:
        out = set()
        for f in struct.fields:
            if f.present_if:
                out.add(f.present_if)
            if isinstance(f, ir.SwitchField):
                out.add(f.selector.name)
        return out

    def layout(self, owner: str, struct: ir.Struct, doc: str, show: Optional[dict] = None) -> str:
        var = f"L_{owner}"
        lines = self.descriptors(owner, struct, self.keep_names(struct), "    ", show=show)
        self.layouts.append(LayoutView(var, doc, lines))
        return var

    def package_info(self, layout: ir.Layout) -> list[dict]:
        """The spec's summary of a robot-state package: enum fields read at fixed offsets, so
        the Info column costs no field work."""
        wanted = [name for _, name in layout.summary]
        enums, offset = [], 0
        for f in layout.struct.fields:
            if offset is None:
                break
            if isinstance(f, ir.ScalarField) and f.enum is not None and f.name in wanted:
                enums.append(dict(offset=offset, size=f.scalar.size, signed=str(f.scalar.signed).lower(),
                                  vs=self.enum_var[f.enum.name], name=f.name))
            offset = offset + f.fixed_size if f.fixed_size is not None and not f.conditional else None
        if len(enums) != len(wanted):
            raise ValueError(f"lua target: the summary of {layout.name} must name enum fields at fixed offsets")
        return enums

    @staticmethod
    def message_show(layout: ir.Layout) -> dict:
        """Fields of a message the Info column shows, each with the text put before it."""
        return {name: before for before, name in layout.summary}

    def add_item(self, name: str, label: str, doc: str) -> str:
        """The subtree field of a package or message: ur.<name>, true when it is present."""
        if name in self.keys:
            raise ValueError(f"lua target: two items named {name}")
        self.keys.add(name)
        self.fields.append(PField(name, f"ProtoField.none({lua_str('ur.' + name)}, {lua_str(label)}, {lua_str(doc)})"))
        return f'F["{name}"]'

    def build(self) -> dict:
        p = self.p
        enums = []
        for e in p.enums.values():
            if e.versioned:
                continue
            var = f"VS_{e.name.upper()}"
            self.enum_var[e.name] = var
            enums.append(dict(var=var, doc=one_line(e.doc, e.field_note),
                              entries=[(v.value, lua_str(v.name)) for v in e.values]))
        # Header fields are ur.length and ur.type (and ur.package.*), outside the owner.field scheme.
        self.fields.append(PField("length", f"ProtoField.{PROTOFIELD[p.message_length.scalar.name]}(\"ur.length\", "
                                  f"\"Length\", base.DEC, nil, nil, {lua_str(p.message_length.doc)})"))
        self.fields.append(PField("type", f"ProtoField.{PROTOFIELD[p.message_type.scalar.name]}(\"ur.type\", "
                                  f"\"Type\", base.DEC, {self.enum_var[p.message_type_enum.name]}, nil, "
                                  f"{lua_str(p.message_type.doc)})"))
        self.fields.append(PField("package.length", f"ProtoField.{PROTOFIELD[p.package_length.scalar.name]}("
                                  f"\"ur.package.length\", \"Length\", base.DEC, nil, nil, {lua_str(p.package_length.doc)})"))
        self.fields.append(PField("package.type", f"ProtoField.{PROTOFIELD[p.package_type.scalar.name]}("
                                  f"\"ur.package.type\", \"Type\", base.DEC, {self.enum_var[p.package_type.enum.name]}, "
                                  f"nil, {lua_str(p.package_type.doc)})"))
        package_messages, dispatch = [], []
        for m in p.messages:
            if isinstance(m, ir.PackageListMessage):
                pkgs = []
                for pk in m.packages:
                    var = self.layout(pk.name, pk.struct, one_line(pk.doc, pk.field_note))
                    label = words(pk.name)
                    pkgs.append(dict(code=pk.code.value, var=var, name=pk.name, label=label,
                                     info=self.package_info(pk),
                                     item=self.add_item(pk.name, label, one_line(pk.doc))))
                package_messages.append(dict(name=m.name, code=m.code.value, label=words(m.name),
                                             doc=one_line(m.doc, m.field_note), packages=pkgs))
            else:
                sub_field = self.scalar_field(m.name, m.subtype.name, m.subtype.scalar, m.subtype.enum,
                                              one_line(m.subtype.doc, "Subtype of the message."))
                # The header then the subtype: shown as such when the subtype is unknown.
                hdr = self.layout(m.name, ir.Struct(m.header.name, m.header.doc, list(m.header.fields) + [m.subtype]),
                                  f"Header and subtype of every {words(m.name).lower()}.")
                view = DispatchView(m.name, m.code.value, words(m.name), one_line(m.doc, m.field_note),
                                    m.header_size + p.header_size, sub_field, hdr, self.enum_var[m.subtype_enum.name])
                for st in m.subtypes:
                    # The header fields of a subtype are filterable under its own name (ur.key.timestamp).
                    sub_hdr = f"L_{st.name}_header"
                    self.layouts.append(LayoutView(sub_hdr, f"Header of the {st.name} message.",
                                                   self.descriptors(st.name, m.header, set(), "    ")))
                    body = self.layout(st.name, st.struct, one_line(st.doc, st.field_note),
                                       show=self.message_show(st))
                    view.subtypes.append(dict(code=st.code.value, name=st.name, label=words(st.name),
                                              header=sub_hdr, body=body,
                                              needs_version=str(st.struct.needs_version).lower(),
                                              item=self.add_item(st.name, words(st.name), one_line(st.doc))))
                dispatch.append(view)
        for m in package_messages:
            for pk in m["packages"]:
                pk["refs"] = [f'F["{k}"]' for k in sorted(self.keys) if k.startswith(pk["name"] + ".")]
        version = self.version_reader()
        value_tables = []
        for t in p.value_type.tables:
            kinds = []
            for v in t.values:
                lay = p.value_layouts[v.name]
                kinds.append(dict(code=v.value, name=lua_str(v.name), layout=lua_str(lay.layout),
                                  item=lua_str(lay.item.name) if lay.item else "nil",
                                  size=lay.item.size if lay.item else 0,
                                  count=lay.count if lay.layout == "array" else 1,
                                  length=lay.length.size if lay.length else 0))
            value_tables.append(dict(low=lua_version(t.versions.low), high=lua_version(t.versions.high),
                                     versions=t.versions.describe(), kinds=kinds))
        return dict(enums=enums, fields=self.fields, layouts=self.layouts, package_messages=package_messages,
                    dispatch=dispatch, version=version, value_tables=value_tables,
                    known_codes=p.known_message_codes,
                    ports=",".join(str(x) for x in p.ports),
                    default_version=ir.version_text(p.default_version))

    def version_reader(self) -> dict:
        """Where the Version message keeps major and minor: fixed bytes and length-prefixed strings."""
        for m in self.p.messages:
            if not isinstance(m, ir.DispatchMessage):
                continue
            for st in m.subtypes:
                if not st.sets_version:
                    continue
                major, minor = st.sets_version
                steps, offset = [], m.header_size + self.p.header_size
                for f in st.struct.fields:
                    if f.name in (major, minor):
                        break
                    if isinstance(f, ir.StringField) and f.length is not None:
                        steps.append(dict(fixed=offset, prefix=f.length.size, signed=f.length.signed))
                        offset = 0
                    elif f.fixed_size is not None and not f.conditional:
                        offset += f.fixed_size
                    else:
                        raise ValueError("lua target: cannot locate the version numbers")
                names = [f.name for f in st.struct.fields]
                if names.index(minor) != names.index(major) + 1:
                    raise ValueError("lua target: minor_version must follow major_version")
                after = st.struct.fields[names.index(minor) + 1:]
                rest = sum(0 if f.conditional else f.min_size for f in after)
                return dict(message=m.code.value, subtype=st.code.value,
                            subtype_offset=m.header_size + self.p.header_size - 1,
                            steps=steps, tail=offset, rest=rest)
        raise ValueError("lua target: no layout sets the version")


def _unconditional(f: ir.AnyField) -> ir.Struct:
    import copy
    g = copy.copy(f)
    g.present_if = None
    g.versions = ir.ALL_VERSIONS
    return ir.Struct(f.name, "", [g])


def render(protocol_plan, banner: list[str]) -> dict[str, str]:
    p = protocol_plan.protocol
    env = environment("lua")
    model = _Builder(p).build()
    ctx = dict(banner=banner, p=p, title=lua_str(p.title), doc=one_line(p.doc), **model)
    return {OUT: env.get_template("urwire.lua.j2").render(**ctx)}
