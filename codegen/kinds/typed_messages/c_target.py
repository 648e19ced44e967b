"""C target of the typed-messages kind: the IR -> a view model -> templates/c/typed_messages/ ->
generated/c/<name>.{h,c}, with the hand-written runtime of runtime/c/typed_messages/<name>_*.{h,c} joined in
(each section naming its file). C99, no malloc: the connection's state is the caller's struct.

Every decision (C types, member kinds, tables) is made here; the templates lay them out."""
from __future__ import annotations

import json
from dataclasses import dataclass

from ... import ir
from ...emit import environment, runtime_section
from ...wrap import spread
from . import model

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
RUNTIME_H = ("rtde_types.h", "rtde_api.h")
RUNTIME_C = {"read": ("common/macros.h", "common/loads.h", "typed_messages/rtde_read.c"),
             "conversation": ("typed_messages/rtde_conversation.c",)}


@dataclass
class MemberView:
    name: str
    ctype: str
    kind: str                 # RTDE_MEMBER_*: how the JSON writer reads it
    step: str                 # scalar | text | prefixed_text | values
    reader: str = ""
    size: int = 0
    prefix: int = 0
    comment: str = ""


def _member(f) -> MemberView:
    if isinstance(f, model.NamesField):
        return MemberView(f.name, "rtde_text", "RTDE_MEMBER_NAMES", "text", comment=f.label)
    if isinstance(f, model.RecipeValuesField):
        return MemberView(f.name, "rtde_data", "RTDE_MEMBER_VALUES", "values", comment=f.label)
    if isinstance(f, ir.StringField):
        if f.length is None:
            return MemberView(f.name, "rtde_text", "RTDE_MEMBER_TEXT", "text", comment=f.label)
        return MemberView(f.name, "rtde_text", "RTDE_MEMBER_TEXT", "prefixed_text", prefix=f.length.size,
                          comment=f.label)
    s = f.scalar.name
    comment = f.label + (f" ({f.unit})" if f.unit else "") + (f"; enum {f.enum.name}" if f.enum else "")
    return MemberView(f.name, C_TYPES[s], MEMBER_KINDS[s], "scalar", READERS[s], f.scalar.size, comment=comment)


@dataclass
class StepView:
    """How the decoder reads: consecutive scalars as one run behind one bounds check (named by its
    first field, as the Python decoder's struct run is), every other field alone."""
    kind: str                 # run | text | prefixed_text | values
    members: list[MemberView]
    size: int = 0

    @property
    def reads(self) -> list[str]:
        """A run's assignments, one statement per member."""
        return [f"out->{m.name} = ({m.ctype}){m.reader};" for m in self.members]


def _steps(members: list[MemberView]) -> list[StepView]:
    steps: list[StepView] = []
    for m in members:
        if m.step == "scalar" and steps and steps[-1].kind == "run":
            steps[-1].members.append(m)
            steps[-1].size += m.size
        elif m.step == "scalar":
            steps.append(StepView("run", [m], m.size))
        else:
            steps.append(StepView(m.step, [m]))
    return steps


def _c_string(text) -> str:
    return "NULL" if text is None else json.dumps(text, ensure_ascii=False)


def render(interface: model.Interface, banner: list[str]) -> dict[str, str]:
    name = interface.name
    kinds = {k.name: i for i, k in enumerate(interface.recipe_kinds)}
    kind_of_request = {m.name: kinds[k.name] for k in interface.recipe_kinds for m in k.requests}
    kind_of_reply = {m.name: kinds[k.name] for k in interface.recipe_kinds for m in k.replies}
    layouts = []
    for m in interface.messages:
        members = [_member(f) for f in m.fields]
        layouts.append({
            "name": m.name, "const": f"{name.upper()}_LAYOUT_{m.name.upper()}", "label": m.label,
            "code": m.code, "letter": m.letter, "from_robot": "true" if m.from_robot else "false",
            "protocols": m.protocols, "members": members, "steps": _steps(members),
            "request_kind": kind_of_request.get(m.name, -1), "reply_kind": kind_of_reply.get(m.name, -1),
            "has_recipe_id": "true" if m.recipe_values and m.field_named("recipe_id") else "false",
            "is_data": "true" if m.recipe_values else "false",
        })
    dispatch = [{"code": m.code, "letter": m.letter, "from_robot": "true" if m.from_robot else "false", "protocol": p,
                 "const": f"{name.upper()}_LAYOUT_{m.name.upper()}"} for m in interface.messages for p in m.protocols]
    codes = sorted({(m.code, m.letter) for m in interface.messages} | {(u.code, chr(u.code)) for u in interface.undocumented})
    variables = []
    for v in interface.variables:
        items = [_c_string(v.name), f"{name.upper()}_VT_{v.value_type.name}", "true" if v.direction == "output" else "false",
                 _c_string(v.label), _c_string(v.unit), _c_string(v.since_text("cb3")), _c_string(v.since_text("eseries"))]
        variables.append(spread(items, "{", "},", "    "))
    view = {
        "banner": banner, "p": interface, "prefix": name, "PREFIX": name.upper(),
        "value_types": [{"name": t.name, "size": t.scalar.size, "count": t.count, "kind": VALUE_KIND[t.scalar.name]}
                        for t in interface.value_types],
        "layouts": layouts, "dispatch": dispatch, "codes": codes, "variables": variables,
        "refusals": [r.word for r in interface.refusals],
        "undocumented": interface.undocumented,
        "runtime_h": {n: _joined(n) for n in RUNTIME_H},
        "runtime_c": {part: "\n\n".join(runtime_section("c", n) for n in names) for part, names in RUNTIME_C.items()},
    }
    env = environment(FOLDER)
    return {f"{FOLDER}/{name}.h": env.get_template("typed_messages/interface.h.j2").render(**view),
            f"{FOLDER}/{name}.c": env.get_template("typed_messages/interface.c.j2").render(**view)}


def _joined(file: str) -> str:
    return runtime_section("c", f"typed_messages/{file}")
