"""epan target: the plan -> a view model of plain data -> templates/epan/packet-ur.c.j2 +
runtime/epan/ur_*.c, one native Wireshark dissector (generated/epan/packet-ur.c), the twin of
the Lua dissector (generated/lua/urwire.lua).

The two must be interchangeable (same protocol, field abbreviations, names, types, bases, value
strings, tree, Info column and expert infos), so the fields, the layouts' descriptors and the
forms of every type code come from the Lua target's model (lua.view_model), which decides them
once over the plan; this module only maps that model to C: hf indices by a generated enum, the
descriptors as const tables (as upstream's generated packet-eti.c walks its fields), the forms and
segments of the version axis as tables the runtime looks a version up in. The code that walks
the tables is hand-written C in runtime/epan/ur_*.c, joined after the generated tables.
"""
from __future__ import annotations

import re
from typing import Optional

from .. import epan_c, ir, plan, wrap
from ..epan_c import value_literal
from ..emit import RUNTIME as RUNTIME_FOLDER, environment, runtime_section
from ..errors import SpecError
from ..view import Step
from . import lua

OUT = "epan/packet-ur.c"
FOLDER = "epan"

# The hand-written runtime, in the order it is joined: types before the generated tables, the
# rest after them (runtime/epan/packages/ur_*.c, and runtime/epan/common/tshark_fields*.c, which every
# kind's dissector joins), after the C library's reader of a version's text (runtime/c/common/).
RUNTIME_TYPES = ("ur_types.c",)
C_RUNTIME = ("common/macros.h", "common/version_text.h", "common/version_text.c")
RUNTIME_CODE = ("ur_versions.c", "tshark_fields.c", "ur_wanted.c", "ur_items.c", "ur_walk.c",
                "ur_values.c", "ur_info.c", "ur_messages.c", "ur_stream.c", "ur_framing.c")
# The upstream copy (Wireshark's own tree) reads no command line: it joins no tshark_fields.c, and
# ur_wanted_upstream.c stands in for ur_wanted.c (every package built), with no ur.named_fields_only.
UPSTREAM_STAND_INS = {"tshark_fields.c": None, "ur_wanted.c": "ur_wanted_upstream.c"}

FT = {"int8": "FT_INT8", "uint8": "FT_UINT8", "int16": "FT_INT16", "uint16": "FT_UINT16", "int32": "FT_INT32",
      "uint32": "FT_UINT32", "int64": "FT_INT64", "uint64": "FT_UINT64", "float": "FT_FLOAT",
      "double": "FT_DOUBLE", "bool": "FT_BOOLEAN", "none": "FT_NONE", "string": "FT_STRING", "bytes": "FT_BYTES"}

# Units of integer fields Wireshark names (epan/unit_strings.h) as the Lua twin shows them (" <unit>"
# after the value); the others are the dissector's own. Wireshark's volt reads "24V", without the
# space: the dissector's own " V" keeps the tree the Lua one's.
WIRESHARK_UNITS = {"s": "units_seconds", "ms": "units_milliseconds"}

# A value string this long is looked up by bisection (value_string_ext), as upstream does.
EXT_STRINGS = 32

# The dissector's own fields and expert infos, after the spec's: the same as the Lua dissector
# declares (runtime/lua/declare.lua), in the same order.
OWN_FIELDS = [
    ("raw", "Raw", "ur.raw", "FT_BYTES", "BASE_NONE",
     "Bytes kept whole: a type the spec does not lay out, or a part that could not be read."),
    ("extra", "Extra bytes", "ur.extra", "FT_BYTES", "BASE_NONE",
     "Bytes after the known layout of a package or message."),
    ("skipped", "Skipped bytes", "ur.skipped", "FT_BYTES", "BASE_NONE",
     "Bytes skipped while looking for the next plausible message header."),
    ("software_version", "Software version", "ur.software_version", "FT_STRING", "BASE_NONE",
     "The software version this message is read with (its layouts, enum names and value types): the stream's "
     "Version message, else the ur.version preference, else what the layout sizes show (\"3.2 to 3.4 (from "
     "layout sizes)\"), else the default."),
    ("version_assumed", "Version assumed", "ur.version_assumed", "FT_BOOLEAN", "BASE_NONE",
     "True when no Version message was seen on this stream: the version comes from the ur.version preference, "
     "the layout sizes or the default."),
    ("unknown_package", "Unknown package", "ur.unknown_package", "FT_NONE", "BASE_NONE",
     "A sub-package type the spec does not lay out, kept raw."),
    ("urscript", "URScript", "ur.urscript", "FT_STRING", "BASE_NONE",
     "Bytes from the client to the robot: URScript program text."),
]

EXPERTS = [
    ("bad_length", "ur.bad_length", "PI_MALFORMED", "PI_ERROR", "Message length out of range (resynchronising)"),
    ("bad_type", "ur.bad_type", "PI_MALFORMED", "PI_ERROR", "Unknown message type (resynchronising)"),
    ("malformed", "ur.malformed", "PI_MALFORMED", "PI_ERROR", "Package or message too short or malformed"),
    ("extra", "ur.extra_bytes", "PI_PROTOCOL", "PI_WARN", "Bytes after the known layout"),
    ("unknown", "ur.unknown", "PI_UNDECODED", "PI_NOTE", "Type not laid out by the spec, kept raw"),
    ("assumed", "ur.assumed_version", "PI_ASSUMPTION", "PI_NOTE",
     "Software version assumed (no Version message seen)"),
    ("version_range", "ur.version_out_of_range", "PI_PROTOCOL", "PI_WARN",
     "Version message number out of range: set aside, the stream is read as major.minor"),
    ("by_length", "ur.layout_by_length", "PI_ASSUMPTION", "PI_NOTE",
     "Layout chosen by its length, not by the software version"),
    ("items_hidden", "ur.items_hidden", "PI_UNDECODED", "PI_NOTE", "More tree items than a message shows"),
    ("internal", "ur.internal_error", "PI_MALFORMED", "PI_ERROR", "urwire dissector error"),
]

ANY_LOW, ANY_HIGH = 0, 0xFFFFFFFF    # an open version bound


def c_str(text: str) -> str:
    """A C string literal; bytes outside ASCII as octal escapes, so the file is ASCII-clean."""
    out = []
    for b in text.encode("utf-8"):
        ch = chr(b)
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch == "\n":
            out.append("\\n")
        elif b < 32 or b > 126:
            out.append(f"\\{b:03o}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def c_text(text: str, indent: str) -> str:
    """A long C string literal as adjacent literals, one per line, at most PROSE wide."""
    pieces = wrap.lines(text, "", "", wrap.PROSE - len(indent) - 4)
    words = [p + (" " if i < len(pieces) - 1 else "") for i, p in enumerate(pieces)]
    return ("\n" + indent).join(c_str(w) for w in words)


def c_literal(value) -> str:
    if value is None:
        return "NULL"
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return c_str(value)
    raise TypeError(f"epan target: no C literal for {value!r}")


def ident(text: str) -> str:
    """A C identifier part from a Lua table name or field key."""
    return re.sub(r"[^0-9A-Za-z]+", "_", text).strip("_").lower()


class _Builder:
    def __init__(self, protocol_plan: plan.ProtocolPlan):
        self.plan = protocol_plan
        self.p = protocol_plan.protocol
        self.model = lua.view_model(protocol_plan)
        self.model_fields = {pf.key: pf for pf in self.model["fields"]}
        self.field_index: dict[str, str] = {}
        self.arrays: list[dict] = []          # descriptor arrays, inner ones first
        self.bit_lists: list[dict] = []
        self.switches: list[dict] = []
        self.value_lists: list[dict] = []
        self.keep_slots: dict[str, int] = {}
        self.units: dict[str, str] = {}       # unit -> its own unit_name_string, where Wireshark has none
        self.labels: dict[tuple[str, str], epan_c.UnitLabel] = {}   # (float type, unit) -> its label function
        self.labelled: set[str] = set()       # the float fields whose label function shows their unit
        self.n_arrays = 0
        self.used: set[str] = set()           # value strings and names by version that the tables use

    # ---- names ----

    def hf(self, key: Optional[str]) -> str:
        return "UR_HF_NONE" if key is None else self.field_index[key]

    def table(self, lua_var: Optional[str]) -> str:
        """VS.ROBOT_MODE -> ur_vs_robot_mode; NAMES.X -> &ur_names_x; L.x -> &ur_layout_x; the
        value strings and names by version are noted as used (only those are written)."""
        if lua_var is None:
            return "NULL"
        kind, _, name = lua_var.partition(".")
        if kind in ("VS", "NAMES"):
            self.used.add(f"ur_{kind.lower()}_{ident(name)}")
        return {"VS": f"ur_vs_{ident(name)}", "NAMES": f"&ur_names_{ident(name)}",
                "L": f"&ur_layout_{ident(name)}", "PART": f"&ur_part_{ident(name)}"}[kind]

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

    def check_unit(self, key: Optional[str], unit: Optional[str]) -> None:
        """A read's unit is its field's, which the field's label shows (the runtime adds none)."""
        pf = self.model_fields.get(key) if key is not None else None
        shown = lua.unit_text(pf.unit) if pf is not None and pf.key in self.labelled else None
        if unit != shown:
            raise ValueError(f"epan target: {key} is read with the unit {unit!r}, its label shows {shown!r}")

    def keep_slot(self, name: Optional[str]) -> int:
        """A value kept for a later field (present_if, a switch's selector): its slot, 1-based."""
        if name is None:
            return 0
        return self.keep_slots.setdefault(name, len(self.keep_slots) + 1)

    # ---- fields ----

    def fields(self) -> list[dict]:
        out = []
        for pf in self.model["fields"]:
            const = f"UR_HF_{ident(pf.key).upper()}"
            self.field_index[pf.key] = const
            ft = FT[pf.ctor]
            strings, display = "NULL", "BASE_NONE"
            if pf.shape == "integer":
                display = "BASE_HEX" if pf.base == "HEX" else "BASE_DEC"
                if pf.unit:
                    display += "|BASE_UNIT_STRING"
                    strings = f"&{self.unit_of(pf.unit)}"
                elif pf.enum:
                    strings = self.value_strings_ref(pf.vs)
                    if strings.startswith("VALS_EXT_PTR"):
                        display += "|BASE_EXT_STRING"
            # Wireshark 4.0 shows no unit string of a float field (BASE_UNIT_STRING shows on
            # integers only): its label function does.
            elif pf.shape == "float" and pf.unit:
                display = "BASE_CUSTOM"
                strings = f"CF_FUNC({self.label_of(ft, pf.unit)})"
                self.labelled.add(pf.key)
            elif pf.shape == "flag":
                display = str(pf.bits)
            elif pf.shape == "text":
                display = "BASE_NONE"   # 4.0 has no STR_UNICODE; Lua base.UNICODE and base.ASCII are both that
            out.append(dict(const=const, label=pf.label, abbr=pf.abbr, ft=ft, display=display, strings=strings,
                            mask=f"0x{pf.mask:x}" if pf.shape == "flag" else "0x0", blurb=pf.desc))
        for key, label, abbr, ft, display, blurb in OWN_FIELDS:
            const = f"UR_HF_{key.upper()}"
            self.field_index["!" + key] = const
            out.append(dict(const=const, label=label, abbr=abbr, ft=ft, display=display, strings="NULL",
                            mask="0x0", blurb=blurb))
        return out

    def value_strings_ref(self, lua_var: str) -> str:
        name = self.table(lua_var)
        if name in self.ext_tables:
            return f"VALS_EXT_PTR(&{name}_ext)"
        return f"VALS({name})"

    def enums(self) -> list[dict]:
        """Every enum's value strings that a field, descriptor or message uses; a versioned enum's
        tables by version where something names it by version."""
        out = []
        for e in self.model["enums"]:
            tables = []
            for t in e["tables"]:
                name = f"ur_vs_{ident(t['var'][3:])}"
                entries = sorted(t["entries"], key=lambda kv: kv[0] & 0xFFFFFFFF)
                ext = name in self.ext_tables
                if name not in self.used and f"ur_names_{ident(e['upper'])}" not in self.used:
                    continue
                tables.append(dict(name=name, versions=t["versions"], low=self.low(t["low"]), high=self.high(t["high"]),
                                   ext=ext,
                                   entries=[(value_literal(v), n) for v, n in entries]))
            if not tables:
                continue
            out.append(dict(name=e["name"], doc=e["doc"], versioned=e["versioned"] and
                            f"ur_names_{ident(e['upper'])}" in self.used, tables=tables,
                            names=f"ur_names_{ident(e['upper'])}", newest=f"ur_vs_{ident(e['upper'])}"))
        return out

    @staticmethod
    def low(v: Optional[int]) -> int:
        return ANY_LOW if v is None else v

    @staticmethod
    def high(v: Optional[int]) -> int:
        return ANY_HIGH if v is None else v

    # ---- descriptors ----

    def array(self, name: str, steps: list[Step]) -> str:
        """A descriptor array (its inner arrays first); its C name."""
        rows = [self.descriptor(name, d) for d in steps]
        self.arrays.append(dict(name=f"ur_desc_{name}", layout=f"ur_layout_{name}", rows=rows,
                                first=f"ur_desc_{name}" if rows else "NULL"))
        return name

    def descriptor(self, owner: str, d: Step) -> dict:
        row = dict(kind="UR_D_" + d.kind.upper(), hf="UR_HF_NONE", n=0, count=0, size=0, flags=[], keep=0,
                   low=ANY_LOW, high=ANY_HIGH, path=None, show=None, label=None, vs="NULL", names="NULL",
                   inner="NULL", bits="NULL", sw="NULL", values="NULL")
        data = d.data
        if d.kind == "cond":
            self.n_arrays += 1
            inner = self.array(f"{owner}_cond{self.n_arrays}", data["fields"])
            row.update(keep=self.keep_slot(data["present_if"]), low=self.low(data["low"]), high=self.high(data["high"]),
                       inner=f"&ur_layout_{inner}", count=len(data["fields"]))
            return self.members(row)
        row.update(path=data.get("path"), show=data.get("show"))
        if "field" in data:
            row["hf"] = self.hf(data["field"])
        if d.kind in ("scalar", "bits", "array"):
            flags = []
            if data.get("signed"):
                flags.append("UR_SIGNED")
            if data.get("float"):
                flags.append("UR_FLOAT")
            if data.get("value"):
                flags.append("UR_VALUE")
            self.check_unit(data.get("field"), data.get("unit"))
            row.update(n=data["size"], flags=flags, vs=self.table(data.get("vs")),
                       names=self.table(data.get("tables")), label=data.get("label"),
                       keep=self.keep_slot(data.get("keep")), count=data.get("count", 0))
            if d.kind == "bits":
                name = f"{owner}_bits{len(self.bit_lists)}"
                self.bit_lists.append(dict(name=name, hfs=[self.hf(b) for b in data["bits"]]))
                row.update(bits=f"ur_bits_{name}", count=len(data["bits"]))
        elif d.kind == "group":
            row.update(label=data["label"], count=data["count"] or 0, size=data["size"] or 0,
                       inner=self.table(data["item"]))
        elif d.kind == "pstring":
            row.update(n=data["size"], flags=["UR_SIGNED"] if data["signed"] else [])
        elif d.kind == "strings":
            row.update(n=data["term"])
        elif d.kind == "switch":
            name = f"{owner}_switch{len(self.switches)}"
            default = data["default"]
            for c in [*data["cases"], default]:
                self.check_unit(c["field"], c.get("unit"))
            cases = [dict(code=c["code"], hf=self.hf(c["field"]), n=c["size"]) for c in data["cases"]]
            self.switches.append(dict(name=name, default=dict(hf=self.hf(default["field"]), n=default["size"]),
                                      cases=cases))
            row.update(keep=self.keep_slot(data["sel"]), sw=f"&ur_switch_{name}")
        elif d.kind == "values":
            name = f"{owner}_values{len(self.value_lists)}"
            roles = dict(data["roles"])
            kinds = dict(data["kinds"])
            self.value_lists.append(dict(name=name, roles={r: self.hf(k) for r, k in roles.items()},
                                         kinds=[(const, self.hf(kinds.get(k))) for k, const in KIND_CONST.items()],
                                         string=self.hf(data["string"])))
            row.update(n=data["term"], label=data["label"], values=f"&ur_values_{name}")
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
        for view in self.model["layouts"]:
            self.array(ident(view.var[2:]), view.descriptors)

    # ---- messages ----

    def forms(self, owner: str, codes: list[dict]) -> list[dict]:
        out = []
        for c in codes:
            name = f"ur_forms_{owner}_{c['code']}"
            forms = [dict(part=self.table(f["part"]), sizes=f["sizes"], min=f["min"],
                          rep=ir.version_number(ir.parse_version(f["rep"])), versions=f["versions"])
                     for f in c["forms"]]
            out.append(dict(name=name, code=c["code"], single=c["single"], summary=c.get("summary", False),
                            segments=c["segments"], by_length=[(b["size"], b["form"]) for b in c["by_length"]],
                            forms=forms))
        return out

    def messages(self) -> list[dict]:
        out = []
        for m in self.model["messages"]:
            owner = ident(m.var)
            parts = []
            for part in m.parts:
                parts.append(dict(name=self.table(part["var"])[1:], key=part["name"], label=part["label"],
                                  item=self.hf(part["item"]), layout=self.table(part["layout"]),
                                  header=self.table(part.get("header")), summary=part.get("summary", False),
                                  needs_version=part.get("needs_version", False)))
            view = dict(kind="UR_M_" + m.kind.upper(), code=m.code, label=m.label, doc=m.doc, owner=owner,
                        parts=parts, codes=self.forms(owner, m.codes), body_offset=0, header="NULL",
                        subtype_hf="UR_HF_NONE", subtype_label=None, names="NULL", tables="NULL",
                        length_hf="UR_HF_NONE", type_hf="UR_HF_NONE", needs_version=False)
            if m.kind == "packages":
                view.update(names=self.table(m.types), tables=self.table(m.type_tables),
                            length_hf=self.hf(m.length), type_hf=self.hf(m.type), needs_version=m.needs_version)
            elif m.kind == "subtypes":
                view.update(body_offset=m.body_offset, header=self.table(m.header), subtype_hf=self.hf(m.subtype_field),
                            subtype_label=m.subtype_label, names=self.table(m.subtype_names),
                            tables=self.table(m.subtype_tables))
            else:
                view.update(body_offset=m.body_offset)
            out.append(view)
        return out

    def value_tables(self) -> list[dict]:
        out = []
        for i, t in enumerate(self.model["value_tables"]):
            kinds = [dict(code=k["code"], name=k["name"], layout="UR_V_" + k["layout"].upper(),
                          item=KIND_CONST[k["item"]] if k["item"] else "UR_VK_NONE", n=k["size"], count=k["count"],
                          len=k["length"]) for k in t["kinds"]]
            out.append(dict(name=f"ur_value_kinds_{i}", low=self.low(t["low"]), high=self.high(t["high"]),
                            versions=t["versions"], min_size=t["min_size"], kinds=kinds))
        return out

    def build(self) -> dict:
        # Long value strings are looked up by bisection (value_string_ext).
        self.ext_tables = {f"ur_vs_{ident(t['var'][3:])}" for e in self.model["enums"] for t in e["tables"]
                           if len(t["entries"]) >= EXT_STRINGS}
        self.used.clear()
        fields = self.fields()
        self.layouts()
        messages = self.messages()
        m = self.model
        m_names, m_tables = self.table(m["message_type_names"]), self.table(m["message_type_tables"])
        enums = self.enums()
        version = m["version"]
        return dict(enums=enums, fields=fields, arrays=self.arrays, bit_lists=self.bit_lists,
                    switches=self.switches, value_lists=self.value_lists, messages=messages,
                    value_tables=self.value_tables(), value_kinds=list(KIND_CONST.items()),
                    units=sorted(self.units.items(), key=lambda kv: kv[1]), keep_slots=len(self.keep_slots),
                    labels=list(self.labels.values()),
                    known_codes=m["known_codes"], message_type_names=m_names,
                    message_type_tables=m_tables, constants=m["constants"],
                    version=version, bugfix=version["bugfix"], experts=EXPERTS,
                    segment_starts=[ir.version_number(s.first) for s in self.plan.segments if s.first],
                    default_version=ir.version_number(self.p.default_version))


# The scalar kinds a typed value can hold, in the order of the runtime's UR_VK_* (ur_types.c).
VALUE_KINDS = ("bool", "float32", "float64", "int16", "int32", "int64", "int8", "uint16", "uint32", "uint64",
               "uint8")
if set(VALUE_KINDS) != set(ir.SCALARS):
    raise ValueError(f"epan target: the runtime's value kinds {VALUE_KINDS} differ from the spec's scalars")
KIND_CONST = {name: f"UR_VK_{name.upper()}" for name in VALUE_KINDS}


def runtime_file(name: str) -> str:
    """Where a runtime file of this kind lives under runtime/epan: its own folder, or the shared one."""
    return f"common/{name}" if name.startswith("tshark_fields") else f"packages/{name}"


def runtime(names: tuple[str, ...]) -> list[str]:
    return [runtime_section(FOLDER, runtime_file(name)) for name in names]


def runtime_code(upstream: bool) -> tuple[str, ...]:
    """The runtime joined after the tables: urwire's own, or the upstream copy's."""
    if not upstream:
        return RUNTIME_CODE
    joined = (UPSTREAM_STAND_INS.get(name, name) for name in RUNTIME_CODE)
    return tuple(name for name in joined if name is not None)


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
    """packet-ur.c; `upstream`: the copy for Wireshark's tree, which reads no command line."""
    code = runtime_code(upstream)
    check_runtime(code)
    env = environment(FOLDER)
    env.filters["c"] = c_literal
    env.filters["c_text"] = c_text
    model = _Builder(protocol_plan).build()
    ctx = dict(banner=banner, p=protocol_plan.protocol, types=runtime(RUNTIME_TYPES),
               code=[runtime_section("c", name) for name in C_RUNTIME] + runtime(code),
               named_fields_preference=not upstream, any_low=ANY_LOW, any_high=ANY_HIGH, **model)
    return {OUT: env.get_template("packet-ur.c.j2").render(**ctx)}
