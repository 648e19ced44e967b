"""Pass 3 for the primary interface: its layouts, messages, headers, value layouts and protocol
(model.py), on the versions, enums and fields every kind resolves alike (codegen/resolve.py)."""
from __future__ import annotations

import re
from typing import Optional

from ... import ir
from ...errors import SpecError
from ...load import LoadedSpec
from ...resolve import Resolver, field_named
from . import model
from .dissector import dissector
from .plan import plan


class _PackagesResolver(Resolver):
    def layout(self, name: str, raw: dict, code_enum: Optional[ir.Enum], parts) -> model.Layout:
        struct = ir.Struct(name, raw["doc"], self.fields(raw["fields"], parts + ["fields"]))
        sets_version = None
        if "sets_version" in raw:
            sv = raw["sets_version"]
            for key in ("major", "minor", "bugfix"):
                if key not in sv:
                    continue
                f = field_named(struct.fields, sv[key])
                if not isinstance(f, ir.ScalarField) or not f.scalar.is_integer:
                    self.fail(parts + ["sets_version", key], f"'{sv[key]}' must name an integer field of this layout")
                elif key != "bugfix" and f.conditional:
                    self.fail(parts + ["sets_version", key], f"'{sv[key]}' must be in every form of the layout")
            sets_version = (sv["major"], sv["minor"], sv.get("bugfix"))
        summary = self.summary(raw.get("summary"), struct, parts + ["summary"])
        versions = self.versions(raw.get("versions"), parts + ["versions"])
        return model.Layout(name, self.member(code_enum, raw["code"], parts + ["code"], versions), raw["doc"],
                         raw.get("field_note", ""), struct, sets_version, summary, self.where(parts), versions,
                         raw.get("inferred", False), raw.get("label", ""))

    def summary(self, text: Optional[str], struct: ir.Struct, parts) -> list[tuple[str, str]]:
        """'{title}: {text}' -> [('', 'title'), (': ', 'text')]; only scalar and string fields."""
        if not text:
            return []
        pieces = re.split(r"\{([a-z][a-z0-9_]*)\}", text)
        if pieces[-1]:
            self.fail(parts, f"text after the last field ('{pieces[-1]}') is not shown; end with a field")
        out = []
        for before, name in zip(pieces[0::2], pieces[1::2]):
            f = field_named(struct.fields, name)
            if not isinstance(f, (ir.ScalarField, ir.StringField)):
                self.fail(parts, f"'{name}' is not a scalar or string field of this layout")
            out.append((before, name))
        return out

    def header_field(self, raw: dict, parts) -> model.HeaderField:
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None
        return model.HeaderField(ir.SCALARS[raw["type"]], enum, raw.get("doc", ""), self.where(parts), raw["label"])

    def unique_codes(self, layouts: list[model.Layout], parts) -> None:
        """Two layouts may share a code only for software versions that do not overlap."""
        seen: list[model.Layout] = []
        for lay in layouts:
            if id(lay.code) in self.unresolved:
                continue
            for other in seen:
                if other.code.value == lay.code.value and other.versions.overlaps(lay.versions):
                    self.fail(parts + [lay.name, "code"], f"code {lay.code.name} is already used by '{other.name}' "
                                                          f"for {other.versions.describe()}")
            seen.append(lay)

    def resolve(self) -> model.Protocol:
        data = self.spec.data
        proto = data["protocol"]
        # The series first: every range after them is stated against them (codegen/series.py).
        series = self.declare_series(proto.get("generations", []), ["protocol", "generations"])
        for name, raw in data["enums"].items():
            self.enums[name] = self.enum(name, raw)

        framing = data["framing"]
        mh = {k: self.header_field(v, ["framing", "message_header", k]) for k, v in framing["message_header"].items()}
        ph = {k: self.header_field(v, ["framing", "package_header", k]) for k, v in framing["package_header"].items()}
        if mh["type"].enum is None:
            self.fail(["framing", "message_header", "type"], "the message type needs an enum")
        if ph["type"].enum is None:
            self.fail(["framing", "package_header", "type"], "the package type needs an enum")

        layouts_by_name: dict[str, list] = {}
        messages: list[model.Message] = []
        for name, raw in data["messages"].items():
            parts = ["messages", name]
            code = self.member(mh["type"].enum, raw["code"], parts + ["code"])
            if "packages" in raw:
                packages = [self.layout(n, r, ph["type"].enum, parts + ["packages", n]) for n, r in raw["packages"].items()]
                self.unique_codes(packages, parts + ["packages"])
                messages.append(model.PackageListMessage(name, code, raw["doc"], raw.get("field_note", ""), packages,
                                                      ph["type"].enum, self.where(parts)))
                layouts = packages
            elif "fields" in raw:
                # A body message: one layout after the message header, named as the message.
                body = self.layout(name, raw, mh["type"].enum, parts)
                messages.append(model.DispatchMessage(name, code, raw["doc"], raw.get("field_note", ""),
                                                   ir.Struct(name + "_header", raw["doc"], []), None, [body],
                                                   self.where(parts), mh["type"].enum))
                continue
            else:
                header = ir.Struct(name + "_header", raw["doc"], self.fields(raw["header"], parts + ["header"]))
                if header.fixed_size is None:
                    self.fail(parts + ["header"], "a message header must have a fixed size")
                st = raw["subtype"]
                sub_enum = self.enum_ref(st["enum"], parts + ["subtype", "enum"])
                subtype = ir.ScalarField(name=st["name"], label=st["label"], doc=st.get("doc", ""),
                                         scalar=ir.SCALARS[st["type"]], enum=sub_enum,
                                         where=self.where(parts + ["subtype"]))
                subtypes = [self.layout(n, r, sub_enum, parts + ["subtypes", n]) for n, r in raw["subtypes"].items()]
                self.unique_codes(subtypes, parts + ["subtypes"])
                messages.append(model.DispatchMessage(name, code, raw["doc"], raw.get("field_note", ""), header,
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
            value_layouts[tname] = model.ValueLayout(
                tname, raw["layout"], ir.SCALARS.get(raw.get("length", "")), ir.SCALARS.get(raw.get("item", "")),
                raw.get("count", 0), raw.get("doc", ""), self.where(["value_layouts", tname]))
        for ename in sorted(self.value_enums):
            for name in self.enums[ename].names:
                if name not in value_layouts:
                    self.fail(["enums", ename], f"value type {name} has no entry in value_layouts")

        documented = [ir.parse_version(v) for v in proto["documented_versions"]]
        protocol = model.Protocol(
            name=proto["name"], title=proto["title"], doc=proto["doc"], ports=list(proto["ports"]),
            max_message_length=proto["max_message_length"], max_value_depth=proto["max_value_depth"],
            documented_versions=documented, default_version=ir.parse_version(proto["default_version"]),
            enums=self.enums, value_layouts=value_layouts,
            message_length=mh["length"], message_type=mh["type"],
            package_length=ph["length"], package_type=ph["type"], messages=messages, source=self.spec.source,
            generations=[(s.name, s.versions) for s in series], robot_buffer=proto.get("robot_buffer"))
        if self.problems:
            raise SpecError(self.spec.source, self.problems)
        return protocol


def resolve(spec: LoadedSpec) -> model.Protocol:
    protocol = _PackagesResolver(spec).resolve()
    # What the Wireshark dissectors show obeys rules of the spec, not of one target: one type per
    # filter name, none of the dissector's own names, summaries the Info column can read. The
    # model is built here, so that every target (`--target c` too) reports them at their path.
    dissector(plan(protocol))
    return protocol
