"""Random VALID messages, generated from the spec's IR: every layout, every field kind, in the
form a given software version sends (`versions()` lists one version per form of every type code,
so every controller generation is covered).

Used by property tests: whatever these bytes hold, a decoder must read them without error,
unknown part or extra bytes, and encoding must give the same bytes back.
"""
from __future__ import annotations

import random
import struct

from codegen import ir
from codegen.kinds.packages import model
from codegen.compile import compile_file
from codegen.kinds.packages.plan import plan

PROTOCOL = compile_file()


def versions() -> list[tuple[int, int, int]]:
    """One software version for every form of every type code (the version each form stands
    for), the default included: every generation the spec knows, oldest first."""
    found = {PROTOCOL.default_version} | {r.low for _, r in PROTOCOL.generations if r.low}
    for mp in plan(PROTOCOL).messages:
        for forms in mp.variants.values():
            found |= {(v.rep[0], v.rep[1], 0 if v.rep[2] == ir.BUGFIX_ANY else v.rep[2]) for v in forms}
    return sorted(found)
_CODES = {"bool": "B", "int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i", "uint32": "I",
          "int64": "q", "uint64": "Q", "float32": "f", "float64": "d"}


class _Gen:
    def __init__(self, rng: random.Random, version: tuple[int, int, int]):
        self.rng = rng
        self.version = version

    def text(self, max_len: int, forbid: int | None = None) -> bytes:
        n = self.rng.randint(0, max_len)
        alphabet = list(range(256)) if forbid is None else [b for b in range(256) if b != forbid]
        return bytes(self.rng.choice(alphabet) for _ in range(n))

    def scalar(self, s: ir.Scalar, enum: ir.Enum | None = None) -> tuple[bytes, int]:
        if enum is not None and self.rng.random() < 0.7:
            value = self.rng.choice(enum.table_for(self.version).values).value
            return struct.pack(">" + _CODES[s.name], value), value
        raw = bytes(self.rng.randrange(256) for _ in range(s.size))
        value = struct.unpack(">" + _CODES[s.name], raw)[0] if s.is_integer or s.is_bool else 0
        return raw, value

    def struct(self, st: ir.Struct, announce: tuple = ()) -> bytes:
        """`announce` names the major, minor and bugfix fields of a Version message: they carry
        the generator's own version, as a controller's do."""
        out = b""
        values: dict[str, int] = {}
        numbers = dict(zip(announce, self.version))
        for f in st.fields:
            if f.present_if is not None and not values.get(f.present_if):
                continue
            if not f.versions.contains(self.version):
                continue
            if f.name in numbers:
                out += struct.pack(">" + _CODES[f.scalar.name], numbers[f.name])
                continue
            out += self.field(f, values)
        return out

    def field(self, f: ir.AnyField, values: dict[str, int]) -> bytes:
        rng = self.rng
        if isinstance(f, ir.ScalarField):
            raw, values[f.name] = self.scalar(f.scalar, f.enum)
            return raw
        if isinstance(f, ir.ArrayField):
            return b"".join(self.scalar(f.scalar, f.enum)[0] for _ in range(f.count))
        if isinstance(f, ir.GroupField):
            n = f.count if f.count is not None else rng.randint(0, 4)
            return b"".join(self.struct(f.item) for _ in range(n))
        if isinstance(f, ir.StringField):
            if f.length is None:
                return self.text(40)
            body = self.text(min(f.length.max, 60))
            return struct.pack(">" + _CODES[f.length.name], len(body)) + body
        if isinstance(f, ir.StringListField):
            return b"".join(self.text(12, forbid=f.terminator) + bytes((f.terminator,)) for _ in range(rng.randint(0, 5)))
        if isinstance(f, ir.BytesField):
            return self.text(50)
        if isinstance(f, ir.SwitchField):
            chosen = f.cases.get(values.get(f.selector.name, -1), f.default)
            return self.scalar(chosen)[0]
        assert isinstance(f, ir.ValueListField)
        table = f.value_type.table_for(self.version)
        return b"".join(self.value(table, 1) + bytes((f.terminator,)) for _ in range(rng.randint(0, 4)))

    def value(self, table: ir.EnumTable, depth: int) -> bytes:
        rng = self.rng
        choices = [v for v in table.values
                   if depth < PROTOCOL.max_value_depth or PROTOCOL.value_layouts[v.name].layout not in ("list", "matrix")]
        kind = rng.choice(choices)
        lay = PROTOCOL.value_layouts[kind.name]
        out = bytes((kind.value,))
        if lay.layout == "empty":
            return out
        if lay.layout == "scalar":
            return out + self.scalar(lay.item)[0]
        if lay.layout == "array":
            return out + b"".join(self.scalar(lay.item)[0] for _ in range(lay.count))
        if lay.layout == "string":
            body = self.text(20)
            return out + struct.pack(">h", len(body)) + body
        if lay.layout == "list":
            n = rng.randint(0, 3)
            return out + struct.pack(">h", n) + b"".join(self.value(table, depth + 1) for _ in range(n))
        rows, cols = rng.randint(0, 3), rng.randint(0, 3)
        if cols == 0:
            rows = 0   # rows of 0 columns are an error: they would take no bytes
        return out + struct.pack(">hh", rows, cols) + b"".join(
            self.value(table, depth + 1) for _ in range(rows * cols))


def message(rng: random.Random, version: tuple[int, int, int] = PROTOCOL.default_version) -> bytes:
    """One valid message of a random laid-out kind, in the form `version` sends it."""
    gen = _Gen(rng, version)
    m = rng.choice(PROTOCOL.messages)
    if isinstance(m, model.PackageListMessage):
        body = b""
        packages = [pkg for pkg in m.packages if pkg.versions.contains(version)]
        for pkg in rng.sample(packages, rng.randint(0, len(packages))):
            payload = gen.struct(pkg.struct)
            body += struct.pack(">iB", len(payload) + 5, pkg.code.value) + payload
    else:
        sub = rng.choice([s for s in m.subtypes if s.versions.contains(version)])
        header = b"".join(gen.field(f, {}) for f in m.header.fields)
        subtype = struct.pack(">B", sub.code.value) if m.has_subtype else b""   # none in a body message
        body = header + subtype + gen.struct(sub.struct, sub.sets_version or ())
    return struct.pack(">iB", len(body) + 5, m.code.value) + body


def version_message(rng: random.Random, version: tuple[int, int, int]) -> bytes:
    """A Version message that announces `version`, in that version's form."""
    gen = _Gen(rng, version)
    for m in PROTOCOL.messages:
        for sub in getattr(m, "subtypes", []):
            if sub.sets_version:
                header = b"".join(gen.field(f, {}) for f in m.header.fields)
                body = header + struct.pack(">B", sub.code.value) + gen.struct(sub.struct, sub.sets_version)
                return struct.pack(">iB", len(body) + 5, m.code.value) + body
    raise LookupError("no layout sets the version")


def session(rng: random.Random, version: tuple[int, int, int], count: int) -> bytes:
    """What a controller of `version` sends a new client: its Version message, then `count`
    random valid messages of its forms."""
    return version_message(rng, version) + b"".join(message(rng, version) for _ in range(count))
