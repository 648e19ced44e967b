"""The epan target of a text-line interface: generated/epan/packet-<name>.c, a native Wireshark
dissector as an upstream epan/dissectors/packet-*.c reads, the twin of the Lua one
(generated/lua/<name>.lua): the same protocol, fields, expert infos, preference and ports, from
one dissector model (dissector.py). The spec's tables as C data, with runtime/c/lines/match.{h,c},
runtime/c/common/version_text.{h,c} and runtime/epan/lines/lines_dissect.c joined in, from the plan;
request/response links from the helpers every dissector shares (packet-ur-common.h)."""
from __future__ import annotations

from ... import exchanges
from ...emit import environment, runtime_section
from ...epan_c import SHARED_HEADER, development_branch
from ...lang.c import prose, string
from ...wrap import lines as wrapped
from .dissector import Dissector, dissector
from .model import Reply
from .plan import LinesPlan

FOLDER = "epan"
# Before the tables: their types and the matcher over them, and the reader of a version's text, the
# C library's own (runtime/c/lines/, runtime/c/common/); after them, the dissector itself.
RUNTIME_TYPES = (("c", "common/macros.h"), ("c", "common/version_text.h"), ("c", "common/version_text.c"),
                 ("c", "lines/match.h"), ("c", "lines/match.c"))
RUNTIME_DISSECTOR = ("lines/lines_dissect.c",)
FIELD_TYPES = {"string": ("FT_STRING", "BASE_NONE"), "boolean": ("FT_BOOLEAN", "BASE_NONE")}


def _reply(reply: Reply) -> dict:
    return dict(pattern=reply.pattern, name=string(reply.name), pieces=[string(p) for p in reply.pieces],
                error="true" if reply.error else "false")


def file_name(name: str) -> str:
    """packet-ur-dashboard.c: upstream's name for the dissector of protocol ur_dashboard."""
    return f"packet-{name.replace('_', '-')}.c"


def view(d: Dissector) -> dict:
    p = d.plan
    m = p.model
    name = m.name
    commands = [dict(comment=f"{c.command.heading}{' <' + c.command.argument + '>' if c.command.argument else ''}: "
                             f"{c.command.doc} ({c.command.since_text()})",
                     name=string(c.command.name), text=string(c.command.text),
                     argument="true" if c.command.argument else "false",
                     since_cb=f"{c.since_cb or 0}u", since_e_series=f"{c.since_e_series or 0}u",
                     since_polyscope_x=f"{c.since_polyscope_x or 0}u",
                     replies=[_reply(r) for r in c.command.replies])
                for c in p.commands]
    return dict(
        file=file_name(name), name=name, title=m.title, doc=wrapped(m.doc, " * ", " * "),
        title_literal=string(m.title),
        short_name=string(name.upper()), column=string(d.column), ports=list(m.ports),
        max_line=m.max_line,
        fields=[dict(name=f.name, label=string(f.label), abbrev=string(f"{name}.{f.name}"),
                     type=FIELD_TYPES[f.type][0], display=FIELD_TYPES[f.type][1], strings="NULL", blurb=string(f.doc))
                for f in d.fields] + [exchanges.epan_field(f, name) for f in d.exchange_fields],
        experts=[dict(name=e.name, abbrev=string(f"{name}.{e.name}"), group=e.group, severity=e.severity,
                      text=string(e.text)) for e in d.experts],
        preference=dict(name=string(d.preference.name), title=string(d.preference.title),
                        doc=prose(d.preference.doc, "        ")),
        banner_reply=_reply(m.banner) if m.banner else None,
        robot_is_client="true" if m.robot_is_client else "false",
        requests_from_robot="true" if m.requests_from_robot else "false",
        one_reply_per_request="true" if m.one_reply_per_request else "false",
        common=[_reply(r) for r in m.common_replies], commands=commands,
        lookup=[str(c.index) for c in p.lookup],
        version_command=f"{p.version_command.index},  /* {p.version_command.command.name} */" if p.version_command
        else "LINES_NONE,",
        shared_header=SHARED_HEADER, version_prefix=string(m.version_prefix), e_series_from=f"{p.e_series_from}u",
        polyscope_x_from=f"{p.polyscope_x_from}u",
        runtime_types="\n\n".join(runtime_section(language, name) for language, name in RUNTIME_TYPES),
        runtime_dissector="\n\n".join(runtime_section(FOLDER, name) for name in RUNTIME_DISSECTOR),
    )


def render(p: LinesPlan, banner: list[str], upstream: bool = False) -> dict[str, str]:
    """`upstream`: the copy for Wireshark's tree, in its development branch's style (this dissector
    reads no command line)."""
    env = environment(FOLDER)
    env.filters["c"] = string
    text = env.get_template("lines/packet.c.j2").render(banner=banner, **view(dissector(p)))
    return {f"{FOLDER}/{file_name(p.model.name)}": development_branch(text) if upstream else text}
