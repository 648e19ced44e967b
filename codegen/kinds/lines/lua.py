"""The Lua target of a text-line interface: generated/lua/<name>.lua, a Wireshark dissector that
loads on its own: the spec's tables from the plan and the dissector model (dissector.py, which
the epan target renders too), then runtime/lua/common and runtime/lua/lines joined in."""
from __future__ import annotations

from ... import exchanges
from ...emit import environment, runtime_section
from ...lang.lua import literal, string
from .dissector import PENDING_KEPT, Dissector, dissector
from .model import Reply
from .plan import LinesPlan

# The runtime joined after the tables, in order (runtime/lua/common, then this kind's own).
RUNTIME = ("common/register.lua", "common/guard.lua", "common/dotted_version.lua", "common/tcp_stream.lua",
           "common/pending.lua", "common/exchange.lua", "lines/match.lua", "lines/dissect.lua")


def _reply(reply: Reply) -> str:
    pieces = ", ".join(string(p) for p in reply.pieces)
    return f"{{name = {string(reply.name)}, pieces = {{{pieces}}}, error = {literal(reply.error)}}}"


def view(d: Dissector) -> dict:
    p = d.plan
    m = p.model
    return dict(
        name=string(m.name), title=string(m.title), short=string(d.column), doc=f"{m.title}: {m.doc}", max_line=m.max_line,
        ports=", ".join(str(port) for port in m.ports), filters=f"{m.name}.command_name == \"load\", "
        f"{m.name}.reply, {m.name}.error == 1",
        banner_reply=_reply(m.banner) if m.banner else "nil",
        requests_from_robot=literal(m.requests_from_robot), one_reply_per_request=literal(m.one_reply_per_request),
        robot_is_client=literal(m.robot_is_client), common=[_reply(r) for r in m.common_replies],
        commands=[dict(comment=f"{c.command.heading}: {c.command.doc} ({c.command.since_text()})",
                       entries=[f"name = {string(c.command.name)}", f"text = {string(c.command.text)}",
                             f"argument = {literal(c.command.argument is not None)}",
                             f"since_cb = {literal(c.since_cb)}", f"since_e_series = {literal(c.since_e_series)}",
                             f"since_polyscope_x = {literal(c.since_polyscope_x)}"],
                       replies=[_reply(r) for r in c.command.replies])
                  for c in p.commands],
        lookup=[str(c.index + 1) for c in p.lookup],
        version_command=literal(p.version_command.index + 1 if p.version_command else None),
        version_prefix=string(m.version_prefix), e_series_from=p.e_series_from, polyscope_x_from=p.polyscope_x_from,
        labels=[dict(name=f.name, label=string(f.label), doc=string(f.doc)) for f in d.fields],
        pending_kept=PENDING_KEPT, not_kept=string(d.expert("not_kept").text),
        reply_not_kept=string(d.expert("reply_not_kept").text),
        exchange_fields=[exchanges.lua_field(f, m.name, f.name, "        ") for f in d.exchange_fields],
        runtime=[runtime_section("lua", name) for name in RUNTIME],
    )


def render(p: LinesPlan, banner: list[str]) -> dict[str, str]:
    text = environment("lua").get_template("lines/lines.lua.j2").render(banner=banner, **view(dissector(p)))
    return {f"lua/{p.model.name}.lua": text}
