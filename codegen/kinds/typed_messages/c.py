"""C target of the typed-messages kind: the plan -> a view model -> templates/c/typed_messages/ ->
generated/c/<name>.{h,c}, with the hand-written runtime of runtime/c/<name>_*.{h,c} joined in
(each section naming its file). C99, no malloc: the connection's state is the caller's struct.

Every decision (C types, member kinds, tables) is made here; the templates lay them out."""
from __future__ import annotations

from dataclasses import dataclass

from ... import ir
from ...emit import environment, runtime_section
from ...lang import c
from ...wrap import trailing
from . import model
from ...lang.c_pool import PART, Pool
from .plan import Step, TypedPlan

FOLDER = "c"
C_TYPES = {"bool": "uint8_t", "int8": "int8_t", "uint8": "uint8_t", "int16": "int16_t", "uint16": "uint16_t",
           "int32": "int32_t", "uint32": "uint32_t", "int64": "int64_t", "uint64": "uint64_t",
           "float32": "float", "float64": "double"}
# How a scalar is read: an expression over the reader's next bytes (runtime/c/typed_messages/rtde_read.c).
READERS = {"bool": "rtde__take(r, 1)", "uint8": "rtde__take(r, 1)", "uint16": "rtde__take(r, 2)",
           "uint32": "rtde__take(r, 4)", "uint64": "rtde__take(r, 8)", "int32": "rtde__as_i32(rtde__take(r, 4))",
           "float64": "urwire__f64_of(rtde__take(r, 8))"}
MEMBER_KINDS = {"bool": "RTDE_MEMBER_BOOL", "uint8": "RTDE_MEMBER_UINT", "uint16": "RTDE_MEMBER_UINT",
                "uint32": "RTDE_MEMBER_UINT", "uint64": "RTDE_MEMBER_UINT", "int32": "RTDE_MEMBER_INT",
                "float64": "RTDE_MEMBER_F64"}
# A value type's items as the runtime reads them: 'u' unsigned, 'i' signed, 'f' float.
VALUE_KIND = {"bool": "'b'", "uint8": "'u'", "uint32": "'u'", "uint64": "'u'", "int32": "'i'", "float64": "'f'"}
# The inline readers' item types and loads (runtime/c/common/loads.h, joined into the header).
ITEM_TYPES = {"bool": "bool", "uint8": "uint8_t", "uint32": "uint32_t", "uint64": "uint64_t", "int32": "int32_t",
              "float64": "double"}
ITEM_LOADS = {"bool": "urwire__u8({}) != 0", "uint8": "urwire__u8({})", "uint32": "urwire__u32({})",
              "uint64": "urwire__u64({})", "int32": "urwire__i32({})", "float64": "urwire__f64({})"}
RUNTIME_H = ("rtde_types.h", "rtde_api.h", "rtde_values.h")
# The loads the inline readers need join the header, and the .c has them from there.
RUNTIME_H_COMMON = ("common/macros.h", "common/loads.h")
RUNTIME_C = {"read": ("typed_messages/rtde_read.c",),
             "variables": ("typed_messages/rtde_variables.c",),
             "conversation": ("typed_messages/rtde_conversation.c",)}


@dataclass
class MemberView:
    name: str
    ctype: str
    kind: str                 # RTDE_MEMBER_*: how the JSON writer reads it
    reader: str = ""
    size: int = 0
    prefix: int = 0
    comment: str = ""


def _member(f) -> MemberView:
    if isinstance(f, model.NamesField):
        return MemberView(f.name, "rtde_text", "RTDE_MEMBER_NAMES", comment=f.label)
    if isinstance(f, model.RecipeValuesField):
        return MemberView(f.name, "rtde_data", "RTDE_MEMBER_VALUES", comment=f.label)
    if isinstance(f, ir.StringField):
        if f.length is None:
            return MemberView(f.name, "rtde_text", "RTDE_MEMBER_TEXT", comment=f.label)
        return MemberView(f.name, "rtde_text", "RTDE_MEMBER_TEXT", prefix=f.length.size,
                          comment=f.label)
    s = f.scalar.name
    comment = f.label + (f" ({f.unit})" if f.unit else "") + (f"; enum {f.enum.name}" if f.enum else "")
    return MemberView(f.name, C_TYPES[s], MEMBER_KINDS[s], READERS[s], f.scalar.size, comment=comment)


@dataclass
class StepView:
    """A step of the plan as the decoder template reads it."""
    kind: str                 # run | text | prefixed_text | values
    members: list[MemberView]
    size: int = 0

    @property
    def reads(self) -> list[str]:
        """A run's assignments, one statement per member."""
        return [f"out->{m.name} = ({m.ctype}){m.reader};" for m in self.members]


# A plan step's kind as the C decoder reads it: a text running to the end is one, names or not.
STEP_KINDS = {"run": "run", "names": "text", "rest_text": "text", "prefixed_text": "prefixed_text",
              "values": "values"}


def _step(step: Step, members: dict[str, MemberView]) -> StepView:
    return StepView(STEP_KINDS[step.kind], [members[f.name] for f in step.fields],
                    step.size if step.kind == "run" else 0)


@dataclass
class ReaderView:
    """The inline reader of one value type: rtde_data_<type>(d, index, out)."""
    name: str                 # vector6d
    type_const: str           # RTDE_VT_VECTOR6D
    param: str                # double out[6], or double *out for one item
    count: int
    load: str                 # an item's load: from p, or from p + its size * k
    comment: str


def _reader(t: model.ValueType, prefix: str) -> ReaderView:
    ctype, size = ITEM_TYPES[t.scalar.name], t.scalar.size
    param = f"{ctype} out[{t.count}]" if t.count > 1 else f"{ctype} *out"
    load = ITEM_LOADS[t.scalar.name].format(f"p + {size} * k" if t.count > 1 else "p")
    return ReaderView(t.name.lower(), f"{prefix.upper()}_VT_{t.name}", param, t.count, load,
                      f"Value `index` of type {t.name}. {t.doc}")


def _kind(index) -> int:
    return -1 if index is None else index


def render(planned: TypedPlan, banner: list[str]) -> dict[str, str]:
    interface = planned.interface
    name = interface.name
    layouts = []
    for mp in planned.messages:
        m = mp.message
        members = [_member(f) for f in m.fields]
        by_name = {member.name: member for member in members}
        layouts.append({
            "name": m.name, "const": f"{name.upper()}_LAYOUT_{m.name.upper()}", "label": m.label,
            "code": m.code, "letter": m.letter, "from_robot": "true" if m.from_robot else "false",
            "protocols": m.protocols, "members": members, "steps": [_step(s, by_name) for s in mp.steps],
            "request_kind": _kind(mp.request_kind),
            "has_recipe_id": "true" if m.recipe_values and m.field_named("recipe_id") else "false",
            "is_data": "true" if m.recipe_values else "false",
        })
    dispatch = [{"code": mp.message.code, "letter": mp.message.letter,
                 "from_robot": "true" if mp.message.from_robot else "false", "protocol": p,
                 "const": f"{name.upper()}_LAYOUT_{mp.message.name.upper()}"}
                # Data packages are nearly every message of a connection: the scan finds them first.
                for mp, p in sorted(planned.dispatch, key=lambda d: not d[0].message.recipe_values)]
    view = {
        "banner": banner, "p": interface, "prefix": name, "PREFIX": name.upper(),
        "value_types": [{"name": t.name, "size": t.scalar.size, "count": t.count, "kind": VALUE_KIND[t.scalar.name],
                         "value_size": t.size}
                        for t in interface.value_types],
        "layouts": layouts, "dispatch": dispatch, "codes": planned.codes,
        "variables": _variable_table(interface.variables, name.upper()),
        "refusals": [r.word for r in interface.refusals],
        "refusal_width": max(len(r.word.encode("utf-8")) for r in interface.refusals) + 1,
        "value_type_width": max(len(t.name.encode("utf-8")) for t in interface.value_types) + 1,
        "undocumented": interface.undocumented,
        "readers": [_reader(t, name) for t in interface.value_types],
        "runtime_h": {**{n: _joined(n) for n in RUNTIME_H},
                      **{n: runtime_section("c", n) for n in RUNTIME_H_COMMON}},
        "runtime_c": {part: "\n\n".join(runtime_section("c", n) for n in names) for part, names in RUNTIME_C.items()},
    }
    env = environment(FOLDER)
    env.filters["c"] = c.string
    return {f"{FOLDER}/{name}.h": env.get_template("typed_messages/interface.h.j2").render(**view),
            f"{FOLDER}/{name}.c": env.get_template("typed_messages/interface.c.j2").render(**view)}


# The columns of the variable table that few texts fill: each row holds an index in a list of these
# words (its texts in the pool), a byte where a pool offset takes two. Index 0 is no unit.
SINCE = ("cb3", "eseries", "polyscope_x")


def _variable_table(variables: list[model.Variable], prefix: str) -> dict:
    """The variable table as small integers: each row's name and label as offsets in one pool of
    texts, its unit and first versions as indices in a short list of words."""
    words = list(dict.fromkeys([v.unit for v in variables if v.unit] +
                               [v.since_text(g) for v in variables for g in SINCE]))
    if len(words) > 255:
        raise ValueError(f"{len(words)} units and versions in the variable table: its rows index them with a byte")
    index = {w: i + 1 for i, w in enumerate(words)}
    pool = Pool([t for v in variables for t in (v.name, v.label)] + words)
    rows = []
    for v in variables:
        items = [str(pool.offset(v.name)), str(pool.offset(v.label)), f"{prefix}_VT_{v.value_type.name}",
                 "true" if v.direction == "output" else "false", str(index[v.unit] if v.unit else 0),
                 "{" + ", ".join(str(index[v.since_text(g)]) for g in SINCE) + "}"]
        rows.append(trailing("{" + ", ".join(items) + "},", v.name, "    "))
    return {"pool": pool.parts, "part_limit": PART, "words": [(pool.offset(w), w) for w in words], "rows": rows,
            "count": len(variables)}


def _joined(file: str) -> str:
    return runtime_section("c", f"typed_messages/{file}")
