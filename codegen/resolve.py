"""Pass 3: turn the validated spec into the typed IR, checking what a schema cannot.

Checks collect problems instead of stopping at the first, so one run shows every mistake.
"""
from __future__ import annotations

import re
from typing import Optional

from . import ir
from .errors import Problem, SpecError
from .load import LoadedSpec


class _Resolver:
    def __init__(self, spec: LoadedSpec):
        self.spec = spec
        self.problems: list[Problem] = []
        self.enums: dict[str, ir.Enum] = {}
        self.unresolved: set[int] = set()

    def fail(self, parts, message: str) -> None:
        self.problems.append(self.spec.problem(parts, message))

    def where(self, parts) -> ir.Where:
        found = self.spec.problem(parts, "")
        return ir.Where(found.path, found.line)

    # ---- versions and enums ----

    def versions(self, raw: Optional[dict], parts) -> ir.VersionRange:
        if not raw:
            return ir.ALL_VERSIONS
        low = ir.parse_version(raw["from"]) if "from" in raw else None
        high = ir.parse_version(raw["until"]) if "until" in raw else None
        if low and high and low > high:
            self.fail(parts, f"version range starts after it ends ({raw['from']} > {raw['until']})")
        return ir.VersionRange(low, high)

    def enum_values(self, raw_values, scalar: ir.Scalar, parts) -> list[ir.EnumValue]:
        out, names, codes = [], set(), set()
        for i, v in enumerate(raw_values):
            where = parts + [i]
            if v["name"] in names:
                self.fail(where + ["name"], f"duplicate enum member {v['name']}")
            if v["value"] in codes:
                self.fail(where + ["value"], f"duplicate enum value {v['value']}")
            if not scalar.min <= v["value"] <= scalar.max:
                self.fail(where + ["value"], f"{v['value']} does not fit in {scalar.name}")
            names.add(v["name"])
            codes.add(v["value"])
            out.append(ir.EnumValue(v["name"], v["value"], v.get("doc", ""), v.get("undocumented", False),
                                    self.versions(v.get("versions"), where + ["versions"])))
        return out

    def enum(self, name: str, raw: dict) -> ir.Enum:
        parts = ["enums", name]
        scalar = ir.SCALARS[raw["type"]]
        if "values" in raw:
            tables = [ir.EnumTable(ir.ALL_VERSIONS, self.enum_values(raw["values"], scalar, parts + ["values"]))]
        else:
            tables = []
            for i, t in enumerate(raw["tables"]):
                where = parts + ["tables", i]
                rng = self.versions(t["versions"], where + ["versions"])
                for earlier in tables:
                    if _overlap(earlier.versions, rng):
                        self.fail(where + ["versions"], f"overlaps the table for {earlier.versions.describe()}")
                tables.append(ir.EnumTable(rng, self.enum_values(t["values"], scalar, where + ["values"])))
        return ir.Enum(name, scalar, raw["doc"], raw.get("field_note", ""), tables)

    def enum_ref(self, name: str, parts) -> Optional[ir.Enum]:
        if name not in self.enums:
            self.fail(parts, f"unknown enum '{name}'")
            return None
        return self.enums[name]

    def member(self, enum: Optional[ir.Enum], name: str, parts) -> ir.EnumValue:
        if enum is not None:
            for v in enum.values:
                if v.name == name:
                    return v
            self.fail(parts, f"'{name}' is not a member of enum '{enum.name}'")
        placeholder = ir.EnumValue(name, 0)
        self.unresolved.add(id(placeholder))  # reported once; kept out of later checks
        return placeholder

    # ---- fields ----

    def fields(self, raw_fields, parts) -> list[ir.AnyField]:
        out: list[ir.AnyField] = []
        for i, raw in enumerate(raw_fields):
            where = parts + [i]
            if raw["name"] in {f.name for f in out}:
                self.fail(where + ["name"], f"duplicate field name '{raw['name']}'")
            f = self.field(raw, where, out)
            if out and _runs_to_end(out[-1]) and not out[-1].conditional:
                self.fail(where, f"field '{f.name}' follows '{out[-1].name}', which runs to the end of the layout")
            out.append(f)
        return out

    def field(self, raw: dict, parts, earlier: list[ir.AnyField]) -> ir.AnyField:
        common = dict(name=raw["name"], doc=raw.get("doc", ""), field_note=raw.get("field_note", ""),
                      present_if=raw.get("present_if"),
                      versions=self.versions(raw.get("versions"), parts + ["versions"]), where=self.where(parts))
        if common["present_if"] is not None:
            cond = _find(earlier, common["present_if"])
            if not isinstance(cond, ir.ScalarField) or cond.scalar.is_float:
                self.fail(parts + ["present_if"], f"'{common['present_if']}' must name an earlier bool or integer field")
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None

        if "switch" in raw:
            selector = _find(earlier, raw["switch"])
            if not isinstance(selector, ir.ScalarField) or not selector.scalar.is_integer:
                self.fail(parts + ["switch"], f"'{raw['switch']}' must name an earlier integer field")
                selector = ir.ScalarField(name=raw["switch"])
            cases = {int(k): ir.SCALARS[v] for k, v in raw["cases"].items()}
            return ir.SwitchField(**common, selector=selector, cases=cases, default=ir.SCALARS[raw["default"]])

        if "fields" in raw:
            item = ir.Struct(raw["item"], raw.get("doc", ""), self.fields(raw["fields"], parts + ["fields"]))
            if "count" not in raw and raw.get("repeat") != "to_end":
                self.fail(parts, "a group needs 'count' or 'repeat: to_end'")
            if "count" not in raw and item.min_size == 0:
                self.fail(parts, "a group repeated to the end must read at least one byte per item")
            return ir.GroupField(**common, item=item, count=raw.get("count"),
                                 item_label=raw.get("item_label", raw["item"].replace("_", " ").capitalize()))

        kind = raw["type"]
        repeat = raw.get("repeat")
        if kind == "value":
            if enum is None or not enum.versioned:
                self.fail(parts + ["enum"], "a value field needs 'enum' naming a versioned type table")
            if repeat != "to_end" or "terminator" not in raw:
                self.fail(parts, "a value field needs 'repeat: to_end' and a 'terminator'")
            return ir.ValueListField(**common, value_type=enum, terminator=raw.get("terminator", 0x0A))
        if kind == "string":
            if repeat == "to_end":
                if "terminator" not in raw:
                    self.fail(parts, "a repeated string needs a 'terminator'")
                return ir.StringListField(**common, terminator=raw.get("terminator", 0x0A))
            length = ir.SCALARS[raw["length"]] if "length" in raw else None
            return ir.StringField(**common, length=length)
        if kind == "bytes":
            return ir.BytesField(**common)
        scalar = ir.SCALARS[kind]
        if enum is not None:
            misfits = [v.name for v in enum.values if not scalar.min <= v.value <= scalar.max]
            if misfits:
                self.fail(parts + ["enum"], f"enum '{enum.name}' has values that do not fit the field's "
                                            f"{scalar.name}: {', '.join(misfits)}")
        if raw.get("bits") and not scalar.is_integer:
            self.fail(parts + ["bits"], "bit names need an integer field")
        if raw.get("bits") and len(raw["bits"]) > scalar.bits:
            self.fail(parts + ["bits"], f"{len(raw['bits'])} bit names do not fit in {scalar.name}")
        if "count" in raw:
            return ir.ArrayField(**common, scalar=scalar, count=raw["count"], enum=enum)
        return ir.ScalarField(**common, scalar=scalar, enum=enum, bits=list(raw.get("bits", [])))

    # ---- layouts and messages ----

    def layout(self, name: str, raw: dict, code_enum: Optional[ir.Enum], parts) -> ir.Layout:
        struct = ir.Struct(name, raw["doc"], self.fields(raw["fields"], parts + ["fields"]))
        sets_version = None
        if "sets_version" in raw:
            sv = raw["sets_version"]
            for key in ("major", "minor"):
                f = _find(struct.fields, sv[key])
                if not isinstance(f, ir.ScalarField) or not f.scalar.is_integer:
                    self.fail(parts + ["sets_version", key], f"'{sv[key]}' must name an integer field of this layout")
            sets_version = (sv["major"], sv["minor"])
        summary = self.summary(raw.get("summary"), struct, parts + ["summary"])
        return ir.Layout(name, self.member(code_enum, raw["code"], parts + ["code"]), raw["doc"],
                         raw.get("field_note", ""), struct, sets_version, summary, self.where(parts))

    def summary(self, text: Optional[str], struct: ir.Struct, parts) -> list[tuple[str, str]]:
        """'{title}: {text}' -> [('', 'title'), (': ', 'text')]; only scalar and string fields."""
        if not text:
            return []
        pieces = re.split(r"\{([a-z][a-z0-9_]*)\}", text)
        if pieces[-1]:
            self.fail(parts, f"text after the last field ('{pieces[-1]}') is not shown; end with a field")
        out = []
        for before, name in zip(pieces[0::2], pieces[1::2]):
            f = _find(struct.fields, name)
            if not isinstance(f, (ir.ScalarField, ir.StringField)):
                self.fail(parts, f"'{name}' is not a scalar or string field of this layout")
            out.append((before, name))
        return out

    def header_field(self, raw: dict, parts) -> ir.HeaderField:
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None
        return ir.HeaderField(ir.SCALARS[raw["type"]], enum, raw.get("doc", ""), self.where(parts))

    def unique_codes(self, layouts: list[ir.Layout], parts) -> None:
        seen: dict[int, str] = {}
        for lay in layouts:
            if id(lay.code) in self.unresolved:
                continue
            if lay.code.value in seen:
                self.fail(parts + [lay.name, "code"], f"code {lay.code.name} is already used by '{seen[lay.code.value]}'")
            seen[lay.code.value] = lay.name

    def resolve(self) -> ir.Protocol:
        data = self.spec.data
        for name, raw in data["enums"].items():
            self.enums[name] = self.enum(name, raw)

        proto = data["protocol"]
        framing = data["framing"]
        mh = {k: self.header_field(v, ["framing", "message_header", k]) for k, v in framing["message_header"].items()}
        ph = {k: self.header_field(v, ["framing", "package_header", k]) for k, v in framing["package_header"].items()}
        if mh["type"].enum is None:
            self.fail(["framing", "message_header", "type"], "the message type needs an enum")
        if ph["type"].enum is None:
            self.fail(["framing", "package_header", "type"], "the package type needs an enum")

        layouts_by_name: dict[str, list] = {}
        messages: list[ir.Message] = []
        for name, raw in data["messages"].items():
            parts = ["messages", name]
            code = self.member(mh["type"].enum, raw["code"], parts + ["code"])
            if "packages" in raw:
                packages = [self.layout(n, r, ph["type"].enum, parts + ["packages", n]) for n, r in raw["packages"].items()]
                self.unique_codes(packages, parts + ["packages"])
                messages.append(ir.PackageListMessage(name, code, raw["doc"], raw.get("field_note", ""), packages,
                                                      ph["type"].enum, self.where(parts)))
                layouts = packages
            else:
                header = ir.Struct(name + "_header", raw["doc"], self.fields(raw["header"], parts + ["header"]))
                if header.fixed_size is None:
                    self.fail(parts + ["header"], "a message header must have a fixed size")
                st = raw["subtype"]
                sub_enum = self.enum_ref(st["enum"], parts + ["subtype", "enum"])
                subtype = ir.ScalarField(name=st["name"], doc=st.get("doc", ""), scalar=ir.SCALARS[st["type"]], enum=sub_enum,
                                         where=self.where(parts + ["subtype"]))
                subtypes = [self.layout(n, r, sub_enum, parts + ["subtypes", n]) for n, r in raw["subtypes"].items()]
                self.unique_codes(subtypes, parts + ["subtypes"])
                messages.append(ir.DispatchMessage(name, code, raw["doc"], raw.get("field_note", ""), header,
                                                   subtype, subtypes, self.where(parts)))
                layouts = subtypes
            for lay in layouts:
                layouts_by_name.setdefault(lay.name, []).append(parts)
        for lname, where in layouts_by_name.items():
            if len(where) > 1 or lname in data["messages"]:
                self.fail(where[-1], f"layout name '{lname}' is used more than once")
        seen_codes: dict[int, str] = {}
        for m in messages:
            if m.code.value in seen_codes:
                self.fail(["messages", m.name, "code"], f"code {m.code.name} is already used by '{seen_codes[m.code.value]}'")
            seen_codes[m.code.value] = m.name

        value_layouts = {}
        for tname, raw in data["value_layouts"].items():
            value_layouts[tname] = ir.ValueLayout(
                tname, raw["layout"], ir.SCALARS.get(raw.get("length", "")), ir.SCALARS.get(raw.get("item", "")),
                raw.get("count", 0), raw.get("doc", ""), self.where(["value_layouts", tname]))
        for ename, enum in self.enums.items():
            if enum.versioned:
                for name in enum.names:
                    if name not in value_layouts:
                        self.fail(["enums", ename], f"value type {name} has no entry in value_layouts")

        documented = [ir.parse_version(v) for v in proto["documented_versions"]]
        protocol = ir.Protocol(
            name=proto["name"], title=proto["title"], doc=proto["doc"], ports=list(proto["ports"]),
            max_message_length=proto["max_message_length"], max_value_depth=proto["max_value_depth"],
            documented_versions=documented, default_version=ir.parse_version(proto["default_version"]),
            enums=self.enums, value_layouts=value_layouts,
            message_length=mh["length"], message_type=mh["type"],
            package_length=ph["length"], package_type=ph["type"], messages=messages, source=self.spec.source)
        if self.problems:
            raise SpecError(self.spec.source, self.problems)
        return protocol


def _find(fields: list, name: str):
    for f in fields:
        if f.name == name:
            return f
    return None


def _runs_to_end(f: ir.AnyField) -> bool:
    return (isinstance(f, (ir.StringListField, ir.BytesField, ir.ValueListField))
            or (isinstance(f, ir.StringField) and f.to_end)
            or (isinstance(f, ir.GroupField) and f.to_end))


def _overlap(a: ir.VersionRange, b: ir.VersionRange) -> bool:
    lo = max(a.low or (0, 0), b.low or (0, 0))
    hi = min(a.high or (1 << 30, 0), b.high or (1 << 30, 0))
    return lo <= hi


def resolve(spec: LoadedSpec) -> ir.Protocol:
    return _Resolver(spec).resolve()
