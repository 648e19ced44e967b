"""epan target: the dissector model (dissector.py) -> templates/epan/packages/packet-ur.c.j2 +
runtime/epan/packages/ur_*.c, one native Wireshark dissector (generated/epan/packet-ur.c), the twin of
the Lua dissector (generated/lua/urwire.lua).

The two must be interchangeable (same protocol, field abbreviations, names, types, bases, value
strings, tree, Info column and expert infos), so both render the one model that decides the
fields, the layouts' descriptors and the forms of every type code; this module only spells it in
C: hf indices by a generated enum, the descriptors as const tables (as upstream's generated
packet-eti.c walks its fields), the forms and segments of the version axis as tables the runtime
looks a version up in. The code that walks the tables is hand-written C in runtime/epan/packages/ur_*.c,
joined after the generated tables.
"""
from __future__ import annotations

from typing import Optional

from ... import epan_c, ir
from ...emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ...lang.c import identifier as ident, literal as c_literal, prose as c_text, string as c_str, value_key
from . import dissector

OUT = "epan/packet-ur.c"
FOLDER = "epan"

# The hand-written runtime, in the order it is joined: types before the generated tables, the
# rest after them (runtime/epan/packages/ur_*.c), after the C library's reader of a version's text
# (runtime/c/common/). ur_wanted.c reads tshark's command line through the helpers every dissector
# shares (packet-ur-common.h: ur_tshark_fields_arguments()).
RUNTIME_TYPES = ("ur_types.c",)
C_RUNTIME = ("common/macros.h", "common/version_text.h", "common/version_text.c")
RUNTIME_CODE = ("ur_versions.c", "ur_wanted.c", "ur_items.c", "ur_walk.c",
                "ur_values.c", "ur_info.c", "ur_messages.c", "ur_stream.c", "ur_framing.c")
# The upstream copy (Wireshark's own tree) reads no command line: ur_wanted_upstream.c stands in for
# ur_wanted.c (every package built), with no ur.named_fields_only, and it needs no shared helper.
UPSTREAM_STAND_INS = {"ur_wanted.c": "ur_wanted_upstream.c"}

# The field type of a field: by its scalar (integer, float, bool), else by its shape.
FT = {"int8": "FT_INT8", "uint8": "FT_UINT8", "int16": "FT_INT16", "uint16": "FT_UINT16", "int32": "FT_INT32",
      "uint32": "FT_UINT32", "int64": "FT_INT64", "uint64": "FT_UINT64", "float32": "FT_FLOAT",
      "float64": "FT_DOUBLE", "bool": "FT_BOOLEAN", "flag": "FT_BOOLEAN", "none": "FT_NONE", "text": "FT_STRING",
      "bytes": "FT_BYTES"}

# Units of integer fields Wireshark names (epan/unit_strings.h) as the Lua twin shows them (" <unit>"
# after the value); the others are the dissector's own. Wireshark's volt reads "24V", without the
# space: the dissector's own " V" keeps the tree the Lua one's.
WIRESHARK_UNITS = {"s": "units_seconds", "ms": "units_milliseconds"}

# A value string this long is looked up by bisection (value_string_ext), as upstream does.
EXT_STRINGS = 32

ANY_LOW, ANY_HIGH = 0, 0xFFFFFFFF    # an open version bound


class _Builder:
    """The dissector model (dissector.py) spelled in C: hf indices, value_string arrays, descriptor
    arrays (a condition group's, bit lists, switches and typed values as arrays of their own)."""

    def __init__(self, d: dissector.Dissector):
        self.d = d
        self.field_index: dict[str, str] = {}
        self.arrays: list[dict] = []          # descriptor arrays, inner ones first
        self.bit_lists: list[dict] = []
        self.switches: list[dict] = []
        self.value_lists: list[dict] = []
        self.keep_slots: dict[str, int] = {}
        self.units: dict[str, str] = {}       # unit -> its own unit_name_string, where Wireshark has none
        self.labels: dict[tuple[str, str], epan_c.UnitLabel] = {}   # (float type, unit) -> its label function
        self.n_arrays = 0
        # Only the value strings the tables use are written: enums whose newest value strings a
        # field, descriptor or message names, and enums named by version.
        self.named: set[str] = set()
        self.by_version: set[str] = set()
        # Long value strings are looked up by bisection (value_string_ext).
        self.ext_tables = {self.vs_name(e, t) for e in d.enums for t in e.tables if len(t.entries) >= EXT_STRINGS}

    # ---- names ----

    def hf(self, key: Optional[str]) -> str:
        return "UR_HF_NONE" if key is None else self.field_index[key]

    @staticmethod
    def vs_name(enum: dissector.EnumStrings, table: Optional[dissector.ValueStrings] = None) -> str:
        """ur_vs_robot_mode, the newest table; ur_vs_robot_mode_upto3_2 an older one."""
        table = table or enum.newest
        return "ur_vs_" + ident(enum.name + (f"_{table.suffix}" if table.suffix else ""))

    @staticmethod
    def names_name(enum: dissector.EnumStrings) -> str:
        return f"ur_names_{ident(enum.name)}"

    def vs(self, enum: Optional[dissector.EnumStrings]) -> str:
        """An enum's newest value strings, noted as used; NULL for none."""
        if enum is None:
            return "NULL"
        self.named.add(enum.name)
        return self.vs_name(enum)

    def names(self, enum: Optional[dissector.EnumStrings]) -> str:
        """An enum's names by version, noted as used; NULL for an enum whose codes do not depend on it."""
        if enum is None or not enum.versioned:
            return "NULL"
        self.by_version.add(enum.name)
        return "&" + self.names_name(enum)

    @staticmethod
    def layout(name: Optional[str]) -> str:
        return "NULL" if name is None else f"&ur_layout_{ident(name)}"

    @staticmethod
    def part(name: str) -> str:
        return f"ur_part_{ident(name)}"

    def unit_of(self, unit: Optional[str]) -> Optional[str]:
        if unit is None:
            return None
        if unit in WIRESHARK_UNITS:
            return WIRESHARK_UNITS[unit]
        if unit not in self.units:
            self.units[unit] = f"ur_units_{len(self.units)}_{ident(unit) or 'unit'}"
        return self.units[unit]

    def label_of(self, ft: str, unit: str) -> str:
        """The label function (BASE_CUSTOM) of a float field with a unit (epan_c.UnitLabel)."""
        label = self.labels.setdefault((ft, unit), epan_c.unit_label("ur", unit, double=ft == "FT_DOUBLE"))
        return label.ident

    def keep_slot(self, name: Optional[str]) -> int:
        """A value kept for a later field (present_if, a switch's selector): its slot, 1-based."""
        if name is None:
            return 0
        return self.keep_slots.setdefault(name, len(self.keep_slots) + 1)

    # ---- fields ----

    def fields(self) -> list[dict]:
        out = []
        # The spec's fields, then the dissector's own (runtime/epan/ur_*.c names them UR_HF_<KEY>).
        for f in (*self.d.fields, *self.d.own_fields):
            const = f"UR_HF_{ident(f.key).upper()}"
            self.field_index[f.key] = const
            ft = FT[f.scalar] if f.shape in ("integer", "float", "bool") else FT[f.shape]
            strings, display = "NULL", "BASE_NONE"
            if f.shape == "integer":
                display = "BASE_HEX" if f.hex else "BASE_DEC"
                if f.unit:
                    display += "|BASE_UNIT_STRING"
                    strings = f"&{self.unit_of(f.unit)}"
                elif f.enum is not None:
                    name = self.vs(f.enum)
                    if name in self.ext_tables:
                        strings, display = f"VALS_EXT_PTR(&{name}_ext)", display + "|BASE_EXT_STRING"
                    else:
                        strings = f"VALS({name})"
            # Wireshark 4.0 shows no unit string of a float field (BASE_UNIT_STRING shows on
            # integers only): its label function does.
            elif f.shape == "float" and f.unit:
                display = "BASE_CUSTOM"
                strings = f"CF_FUNC({self.label_of(ft, f.unit)})"
            elif f.shape == "flag":
                display = str(f.bits)
            # A text field is BASE_NONE: 4.0 has no STR_UNICODE; Lua base.UNICODE and base.ASCII are both that.
            out.append(dict(const=const, label=f.label, abbr=f.filter, ft=ft, display=display, strings=strings,
                            mask=f"0x{f.mask:x}" if f.shape == "flag" else "0x0", blurb=f.description))
        return out

    def enums(self) -> list[dict]:
        """Every enum's value strings that a field, descriptor or message uses; a versioned enum's
        tables by version where something names it by version."""
        out = []
        for e in self.d.enums:
            by_version = e.name in self.by_version
            tables = []
            for t in e.tables:
                if not (by_version or (t is e.newest and e.name in self.named)):
                    continue
                name = self.vs_name(e, t)
                entries = sorted(t.entries, key=lambda kv: kv[0] & 0xFFFFFFFF)
                tables.append(dict(name=name, versions=t.versions, low=self.low(t.low), high=self.high(t.high),
                                   ext=name in self.ext_tables, entries=[(value_key(v), n) for v, n in entries]))
            if not tables:
                continue
            out.append(dict(name=e.name, doc=e.doc, versioned=e.versioned and by_version, tables=tables,
                            names=self.names_name(e), newest=self.vs_name(e)))
        return out

    @staticmethod
    def low(v: Optional[int]) -> int:
        return ANY_LOW if v is None else v

    @staticmethod
    def high(v: Optional[int]) -> int:
        return ANY_HIGH if v is None else v

    # ---- descriptors ----

    def array(self, name: str, descriptors: list[dissector.AnyDescriptor]) -> str:
        """A descriptor array (its inner arrays first); its C name."""
        rows = [self.descriptor(name, d) for d in descriptors]
        self.arrays.append(dict(name=f"ur_desc_{name}", layout=f"ur_layout_{name}", rows=rows,
                                first=f"ur_desc_{name}" if rows else "NULL"))
        return name

    def descriptor(self, owner: str, d: dissector.AnyDescriptor) -> list[str]:
        row = dict(kind="UR_D_" + d.kind.upper(), hf="UR_HF_NONE", n=0, count=0, size=0, flags=[], keep=0,
                   low=ANY_LOW, high=ANY_HIGH, path=None, show=None, label=None, vs="NULL", names="NULL",
                   inner="NULL", bits="NULL", sw="NULL", values="NULL")
        if isinstance(d, dissector.Cond):
            self.n_arrays += 1
            inner = self.array(f"{owner}_cond{self.n_arrays}", d.fields)
            row.update(keep=self.keep_slot(d.present_if), low=self.low(d.low), high=self.high(d.high),
                       inner=f"&ur_layout_{inner}", count=len(d.fields))
            return self.members(row)
        row.update(path=d.path, show=d.show)
        if getattr(d, "field", None) is not None:
            row["hf"] = self.hf(d.field)
        if isinstance(d, dissector.Read):
            flags = [flag for flag, on in (("UR_SIGNED", d.signed), ("UR_FLOAT", d.float), ("UR_VALUE", d.value))
                     if on]
            row.update(n=d.size, flags=flags, names=self.names(d.enum), label=d.label if d.by_version else None)
            if isinstance(d, dissector.Scalar):
                row.update(vs=self.vs(d.enum), keep=self.keep_slot(d.keep))
            if isinstance(d, dissector.Array):
                row.update(count=d.count)
            if isinstance(d, dissector.Bits):
                name = f"{owner}_bits{len(self.bit_lists)}"
                self.bit_lists.append(dict(name=name, hfs=[self.hf(b) for b in d.bits]))
                row.update(bits=f"ur_bits_{name}", count=len(d.bits))
        elif isinstance(d, dissector.Group):
            row.update(label=d.label, count=d.count or 0, size=d.size or 0, inner=self.layout(d.item))
        elif isinstance(d, dissector.PString):
            row.update(n=d.size, flags=["UR_SIGNED"] if d.signed else [])
        elif isinstance(d, dissector.Strings):
            row.update(n=d.term)
        elif isinstance(d, dissector.Switch):
            name = f"{owner}_switch{len(self.switches)}"
            cases = [dict(code=c.code, hf=self.hf(c.field), n=c.size) for c in d.cases]
            self.switches.append(dict(name=name, default=dict(hf=self.hf(d.default.field), n=d.default.size),
                                      cases=cases))
            row.update(keep=self.keep_slot(d.sel), sw=f"&ur_switch_{name}")
        elif isinstance(d, dissector.Values):
            name = f"{owner}_values{len(self.value_lists)}"
            kinds = dict(d.kinds)
            self.value_lists.append(dict(name=name, roles={r: self.hf(k) for r, k in d.roles},
                                         kinds=[(const, self.hf(kinds.get(k))) for k, const in KIND_CONST.items()],
                                         string=self.hf(d.string)))
            row.update(n=d.term, label=d.label, values=f"&ur_values_{name}")
        return self.members(row)

    @staticmethod
    def members(row: dict) -> list[str]:
        """A descriptor's designated initialisers, those that differ from the zero of a static."""
        out = []
        for key, value in row.items():
            if key == "flags":
                value = "|".join(value) or "0"
            if key in ("path", "show", "label"):
                if value is not None:
                    out.append(f".{key} = {c_str(value)}")
            elif key in ("low", "high"):
                if row["kind"] == "UR_D_COND":
                    out.append(f".{key} = {value}u")
            elif value not in (0, "0", "NULL"):
                out.append(f".{key} = {value}")
        return out

    def layouts(self) -> None:
        for layout in self.d.layouts:
            self.array(ident(layout.name), layout.descriptors)

    # ---- messages ----

    def forms(self, owner: str, codes: list[dissector.Code]) -> list[dict]:
        out = []
        for c in codes:
            forms = [dict(part="&" + self.part(f.part.name), sizes=f.sizes, min=f.min, rep=ir.version_number(f.rep),
                          versions=f.versions) for f in c.forms]
            out.append(dict(name=f"ur_forms_{owner}_{c.code}", code=c.code, single=c.single, summary=c.summary,
                            segments=c.segments, by_length=c.by_length, forms=forms))
        return out

    def messages(self) -> list[dict]:
        out = []
        for m in self.d.messages:
            owner = ident(m.forms_table)
            parts = [dict(name=self.part(part.name), key=part.key, label=part.label, item=self.hf(part.item),
                          layout=self.layout(part.layout), header=self.layout(part.header), summary=part.summary,
                          needs_version=part.needs_version) for part in m.parts]
            view = dict(kind="UR_M_" + m.kind.upper(), code=m.code, label=m.label, doc=m.doc, owner=owner,
                        parts=parts, codes=self.forms(owner, m.codes), body_offset=m.body_offset,
                        header=self.layout(m.header), subtype_hf=self.hf(m.subtype_field),
                        subtype_label=m.subtype_label, names=self.vs(m.names), tables=self.names(m.names),
                        length_hf=self.hf(m.length), type_hf=self.hf(m.type), needs_version=m.needs_version)
            out.append(view)
        return out

    def value_tables(self) -> list[dict]:
        out = []
        for i, t in enumerate(self.d.value_tables):
            kinds = [dict(code=k.code, name=k.name, layout="UR_V_" + k.layout.upper(),
                          item=KIND_CONST[k.item] if k.item else "UR_VK_NONE", n=k.size, count=k.count,
                          len=k.length) for k in t.kinds]
            out.append(dict(name=f"ur_value_kinds_{i}", low=self.low(t.low), high=self.high(t.high),
                            versions=t.versions, min_size=t.min_size, kinds=kinds))
        return out

    def build(self) -> dict:
        d = self.d
        fields = self.fields()
        self.layouts()
        messages = self.messages()
        m_names, m_tables = self.vs(d.message_types), self.names(d.message_types)
        enums = self.enums()
        return dict(enums=enums, fields=fields, arrays=self.arrays, bit_lists=self.bit_lists,
                    switches=self.switches, value_lists=self.value_lists, messages=messages,
                    value_tables=self.value_tables(), value_kinds=list(KIND_CONST.items()),
                    units=sorted(self.units.items(), key=lambda kv: kv[1]), keep_slots=len(self.keep_slots),
                    labels=list(self.labels.values()),
                    known_codes=d.known_codes, message_type_names=m_names,
                    message_type_tables=m_tables, constants=d.constants, title=d.title,
                    version=d.version, bugfix=d.version.bugfix,
                    experts=[(e.name, e.filter, f"PI_{e.group.upper()}", f"PI_{e.severity.upper()}", e.text)
                             for e in d.experts],
                    segment_starts=[ir.version_number(v) for v in d.segment_starts],
                    default_version=ir.version_number(d.default_version))


# The scalar kinds a typed value can hold, in the order of the runtime's UR_VK_* (ur_types.c).
VALUE_KINDS = ("bool", "float32", "float64", "int16", "int32", "int64", "int8", "uint16", "uint32", "uint64",
               "uint8")
if set(VALUE_KINDS) != set(ir.SCALARS):
    raise ValueError(f"epan target: the runtime's value kinds {VALUE_KINDS} differ from the spec's scalars")
KIND_CONST = {name: f"UR_VK_{name.upper()}" for name in VALUE_KINDS}


def runtime_file(name: str) -> str:
    """Where a runtime file of this kind lives under runtime/epan."""
    return f"packages/{name}"


def runtime(names: tuple[str, ...]) -> list[str]:
    return [runtime_section(FOLDER, runtime_file(name)) for name in names]


def runtime_code(upstream: bool) -> tuple[str, ...]:
    """The runtime joined after the tables: urwire's own, or the upstream copy's."""
    if not upstream:
        return RUNTIME_CODE
    return tuple(UPSTREAM_STAND_INS.get(name, name) for name in RUNTIME_CODE)


def check_runtime(code: tuple[str, ...]) -> None:
    """Every ur_*.c of the runtime is joined by one copy or the other, and the files this copy
    joins are there (Wireshark's tree holds only the upstream copy's)."""
    folder = RUNTIME_FOLDER / FOLDER
    known = set(RUNTIME_TYPES + runtime_code(False) + runtime_code(True))
    own = {p.name for p in (folder / "packages").glob("ur_*.c")}
    missing = [name for name in RUNTIME_TYPES + code if not (folder / runtime_file(name)).exists()]
    if own - known or missing:
        raise ValueError(f"epan target: runtime files {sorted(own - known)} are in no joining order, "
                         f"{missing} are missing")


def render(protocol_plan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """packet-ur.c; `upstream`: the copy for Wireshark's tree, which reads no command line, in its
    development branch's style."""
    code = runtime_code(upstream)
    check_runtime(code)
    env = environment(FOLDER)
    env.filters["c"] = c_literal
    env.filters["c_text"] = c_text
    model = _Builder(dissector.dissector(protocol_plan)).build()
    ctx = dict(banner=banner, types=runtime(RUNTIME_TYPES),
               code=[runtime_section("c", name) for name in C_RUNTIME] + runtime(code),
               named_fields_preference=not upstream, shared_header=None if upstream else epan_c.SHARED_HEADER,
               any_low=ANY_LOW, any_high=ANY_HIGH, **model)
    text = env.get_template("packages/packet-ur.c.j2").render(**ctx)
    return {OUT: epan_c.development_branch(text) if upstream else text}
