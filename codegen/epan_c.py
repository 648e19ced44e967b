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
