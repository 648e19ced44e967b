"""The Wireshark model of a text-line interface, computed once from the plan: the fields every line
shows (with the spec's labels and descriptions), the expert infos, the version preference and the
Protocol column, as plain data that lua.py and epan.py both render. Much of the dissector is the
hand-written runtime (runtime/lua/lines/*.lua, runtime/epan/lines_*.c); the model is what the
two must show alike."""
from __future__ import annotations

from dataclasses import dataclass

from ... import exchanges
from ...naming import column_name
from .model import RecordField
from .plan import LinesPlan

PENDING_KEPT = 256              # commands awaiting a reply that a conversation keeps (both runtimes)


@dataclass(frozen=True)
class Field(RecordField):
    """A spec field (filtered as <protocol>.<name>) with the type the runtimes give it."""
    type: str = "string"        # string or boolean


@dataclass(frozen=True)
class Expert:
    name: str                   # filtered as <protocol>.<name>
    group: str                  # Wireshark's PI_ group
    severity: str               # PI_WARN, PI_ERROR
    text: str


@dataclass(frozen=True)
class Preference:
    name: str
    title: str
    doc: str


@dataclass(frozen=True)
class Dissector:
    plan: LinesPlan
    column: str                 # what the Protocol column shows
    fields: tuple[Field, ...]   # in the order the runtimes declare them
    experts: tuple[Expert, ...]
    preference: Preference
    # A command's link to its reply and a reply's to its command: in order (one_reply_per_request),
    # else every answering line's to the latest request.
    exchange_fields: tuple[exchanges.ExchangeField, ...] = exchanges.FIELDS

    def expert(self, name: str) -> Expert:
        return next(e for e in self.experts if e.name == name)


# The fields of every line, in the order the runtimes declare them, and their types.
FIELD_TYPES = (("command", "string"), ("command_name", "string"), ("argument", "string"),
               ("available", "boolean"), ("reply", "string"), ("reply_name", "string"), ("error", "boolean"))


def _experts(max_line: int) -> tuple[Expert, ...]:
    """The expert infos. (The Lua runtime's internal_error, a Lua error caught while dissecting, has
    no native twin and is the runtime's own.)"""
    return (Expert("error_reply", "PI_RESPONSE_CODE", "PI_WARN", "The reply says an error"),
            Expert("unknown_command", "PI_MALFORMED", "PI_WARN", "Unknown command"),
            Expert("unavailable", "PI_PROTOCOL", "PI_WARN", "The software version lacks this command"),
            Expert("too_long", "PI_MALFORMED", "PI_ERROR", f"Line longer than {max_line} bytes"),
            Expert("not_kept", "PI_SEQUENCE", "PI_ERROR",
                   f"Command not kept: more than {PENDING_KEPT} commands awaited replies"),
            Expert("reply_not_kept", "PI_SEQUENCE", "PI_ERROR",
                   f"Reply to a command that was not kept: more than {PENDING_KEPT} commands awaited replies"))


PREFERENCE = Preference("version", "Software version",
                        "Controller software version (as 5.11 or 3.15.7) assumed until a PolyscopeVersion reply "
                        "tells it: commands it lacks are flagged. Empty: none assumed.")


def dissector(planned: LinesPlan) -> Dissector:
    m = planned.model
    fields = tuple(Field(name, m.fields[name].label, m.fields[name].doc, type_) for name, type_ in FIELD_TYPES)
    return Dissector(planned, column_name(m.name), fields, _experts(m.max_line), PREFERENCE)
