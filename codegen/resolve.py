"""Pass 3, the part every kind shares: software versions, enums and fields of the validated spec
into the typed IR (codegen/ir.py), checking what a schema cannot. Each kind's resolve.py builds
on Resolver for the rest of its spec (the primary interface's: kinds/packages/resolve.py).

Checks collect problems instead of stopping at the first, so one run shows every mistake.
"""
from __future__ import annotations

from typing import Optional

from . import ir, series as series_rules
from .errors import Problem
from .load import LoadedSpec
from .naming import words


class Resolver:
    def __init__(self, spec: LoadedSpec):
        self.spec = spec
        self.problems: list[Problem] = []
        self.enums: dict[str, ir.Enum] = {}
        self.unresolved: set[int] = set()
        self.value_enums: set[str] = set()     # enums that value fields take their type codes from
        self.series: list[series_rules.Series] = []   # the spec's series, once declare_series has read them

    def fail(self, parts, message: str) -> None:
        self.problems.append(self.spec.problem(parts, message))

    def where(self, parts) -> ir.Where:
        found = self.spec.problem(parts, "")
        return ir.Where(found.path, found.line)

    # ---- versions and enums ----

    def versions(self, raw: Optional[dict], parts) -> ir.VersionRange:
        """A `versions:` range: `from:`, and `until:` (an explicit last version) or `through:` (the
        last version of a series; none for the last series, which is open). Where the spec
        declares series, the range keeps the rules of codegen/series.py."""
        if not raw:
            return ir.ALL_VERSIONS
        low = ir.parse_version(raw["from"]) if "from" in raw else None
        if "until" in raw:
            high = ir.parse_version(raw["until"], upper=True)
        else:
            high = series_rules.through_end(self.series, raw["through"]) if "through" in raw else None
        for key, message in series_rules.range_problems(self.series, raw, low, high):
            self.fail(parts + ([key] if key else []), message)
        if low and high and "until" in raw and low > high:
            self.fail(parts, f"version range starts after it ends ({raw['from']} > {raw['until']})")
        return ir.VersionRange(low, high)

    def declare_series(self, raws: list[dict], parts) -> list[series_rules.Series]:
        """The spec's series (`protocol.generations`), oldest first, each starting after the one
        before ends; every `versions:` range resolved after this keeps the rules of series.py."""
        declared: list[series_rules.Series] = []
        for i, raw in enumerate(raws):
            rng = self.versions(raw["versions"], parts + [i, "versions"])
            before = declared[-1].versions if declared else None
            if before is not None and (before.high is None or rng.low is None or rng.low <= before.high):
                self.fail(parts + [i, "versions"], f"{raw['name']} must start after {declared[-1].name} ends")
            declared.append(series_rules.Series(raw["name"], rng))
        self.series = declared
        return declared

    def enum_values(self, raw_values, scalar: ir.Scalar, parts) -> list[ir.EnumValue]:
        out: list[ir.EnumValue] = []
        for i, v in enumerate(raw_values):
            where = parts + [i]
            member = ir.EnumValue(v["name"], v["value"], v.get("doc", ""), v.get("undocumented", False),
                                  self.versions(v.get("versions"), where + ["versions"]), v.get("field_note", ""))
            # A name or a value may repeat only for versions that do not overlap.
            for earlier in out:
                if earlier.versions.overlaps(member.versions):
                    if earlier.name == member.name:
                        self.fail(where + ["name"], f"duplicate enum member {member.name}")
                    if earlier.value == member.value:
                        self.fail(where + ["value"], f"duplicate enum value {member.value}")
            if not scalar.min <= v["value"] <= scalar.max:
                self.fail(where + ["value"], f"{v['value']} does not fit in {scalar.name}")
            out.append(member)
        return out

    def enum(self, name: str, raw: dict) -> ir.Enum:
        parts = ["enums", name]
        scalar = ir.SCALARS[raw["type"]]
        if "values" in raw:
            tables = _tables_by_member(self.enum_values(raw["values"], scalar, parts + ["values"]))
        else:
            tables = []
            for i, t in enumerate(raw["tables"]):
                where = parts + ["tables", i]
                rng = self.versions(t["versions"], where + ["versions"])
                for earlier in tables:
                    if earlier.versions.overlaps(rng):
                        self.fail(where + ["versions"], f"overlaps the table for {earlier.versions.describe()}")
                tables.append(ir.EnumTable(rng, self.enum_values(t["values"], scalar, where + ["values"])))
        return ir.Enum(name, scalar, raw["doc"], raw.get("field_note", ""), tables)

    def enum_ref(self, name: str, parts) -> Optional[ir.Enum]:
        if name not in self.enums:
            self.fail(parts, f"unknown enum '{name}'")
            return None
        return self.enums[name]

    def member(self, enum: Optional[ir.Enum], name: str, parts,
               versions: ir.VersionRange = ir.ALL_VERSIONS) -> ir.EnumValue:
        if enum is not None:
            for v in enum.values:
                if v.name == name:
                    if not v.versions.unbounded and not versions.unbounded and not versions.overlaps(v.versions):
                        self.fail(parts, f"'{name}' is not a member for {versions.describe()}")
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
            f = self.field(raw, where, out)
            for earlier in out:
                if earlier.name == f.name:
                    self.same_name(earlier, f, where)
            if out and _runs_to_end(out[-1]) and not out[-1].conditional:
                self.fail(where, f"field '{f.name}' follows '{out[-1].name}', which runs to the end of the layout")
            out.append(f)
        return out

    def same_name(self, earlier: ir.AnyField, f: ir.AnyField, where) -> None:
        """The one rule for a name that stands more than once in a layout (every target relies on
        it): its entries are sent by versions that do not overlap, and they are one value of one
        kind, so that one record attribute, C member or Wireshark field holds them all. Each entry
        is a scalar of the same kind (integer, float, bool) and the same signedness, under the
        same flag, with the same enum, its bit names alike as far as both go; only its size may
        differ (int16 before int32, float32 before float64): the widest entry then holds every
        value of the others (ir.Struct.public_fields)."""
        if earlier.versions.overlaps(f.versions):
            self.fail(where + ["name"], f"duplicate field name '{f.name}' (give the entries version ranges "
                                        f"that do not overlap)")
            return
        if not (isinstance(f, ir.ScalarField) and isinstance(earlier, ir.ScalarField)
                and _kind(f.scalar) == _kind(earlier.scalar) and f.enum is earlier.enum
                and _prefix(f.bits, earlier.bits) and f.present_if == earlier.present_if):
            self.fail(where + ["name"], f"'{f.name}' stands twice with another kind of value: give the older "
                                        f"form a name of its own")
        elif f.scalar.signed != earlier.scalar.signed:
            self.fail(where + ["type"], f"'{f.name}' stands twice as {earlier.scalar.name} and {f.scalar.name}: "
                                        f"entries of one name may differ in size only, not in signedness (give "
                                        f"the older form a name of its own)")
        # One name is one field to its readers: one label, one unit.
        if (f.label, f.unit) != (earlier.label, earlier.unit):
            self.fail(where + ["label"], f"'{f.name}' stands twice with another label or unit "
                                         f"('{earlier.titled}' and '{f.titled}')")

    def field(self, raw: dict, parts, earlier: list[ir.AnyField]) -> ir.AnyField:
        common = dict(name=raw["name"], label=raw["label"], unit=raw.get("unit"), doc=raw.get("doc", ""),
                      field_note=raw.get("field_note", ""), present_if=raw.get("present_if"),
                      versions=self.versions(raw.get("versions"), parts + ["versions"]), where=self.where(parts))
        if common["present_if"] is not None:
            cond = field_named(earlier, common["present_if"])
            if not isinstance(cond, ir.ScalarField) or cond.scalar.is_float:
                self.fail(parts + ["present_if"], f"'{common['present_if']}' must name an earlier bool or integer field")
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None
        if "unit" in raw and not _measured(raw):
            self.fail(parts + ["unit"], "a unit needs a number: an integer or float field with no enum and no bits")

        if "switch" in raw:
            selector = field_named(earlier, raw["switch"])
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
                                 item_label=raw.get("item_label", words(raw["item"])))

        kind = raw["type"]
        repeat = raw.get("repeat")
        if kind == "value":
            if enum is None or not enum.versioned:
                self.fail(parts + ["enum"], "a value field needs 'enum' naming a versioned type table")
            else:
                self.value_enums.add(enum.name)
            if repeat != "to_end" or "terminator" not in raw:
                self.fail(parts, "a value field needs 'repeat: to_end' and a 'terminator'")
            return ir.ValueListField(**common, value_type=enum, terminator=raw.get("terminator", 0x0A),
                                     item_label=raw.get("item_label", raw["label"]))
        if kind == "string":
            if repeat == "to_end":
                if "terminator" not in raw:
                    self.fail(parts, "a repeated string needs a 'terminator'")
                return ir.StringListField(**common, terminator=raw.get("terminator", 0x0A),
                                          item_label=raw.get("item_label", raw["label"]))
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
        bits = list(raw.get("bits", []))
        return ir.ScalarField(**common, scalar=scalar, enum=enum, bits=bits, bit_labels=[words(b) for b in bits])


def _tables_by_member(values: list[ir.EnumValue]) -> list[ir.EnumTable]:
    """One table, or, where members carry version ranges, one table per stretch of versions in
    which the same members hold (oldest first): what a code means then depends on the version."""
    if all(v.versions.unbounded for v in values):
        return [ir.EnumTable(ir.ALL_VERSIONS, values)]
    cuts = {(0, 0, 0)}
    for v in values:
        if v.versions.low:
            cuts.add(v.versions.low)
        if v.versions.high:
            cuts.add(_next_version(v.versions.high))
    points = sorted(cuts)
    tables: list[ir.EnumTable] = []
    for i, low in enumerate(points):
        members = [v for v in values if v.versions.contains(low)]
        high = _previous_version(points[i + 1]) if i + 1 < len(points) else None
        if tables and [id(v) for v in tables[-1].values] == [id(v) for v in members]:
            tables[-1] = ir.EnumTable(ir.VersionRange(tables[-1].versions.low, high), members)
        else:
            tables.append(ir.EnumTable(ir.VersionRange(low if i else None, high), members))
    return tables


def _next_version(v: ir.Version) -> ir.Version:
    major, minor, bugfix = v
    return (major, minor + 1, 0) if bugfix >= ir.BUGFIX_ANY else (major, minor, bugfix + 1)


def _previous_version(v: ir.Version) -> ir.Version:
    major, minor, bugfix = v
    if bugfix:
        return major, minor, bugfix - 1
    return (major, minor - 1, ir.BUGFIX_ANY) if minor else (major - 1, 999, ir.BUGFIX_ANY)


def _prefix(a: list, b: list) -> bool:
    """Bit names of two entries of one name: a narrower one names the first bits alike."""
    return a[:len(b)] == b[:len(a)]


def _measured(raw: dict) -> bool:
    """True for a field whose value is a number a unit can follow: an integer or float (or a
    switch among them) that no enum names and no bits split."""
    kinds = [raw["type"]] if "type" in raw else list(raw.get("cases", {}).values()) + [raw.get("default")]
    return (all(k in ir.SCALARS and k != "bool" for k in kinds)
            and "enum" not in raw and "bits" not in raw)


def _kind(s: ir.Scalar) -> str:
    return "bool" if s.is_bool else "float" if s.is_float else "int"


def field_named(fields: list, name: str):
    """The first field of `fields` called `name`, or None."""
    for f in fields:
        if f.name == name:
            return f
    return None


def _runs_to_end(f: ir.AnyField) -> bool:
    return (isinstance(f, (ir.StringListField, ir.BytesField, ir.ValueListField))
            or (isinstance(f, ir.StringField) and f.to_end)
            or (isinstance(f, ir.GroupField) and f.to_end))
