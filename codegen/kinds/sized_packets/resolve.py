"""LoadedSpec -> SizedProtocol: the catalogue of fields resolved once by the primary resolver's
own methods, then each layout's list of names (after the fields of the layout it extends), with
its size checked against them. Every problem names its YAML path and line."""
from __future__ import annotations

from ... import ir, items
from ...errors import SpecError
from ...load import LoadedSpec
from ...resolve import Resolver
from .model import SizedLayout, SizedProtocol


def resolve(spec: LoadedSpec) -> SizedProtocol:
    r = Resolver(spec)
    data = spec.data
    proto = data["protocol"]
    # The series first: every range after them is stated against them (codegen/series.py).
    series = r.declare_series(proto["generations"], ["protocol", "generations"])
    for name, raw in data["enums"].items():
        r.enums[name] = r.enum(name, raw)
    sets = items.item_sets(r, data.get("item_names"))
    catalogue, named, bits = _catalogue(r, data["fields"], sets)
    size_raw = data["framing"]["size"]
    size_field = r.field(dict(size_raw), ["framing", "size"], [])
    _check_filter_names(r, data["protocol"]["name"], data["fields"], size_field)
    layouts: dict[str, SizedLayout] = {}
    for name, raw in data["layouts"].items():
        layouts[name] = _layout(r, name, raw, catalogue, layouts, size_field.scalar.size)
    _check_sizes(r, list(layouts.values()), data["protocol"]["max_message_size"])
    if r.problems:
        raise SpecError(spec.source, r.problems)
    return SizedProtocol(proto["name"], proto["title"], proto["doc"], list(proto["ports"]),
                         proto["max_message_size"], [(s.name, s.versions) for s in series], size_field,
                         data["framing"]["same_size"], r.enums, list(catalogue.values()), list(layouts.values()),
                         named, bits)


def _catalogue(r: Resolver, raw_fields: list, sets: dict) -> tuple[dict, dict, dict]:
    """The fields by name, the named items of vectors and the bits of doubles. Bits are read here:
    the shared resolver keeps them to integer fields, and every value here is a double (a whole
    one, where it carries bits)."""
    out: dict[str, ir.AnyField] = {}
    named: dict[str, tuple[items.Item, ...]] = {}
    bits: dict[str, tuple[items.Bit, ...]] = {}
    for i, raw in enumerate(raw_fields):
        parts = ["fields", i]
        if raw["name"] in out:
            r.fail(parts + ["name"], f"field '{raw['name']}' is described twice")
        f = r.field({k: v for k, v in raw.items() if k not in ("item_names", "bits")}, parts, [])
        out[raw["name"]] = f
        count = f.count if isinstance(f, ir.ArrayField) else 1
        if count > 1 or "item_names" in raw:
            found = items.items_of(r, parts, sets, raw.get("item_names"), count, f.unit)
            if found:
                named[f.name] = found
        if "bits" in raw:
            if count > 1 or getattr(f, "enum", None) is not None or f.unit:
                r.fail(parts + ["bits"], "bits need one double with no enum and no unit")
            bits[f.name] = items.bits_of(raw["bits"])
    return out, named, bits


def _check_filter_names(r: Resolver, protocol: str, raw_fields: list, size_field: ir.AnyField) -> None:
    """Every field and the size field are the filters <protocol>.<name> in both dissectors: no
    field takes the size field's name."""
    for i, raw in enumerate(raw_fields):
        if raw["name"] == size_field.name:
            r.fail(["fields", i, "name"], f"{protocol}.{raw['name']} is the size field's filter name (framing.size)")


def _layout(r: Resolver, name: str, raw: dict, catalogue: dict, earlier: dict, size_bytes: int) -> SizedLayout:
    parts = ["layouts", name]
    fields: list[ir.AnyField] = []
    if "extends" in raw:
        base = earlier.get(raw["extends"])
        if base is None:
            r.fail(parts + ["extends"], f"'{raw['extends']}' is not a layout written above this one")
        else:
            fields = list(base.fields)
    for i, field_name in enumerate(raw["fields"]):
        f = catalogue.get(field_name)
        if f is None:
            r.fail(parts + ["fields", i], f"unknown field '{field_name}' (describe it under fields:)")
        elif any(g.name == field_name for g in fields):
            r.fail(parts + ["fields", i], f"field '{field_name}' stands twice in this layout")
        else:
            fields.append(f)
    versions = [r.versions(v, parts + ["versions", i]) for i, v in enumerate(raw["versions"])]
    for i, v in enumerate(versions):
        for j in range(i):
            if versions[j].overlaps(v):
                r.fail(parts + ["versions", i], f"overlaps {versions[j].describe()}")
    laid = size_bytes + sum(f.fixed_size or 0 for f in fields)
    if laid != raw["size"]:
        r.fail(parts + ["size"], f"size {raw['size']} is not what the fields add up to: {laid} bytes "
                                 f"({size_bytes} of size field and {laid - size_bytes} of fields)")
    return SizedLayout(name, raw["label"], raw.get("doc", ""), raw.get("field_note", ""), raw["size"],
                       versions, fields, r.where(parts))


def _check_sizes(r: Resolver, layouts: list[SizedLayout], max_size: int) -> None:
    """Layouts may share a size (the spec's same_size rule tells them apart), but two that share
    one must not both be sent by one version: the version would then not tell them apart."""
    for i, layout in enumerate(layouts):
        if layout.size > max_size:
            r.fail(["layouts", layout.name, "size"], f"size {layout.size} exceeds max_message_size {max_size}")
        for other in layouts[:i]:
            if other.size != layout.size:
                continue
            for v in layout.versions:
                for w in other.versions:
                    if v.overlaps(w):
                        r.fail(["layouts", layout.name, "versions"],
                               f"shares size {layout.size} with '{other.name}' for {v.describe()}: "
                               f"a version must tell layouts of one size apart")
