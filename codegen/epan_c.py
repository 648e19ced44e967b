"""What the epan renderers of every kind write alike in C beside codegen/lang/c.py: the labels of
float fields with a unit.

A float field's unit is shown by a label function (BASE_CUSTOM), as the Lua dissector shows it
(" rad" after the value). Wireshark 4.0 shows no unit string of a float field; appending the unit
to each item instead would build every label while dissecting, where Wireshark builds a label
only when the tree is printed (`tshark -T fields` builds the whole tree and prints none of it)."""
from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass(frozen=True)
class UnitLabel:
    """The label function of float fields with one unit: the value as Wireshark prints the field's
    type (%.*g with DBL_DIG or FLT_DIG digits), then the unit as the Lua dissector appends it."""
    ident: str      # ur_label_rad_s_double
    digits: str     # DBL_DIG or FLT_DIG
    suffix: str     # " rad/s"


def unit_label(prefix: str, unit: str, double: bool = True) -> UnitLabel:
    """The label function of a float field of `unit`, its name under `prefix`."""
    spelled = unit.replace("²", "2").replace("³", "3").replace("°", "deg").replace("/", "_per_")
    spelled = re.sub(r"[^0-9A-Za-z]+", "_", spelled).strip("_").lower() or "unit"
    kind = "double" if double else "float"
    return UnitLabel(f"{prefix}_label_{spelled}_{kind}", "DBL_DIG" if double else "FLT_DIG", " " + unit)


# ---- the upstream copy: the style of Wireshark's development branch ----
#
# Wireshark's development branch declares its handles zero-initialised (`static int proto_eti;`,
# `static int hf_eti_x;`, `static int ett_eti;`, as its generated packet-eti.c does). The in-tree
# plugin keeps `= -1` for the Wireshark 4.0 it builds against; the upstream copy (`--upstream`)
# drops it from its protocol, field and subtree handles. 4.0 registers a zero `proto_` or `hf_`
# handle but refuses a zero `ett_` one ("subtree item type (ett_...) not -1"): the out-of-tree
# build of this copy against 4.0 gives them -1 as it registers them (dissector/native/
# subtrees_from_zero.h). One rule over the rendered file, for the generated part and the joined
# runtime alike.
DEVELOPMENT_BRANCH_HANDLES = ("proto", "hf", "ett")
_HANDLE_INIT = re.compile(rf"\b((?:{'|'.join(DEVELOPMENT_BRANCH_HANDLES)})_\w+) = -1\b")
_HANDLE_ARRAY = re.compile(r"^(static int hf_\w+\[\w+\]) = \{\n(?:\s*(?:-1,\s*)+\n)*\s*(?:-1,?\s*)*\};", re.M)
_DECLARATION = re.compile(r"^static (?:int|gint) [^;(]*;", re.M)


def development_branch(text: str) -> str:
    """The rendered file with its protocol, field and subtree handles declared without `= -1`."""
    text = _HANDLE_ARRAY.sub(r"\1;", text)
    return _DECLARATION.sub(lambda m: _HANDLE_INIT.sub(r"\1", m.group(0)), text)
