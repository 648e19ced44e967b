"""LoadedSpec -> the typed-messages IR (model.Interface), checking what the schema cannot.

Enums and scalar/string fields go through the primary resolver (codegen.resolve.Resolver), so
they become the same ir.Enum and ir.Field objects; every problem names its YAML path and line."""
from __future__ import annotations

from ... import ir, items, series
from ...errors import Problem, SpecError
from ...load import LoadedSpec
from ...resolve import Resolver
from . import model

# Where RTDE begins in each generation: a variable without `since` is there from these on.
_FIRST = {"cb3": ir.parse_version("3.3"), "eseries": series.E_SERIES_FROM, "polyscope_x": series.POLYSCOPE_X_FROM}
# The software each generation's column is read for: from here to the next generation's start.
_COLUMN_FROM = {"cb3": (0, 0, 0), "eseries": series.E_SERIES_FROM, "polyscope_x": series.POLYSCOPE_X_FROM}


class _TypedResolver(Resolver):

    def resolve_interface(self) -> model.Interface:
        data = self.spec.data
        proto, framing = data["protocol"], data["framing"]
        for name, raw in (data.get("enums") or {}).items():
            self.enums[name] = self.enum(name, raw)
        if proto["default_protocol_version"] not in proto["protocol_versions"]:
            self.fail(["protocol", "default_protocol_version"], "is not one of protocol_versions")
        value_types = self.value_types(data["value_types"])
        messages = [self.message(raw, ["messages", i], proto["protocol_versions"])
                    for i, raw in enumerate(data["messages"])]
        self.check_dispatch(messages)
        by_name = {m.name: m for m in messages}
        undocumented = [model.RawMessage(r["name"], ord(r["code"]), r["label"], r["doc"])
                        for r in data.get("undocumented", [])]
        for i, raw in enumerate(undocumented):
            if any(m.code == raw.code for m in messages):
                self.fail(["undocumented", i, "code"], f"code {chr(raw.code)!r} has a layout in messages")
        kinds = [self.recipe_kind(raw, ["recipes", "kinds", i], by_name)
                 for i, raw in enumerate(data["recipes"]["kinds"])]
        if sorted(k.data_from_robot for k in kinds) != [False, True]:
            self.fail(["recipes", "kinds"], "needs one recipe kind for each direction's data packages")
        refusals = [model.Refusal(r["word"], r["doc"]) for r in data["recipes"]["refusals"]]
        generations = [model.Generation(g["name"], g["label"], _FIRST.get(g["name"], (0, 0, 0)),
                                        _COLUMN_FROM.get(g["name"], (0, 0, 0)))
                       for g in data.get("generations", [])]
        follows = ir.parse_version(proto["polyscope_x_follows"]) if "polyscope_x_follows" in proto else None
        sets = items.item_sets(self, data.get("item_names"))
        variables = self.variables(data["variables"], {t.name: t for t in value_types}, generations, follows,
                                   sets)
        self.check_filter_names(proto["name"], messages, variables)
        exchanges = self.exchanges(data["exchanges"]["pairs"], by_name)
        return model.Interface(
            name=proto["name"], title=proto["title"], doc=proto["doc"], ports=tuple(proto["ports"]),
            protocol_versions=tuple(proto["protocol_versions"]),
            default_protocol_version=proto["default_protocol_version"],
            length=ir.SCALARS[framing["length"]], type=ir.SCALARS[framing["type"]],
            length_counts_header=framing["length_counts_header"], enums=list(self.enums.values()),
            value_types=value_types, messages=messages, undocumented=undocumented, recipe_kinds=kinds,
            refusals=refusals, generations=generations, max_pending_setups=data["recipes"]["max_pending_setups"],
            max_pending_version_requests=data["recipes"]["max_pending_version_requests"],
            variables=variables, exchanges=exchanges, max_pending_requests=data["exchanges"]["max_pending"])

    def value_types(self, raws) -> list[model.ValueType]:
        out = []
        for i, raw in enumerate(raws):
            if any(t.name == raw["name"] for t in out):
                self.fail(["value_types", i, "name"], f"duplicate value type {raw['name']}")
            out.append(model.ValueType(raw["name"], ir.SCALARS[raw["scalar"]], raw["count"], raw["doc"]))
        return out

    def message(self, raw: dict, parts, all_protocols) -> model.Message:
        protocols = tuple(raw.get("protocols", all_protocols))
        for p in protocols:
            if p not in all_protocols:
                self.fail(parts + ["protocols"], f"protocol {p} is not one of protocol_versions")
        fields = []
        for i, f in enumerate(raw.get("fields", [])):
            where = parts + ["fields", i]
            if f["type"] == "names":
                fields.append(model.NamesField(f["name"], f["label"], f.get("separator", ","), f.get("role"),
                                               f.get("doc", ""), self.where(where)))
            elif f["type"] == "recipe_values":
                fields.append(model.RecipeValuesField(f["name"], f["label"], f.get("doc", ""), self.where(where)))
            else:
                resolved = self.field(f, where, [x for x in fields if isinstance(x, ir.Field)])
                if not isinstance(resolved, (ir.ScalarField, ir.StringField)) or resolved.conditional:
                    self.fail(where, "a message field here is a scalar or a string, present in every version")
                fields.append(resolved)
            if len(fields) > 1 and _runs_to_end(fields[-2]):
                self.fail(where, f"field '{f['name']}' follows '{fields[-2].name}', which runs to the end")
        return model.Message(raw["name"], ord(raw["code"]), raw["from_robot"], protocols, raw["label"],
                             raw.get("doc", ""), raw.get("field_note", ""), fields, self.where(parts))

    def check_dispatch(self, messages: list[model.Message]) -> None:
        """A type code, direction and protocol version choose exactly one layout."""
        seen: dict[tuple, str] = {}
        for i, m in enumerate(messages):
            if any(o.name == m.name for o in messages[:i]):
                self.fail(["messages", i, "name"], f"duplicate message name {m.name}")
            for p in m.protocols:
                key = (m.code, m.from_robot, p)
                if key in seen:
                    self.fail(["messages", i], f"'{m.letter}' {'from' if m.from_robot else 'to'} the robot in "
                                               f"protocol {p} is already '{seen[key]}'")
                seen[key] = m.name

    def check_filter_names(self, protocol: str, messages: list[model.Message], variables: list[model.Variable]) -> None:
        """Every message field and variable is the filterable field <protocol>.<name> in the
        dissectors: a name has one type, is none of the dissectors' own, and differs from every
        other in more than case (the native dissector names its fields in upper case)."""
        types = dict([model.RECIPE_ID])
        for f in [f for m in messages for f in m.fields] + list(variables):
            kind = model.filter_type(f)
            if kind is None:
                continue
            problem = None
            if f.name in model.OWN_FIELDS + model.LINK_FIELDS or f.name.startswith(model.VALUE_FIELD_PREFIX):
                problem = f"{protocol}.{f.name} is the dissector's own field"
            elif f.name in types:
                if types[f.name] != kind:
                    problem = f"{protocol}.{f.name} would be both a {types[f.name]} and a {kind} field"
            else:
                same = next((n for n in types if n.upper() == f.name.upper()), None)
                if same is not None:
                    problem = f"{protocol}.{f.name} and {protocol}.{same} differ only in case"
                else:
                    types[f.name] = kind
            if problem:
                self.problems.append(Problem(f.where.path, problem, f.where.line))

    def exchanges(self, raws: list, by_name: dict) -> list[model.Exchange]:
        """Each pair: requests to the robot, replies from it, every message in one pair at most."""
        out, seen = [], set()
        for i, raw in enumerate(raws):
            sides = []
            for key, from_robot in (("requests", False), ("replies", True)):
                side = []
                for j, name in enumerate(raw[key]):
                    where = ["exchanges", "pairs", i, key, j]
                    m = by_name.get(name)
                    if m is None:
                        self.fail(where, f"unknown message '{name}'")
                    elif m.from_robot != from_robot:
                        self.fail(where, f"'{name}' is not a message {'from' if from_robot else 'to'} the robot")
                    elif name in seen:
                        self.fail(where, f"'{name}' is in another pair already")
                    else:
                        seen.add(name)
                        side.append(m)
                sides.append(side)
            out.append(model.Exchange(*sides))
        return out

    def recipe_kind(self, raw: dict, parts, by_name: dict) -> model.RecipeKind:
        def named(names, key, want_role, from_robot):
            out = []
            for j, name in enumerate(names):
                m = by_name.get(name)
                if m is None:
                    self.fail(parts + [key, j], f"unknown message '{name}'")
                    continue
                roles = [f.role for f in m.fields if isinstance(f, model.NamesField)]
                if want_role not in roles or m.from_robot != from_robot:
                    self.fail(parts + [key, j], f"'{name}' must be a message {'from' if from_robot else 'to'} "
                                                f"the robot with a names field of role '{want_role}'")
                out.append(m)
            return out
        return model.RecipeKind(raw["name"], raw["data_from_robot"],
                                named(raw["requests"], "requests", "variables", False),
                                named(raw["replies"], "replies", "types", True), raw["doc"])

    def variables(self, raws, types: dict, generations, follows, sets: dict) -> list[model.Variable]:
        out: list[model.Variable] = []
        seen: set[tuple[str, str]] = set()
        meanings: dict[str, tuple] = {}     # a name's enum, bits and items: one field shows both directions
        for i, raw in enumerate(raws):
            parts = ["variables", i]
            vt = types.get(raw["type"])
            if vt is None:
                self.fail(parts + ["type"], f"unknown value type {raw['type']}")
                continue
            since = {}
            for g in generations:
                given = (raw.get("since") or {}).get(g.name)
                if g.name == "polyscope_x":
                    # PolyScope X reads the e-Series column only as far as it is known to follow it.
                    e_series = since.get("eseries", model.NONE)
                    since[g.name], problem = series.polyscope_x_first(e_series, given, follows)
                    if problem:
                        self.fail(parts + ["since"] + (["polyscope_x"] if given else []), problem)
                    continue
                since[g.name] = given if given in (model.UNKNOWN, model.NONE) else \
                    (ir.parse_version(given) if given else g.first)
            enum, bits, named = self.variable_meanings(raw, parts, vt, sets)
            pattern, indices = raw["name"], raw.get("indices")
            if ("{n}" in pattern) != (indices is not None):
                self.fail(parts, "a name with {n} needs 'indices: [first, last]', and only such a name")
                continue
            names = [(pattern.replace("{n}", str(n)), f"{raw['label']} {n}")
                     for n in range(indices[0], indices[1] + 1)] if indices else [(pattern, raw["label"])]
            for name, label in names:
                if (name, raw["direction"]) in seen:
                    self.fail(parts + ["name"], f"variable {name} ({raw['direction']}) is listed twice")
                seen.add((name, raw["direction"]))
                meaning = (enum.name if enum else None, bits, named)
                if meanings.setdefault(name, meaning) != meaning:
                    self.fail(parts, f"variable {name} names its enum, bits or items otherwise than in its other "
                                     f"direction, and one field shows both")
                out.append(model.Variable(name, vt, raw["direction"], label, raw.get("unit"), raw.get("doc", ""),
                                          since, self.where(parts), enum, bits, named))
        return out

    def variable_meanings(self, raw: dict, parts, vt: model.ValueType, sets: dict) -> tuple:
        """A variable's enum (its codes fit its scalar), bits (one integer's) and named items."""
        enum = self.enum_ref(raw["enum"], parts + ["enum"]) if "enum" in raw else None
        if enum is not None:
            if vt.scalar.is_float or vt.scalar.is_bool:
                self.fail(parts + ["enum"], "an enum needs integer values")
            misfits = [v.name for v in enum.values if not vt.scalar.min <= v.value <= vt.scalar.max]
            if misfits:
                self.fail(parts + ["enum"], f"enum '{enum.name}' has codes that do not fit {raw['type']}: "
                                            f"{', '.join(misfits)}")
        bits = items.bits_of(raw.get("bits", []))
        if bits and (vt.count > 1 or not vt.scalar.is_integer or enum is not None or "unit" in raw):
            self.fail(parts + ["bits"], "bits need one integer with no enum and no unit")
        elif bits and len(bits) > vt.scalar.bits:
            self.fail(parts + ["bits"], f"{len(bits)} bit names do not fit in {raw['type']}")
        named = items.items_of(self, parts, sets, raw.get("item_names"), vt.count, raw.get("unit")) \
            if vt.count > 1 or "item_names" in raw else ()
        return enum, bits, named


def _runs_to_end(f) -> bool:
    return isinstance(f, (model.NamesField, model.RecipeValuesField)) or \
        (isinstance(f, ir.StringField) and f.length is None)


def resolve(spec: LoadedSpec) -> model.Interface:
    r = _TypedResolver(spec)
    interface = r.resolve_interface()
    if r.problems:
        raise SpecError(spec.source, r.problems)
    return interface
