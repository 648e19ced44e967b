"""The C target of a text-line interface: generated/c/<name>.{h,c}, the tables as C data and the
runtime of runtime/c/lines/*.{h,c} joined in, from the plan."""
from __future__ import annotations

from ...emit import environment, runtime_section
from ...lang.c import string
from ...wrap import LIMIT
from .model import Reply
from .plan import LinesPlan

FOLDER = "c"
# The runtime each interface joins, verbatim: the types into its header, the code into its .c
# (what every kind shares, the matcher, the conversation, the JSON writer), all static there.
RUNTIME_HEADER = ("lines/match.h", "lines/lines.h")
RUNTIME_SOURCES = ("common/macros.h", "common/buffer.h", "common/buffer.c", "common/utf8.h", "common/utf8.c",
                   "common/version_text.h", "common/version_text.c", "lines/match.c", "lines/lines.c", "lines/json.c")
# The kind's constants (runtime/c/lines/lines.h) the header names after the interface too.
ALIASES = ("PENDING", "PENDING_RAW", "NONE", "COMMAND", "REPLY", "FAULT", "LINE_TOO_LONG", "NO_NEWLINE_AT_END")


def _reply(symbol: str, reply: Reply) -> dict:
    return dict(symbol=symbol, name=string(reply.name), pieces=[string(p) for p in reply.pieces],
                count=len(reply.pieces), error="true" if reply.error else "false", pattern=reply.pattern)


def view(p: LinesPlan) -> dict:
    m = p.model
    prefix = m.name
    commands = []
    for c in p.commands:
        cmd = c.command
        replies = [_reply(f"{prefix}__{cmd.name}_{i}", r) for i, r in enumerate(cmd.replies)]
        commands.append(dict(
            constant=f"{prefix.upper()}_{cmd.name.upper()}", name=string(cmd.name), text=string(cmd.text),
            doc=f"{cmd.heading}{' <' + cmd.argument + '>' if cmd.argument else ''}: {cmd.doc} ({cmd.since_text()})",
            takes_argument="true" if cmd.argument else "false",
            since_cb=c.since_cb or 0, since_e_series=c.since_e_series or 0,
            replies=replies, replies_symbol=f"{prefix}__{cmd.name}_replies",
            row=[string(cmd.name), string(cmd.text), "true" if cmd.argument else "false", f"{c.since_cb or 0}u",
                 f"{c.since_e_series or 0}u", f"{c.since_polyscope_x or 0}u", f"{prefix}__{cmd.name}_replies",
                 str(len(replies))]))
    return dict(
        prefix=prefix, upper=prefix.upper(), title=m.title, doc=m.doc, ports=m.ports, max_line=m.max_line,
        commands=commands, lookup=[f"{prefix.upper()}_{c.command.name.upper()}" for c in p.lookup],
        banner_reply=_reply(f"{prefix}_banner", m.banner) if m.banner else None,
        requests_from_robot=int(m.requests_from_robot), one_reply_per_request=int(m.one_reply_per_request),
        common=[_reply(f"{prefix}__common_{i}", r) for i, r in enumerate(m.common_replies)],
        version_command=f"{prefix.upper()}_{p.version_command.command.name.upper()}" if p.version_command
        else f"{prefix.upper()}_NONE",
        version_prefix=string(m.version_prefix),
        runtime_header="\n\n".join(runtime_section(FOLDER, name) for name in RUNTIME_HEADER),
        runtime_sources=[runtime_section(FOLDER, name) for name in RUNTIME_SOURCES],
        aliases=ALIASES, e_series_from=f"{p.e_series_from}u", polyscope_x_from=f"{p.polyscope_x_from}u",
        limit=LIMIT,
    )


def render(p: LinesPlan, banner: list[str]) -> dict[str, str]:
    env = environment("c")
    ctx = dict(banner=banner, **view(p))
    name = p.model.name
    return {f"c/{name}.h": env.get_template("lines/lines.h.j2").render(**ctx),
            f"c/{name}.c": env.get_template("lines/lines.c.j2").render(**ctx)}
