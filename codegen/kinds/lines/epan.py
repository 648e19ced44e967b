"""The epan target of a text-line interface: generated/epan/packet-<name>.c, a native Wireshark
dissector as an upstream epan/dissectors/packet-*.c reads, the twin of the Lua one
(generated/lua/<name>.lua): the same protocol, fields, expert infos, preference and ports. The
spec's tables as C data, with runtime/c/lines/match.{h,c}, runtime/c/common/version_text.{h,c} and
runtime/epan/lines/lines_dissect.c joined in, from the plan."""
from __future__ import annotations

import json
from dataclasses import dataclass

from ...emit import environment, runtime_section
from ...wrap import lines as wrapped
from ...naming import column_name
from .model import Reply
from .plan import LinesPlan

FOLDER = "epan"
# Before the tables: their types and the matcher over them, and the reader of a version's text, the
# C library's own (runtime/c/lines/, runtime/c/common/); after them, the dissector itself.
RUNTIME_TYPES = (("c", "common/macros.h"), ("c", "common/version_text.h"), ("c", "common/version_text.c"),
                 ("c", "lines/match.h"), ("c", "lines/match.c"))
RUNTIME_DISSECTOR = ("lines/lines_dissect.c",)


@dataclass(frozen=True)
class Field:
    name: str
    type: str
    display: str


# The fields of every line, in the order the Lua runtime (runtime/lua/lines_dissect.lua) declares
# them; their labels are the spec's.
FIELDS = (Field("command", "FT_STRING", "BASE_NONE"), Field("command_name", "FT_STRING", "BASE_NONE"),
          Field("argument", "FT_STRING", "BASE_NONE"), Field("available", "FT_BOOLEAN", "BASE_NONE"),
          Field("reply", "FT_STRING", "BASE_NONE"), Field("reply_name", "FT_STRING", "BASE_NONE"),
          Field("error", "FT_BOOLEAN", "BASE_NONE"))


@dataclass(frozen=True)
class Expert:
    name: str
    group: str
    severity: str
    text: str


def experts(max_line: int) -> tuple[Expert, ...]:
    """The expert infos, named, grouped and worded as the Lua runtime's. (Its internal_error, a Lua
    error caught while dissecting, has no native twin.)"""
    return (Expert("error_reply", "PI_RESPONSE_CODE", "PI_WARN", "The reply says an error"),
            Expert("unknown_command", "PI_MALFORMED", "PI_WARN", "Unknown command"),
            Expert("unavailable", "PI_PROTOCOL", "PI_WARN", "The software version lacks this command"),
            Expert("too_long", "PI_MALFORMED", "PI_ERROR", f"Line longer than {max_line} bytes"),
            Expert("not_kept", "PI_SEQUENCE", "PI_ERROR", "Command not kept: more than 256 commands awaited replies"),
            Expert("reply_not_kept", "PI_SEQUENCE", "PI_ERROR",
                   "Reply to a command that was not kept: more than 256 commands awaited replies"))


# The version preference, as the Lua runtime names and words it.
PREFERENCE = ("version", "Software version",
              "Controller software version (as 5.11 or 3.15.7) assumed until a PolyscopeVersion reply tells it: "
              "commands it lacks are flagged. Empty: none assumed.")


def _string(text: str) -> str:
    """A C string literal (the schema keeps spec texts printable ASCII; JSON escapes suit C)."""
    return json.dumps(text)


def _literals(text: str) -> list[str]:
    """Prose as adjacent C string literals, one per line, that C joins into one string."""
    words = wrapped(text, "", "", width=90)
    return [_string(w + " ") for w in words[:-1]] + [_string(words[-1])]


def _reply(reply: Reply) -> dict:
    return dict(pattern=reply.pattern, name=_string(reply.name), pieces=[_string(p) for p in reply.pieces],
                error="true" if reply.error else "false")


def file_name(name: str) -> str:
    """packet-ur-dashboard.c: upstream's name for the dissector of protocol ur_dashboard."""
    return f"packet-{name.replace('_', '-')}.c"


def view(p: LinesPlan) -> dict:
    m = p.model
    name = m.name
    commands = [dict(comment=f"{c.command.text}{' <' + c.command.argument + '>' if c.command.argument else ''}: "
                             f"{c.command.doc} ({c.command.since_text()})",
                     name=_string(c.command.name), text=_string(c.command.text),
                     argument="true" if c.command.argument else "false",
                     since_cb=f"{c.since_cb or 0}u", since_e_series=f"{c.since_e_series or 0}u",
                     replies=[_reply(r) for r in c.command.replies])
                for c in p.commands]
    return dict(
        file=file_name(name), name=name, title=m.title, doc=wrapped(m.doc, " * ", " * "),
        title_literal=_string(m.title),
        short_name=_string(name.upper()), column=_string(column_name(name)), ports=list(m.ports),
        max_line=m.max_line,
        fields=[dict(name=f.name, label=_string(m.fields[f.name].label), abbrev=_string(f"{name}.{f.name}"),
                     type=f.type, display=f.display, blurb=_string(m.fields[f.name].doc)) for f in FIELDS],
        experts=[dict(name=e.name, abbrev=_string(f"{name}.{e.name}"), group=e.group, severity=e.severity,
                      text=_string(e.text)) for e in experts(m.max_line)],
        preference=dict(name=_string(PREFERENCE[0]), title=_string(PREFERENCE[1]), doc=_literals(PREFERENCE[2])),
        banner_reply=_reply(m.banner) if m.banner else None,
        robot_is_client="true" if m.robot_is_client else "false",
        requests_from_robot="true" if m.requests_from_robot else "false",
        one_reply_per_request="true" if m.one_reply_per_request else "false",
        common=[_reply(r) for r in m.common_replies], commands=commands,
        lookup=[str(c.index) for c in p.lookup],
        version_command=f"{p.version_command.index},  /* {p.version_command.command.name} */" if p.version_command
        else "LINES_NONE,",
        version_prefix=_string(m.version_prefix), e_series_from=f"{p.e_series_from}u",
        runtime_types="\n\n".join(runtime_section(language, name) for language, name in RUNTIME_TYPES),
        runtime_dissector="\n\n".join(runtime_section(FOLDER, name) for name in RUNTIME_DISSECTOR),
    )


def render(p: LinesPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """`upstream` (the copy for Wireshark's tree) changes nothing: this dissector reads no command line."""
    text = environment(FOLDER).get_template("lines/packet.c.j2").render(banner=banner, **view(p))
    return {f"{FOLDER}/{file_name(p.model.name)}": text}
