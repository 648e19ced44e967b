"""What the epan renderers of every kind write alike in C: string literals, value_string values,
and units.

A spec unit -> the `unit_name_string` a field's BASE_UNIT_STRING display names: Wireshark's own
(epan/unit_strings.h) where it has the unit, else one the generated file defines
(`static const unit_name_string`), named after the unit.

Wireshark's abbreviations carry no space ("48V", "30.5°C"); its names do (" seconds"), and so do
the project's own (" rad"), which read as the Lua dissector's appended units do."""
from __future__ import annotations

import re
from dataclasses import dataclass

# Spec unit -> Wireshark 4.0's unit_name_string for it.
WIRESHARK = {
    "s": "units_second_seconds",
    "m": "units_meter_meters",
    "V": "units_volt",
    "A": "units_amp",
    "°C": "units_degree_celsius",
    "Nm": "units_newton_metre",
    "m/s": "units_meter_sec",
    "m/s²": "units_meter_sec_squared",
    "%": "units_percent",
}


@dataclass(frozen=True)
class OwnUnit:
    """A unit Wireshark does not name: the generated file defines it."""
    ident: str      # units_rad_s
    text: str       # " rad/s"


def unit_ident(unit: str) -> str:
    """The C name of a unit: Wireshark's, or units_<unit> with its symbols spelled out."""
    if unit in WIRESHARK:
        return WIRESHARK[unit]
    spelled = unit.replace("²", "2").replace("³", "3").replace("°", "deg").replace("/", "_per_")
    return "units_" + re.sub(r"[^0-9A-Za-z]+", "_", spelled).strip("_").lower()


def own_units(units: list[str]) -> list[OwnUnit]:
    """The units of `units` that the generated file must define, once each, in first-seen order."""
    seen = dict.fromkeys(u for u in units if u and u not in WIRESHARK)
    return [OwnUnit(unit_ident(u), " " + u) for u in seen]


def c_string(text: str) -> str:
    """A C string literal of text (UTF-8 as it is; quotes and backslashes escaped)."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def value_literal(value: int) -> str:
    """A value_string's value: a guint32, a negative code as its two's complement (-1 is 0xffffffff),
    which is what a signed field's value is looked up as."""
    return str(value) if value >= 0 else f"(guint32){value}"
