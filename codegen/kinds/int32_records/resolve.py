"""LoadedSpec (framing.kind: int32_records) -> RecordsProtocol, with every problem at its YAML path."""
from __future__ import annotations

from ... import ir
from ...errors import SpecError
from ...load import LoadedSpec
from ...resolve import Resolver
from .model import Int32Field, Record, RecordsProtocol


class _RecordsResolver(Resolver):
    def field(self, raw: dict, parts) -> Int32Field:
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None
        if enum is not None and enum.scalar.name != "int32":
            self.fail(parts + ["enum"], f"enum {enum.name} is {enum.scalar.name}: every field here is an int32")
        return Int32Field(raw["name"], raw["label"], raw.get("doc", ""), raw.get("count", 1), raw.get("scale"),
                          raw.get("scale_name", ""), raw.get("unit"), enum,
                          self.versions(raw.get("versions"), parts + ["versions"]), self.where(parts))

    def record(self, raw: dict, parts) -> Record:
        fields: list[Int32Field] = []
        for i, raw_field in enumerate(raw["fields"]):
            field = self.field(raw_field, parts + ["fields", i])
            for earlier in fields:
                if earlier.name != field.name:
                    continue
                # One name, one kind: the same field in releases that do not overlap.
                if earlier.versions.overlaps(field.versions):
                    self.fail(parts + ["fields", i, "versions"], f"{field.name} is sent twice in "
                              f"{earlier.versions.describe()} and {field.versions.describe()}")
                if _kind(earlier) != _kind(field):
                    self.fail(parts + ["fields", i], f"{field.name} changes its kind between releases")
            fields.append(field)
        return Record(raw["name"], raw["direction"], raw["label"], raw["doc"], tuple(fields), self.where(parts))

    def check_filter_names(self, protocol: str, records: list[Record]) -> None:
        """Each field is the filter <protocol>.<name> in both dissectors, one per name over both
        records, and a scaled field's raw int32 is <protocol>.<name>_raw beside it: a name both
        records send keeps one kind, and no field takes a scaled field's raw name."""
        first: dict[str, tuple[Record, Int32Field]] = {}
        raw = {f"{f.name}_raw": f.name for r in records for f in r.fields if f.scale is not None}
        for i, record in enumerate(records):
            for j, field in enumerate(record.fields):
                other, earlier = first.setdefault(field.name, (record, field))
                if other is not record and _kind(earlier) != _kind(field):
                    self.fail(["records", i, "fields", j], f"{protocol}.{field.name} is a field of {other.name} "
                                                           f"too, of another kind: one filter name, one kind")
                if field.name in raw:
                    self.fail(["records", i, "fields", j, "name"], f"{protocol}.{field.name} is the raw int32 of "
                                                                   f"the scaled field {raw[field.name]}")

    def protocol(self) -> RecordsProtocol:
        data = self.spec.data
        for name, raw in data.get("enums", {}).items():
            self.enums[name] = self.enum(name, raw)
        records = []
        for i, raw in enumerate(data["records"]):
            record = self.record(raw, ["records", i])
            if record.name in self.enums:
                self.fail(["records", i, "name"], f"{record.name} names an enum too (one class per name in Python)")
            if any(r.direction == record.direction for r in records):
                self.fail(["records", i, "direction"], f"a second record {record.direction}")
            records.append(record)
        framing, proto = data["framing"], data["protocol"]
        self.check_filter_names(proto["name"], records)
        releases = tuple(ir.parse_version(v) for v in framing["releases"])
        if list(releases) != sorted(set(releases)):
            self.fail(["framing", "releases"], "releases are listed once each, oldest first")
        default = ir.parse_version(framing["default_release"])
        if default not in releases:
            self.fail(["framing", "default_release"], f"{framing['default_release']} is not among the releases")
        return RecordsProtocol(proto["name"], proto["title"], proto["doc"], tuple(proto["ports"]), releases, default,
                               dict(self.enums), tuple(records))


def _kind(f: Int32Field) -> tuple:
    """What a field's name stands for wherever it is sent: scaled or not, its enum, one value or a list."""
    return f.scale is None, f.enum, f.count == 1


def resolve(spec: LoadedSpec) -> RecordsProtocol:
    resolver = _RecordsResolver(spec)
    model = resolver.protocol()
    if resolver.problems:
        raise SpecError(spec.source, resolver.problems)
    return model
