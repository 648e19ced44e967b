"""The Lua target of a text-line interface: generated/lua/<name>.lua, a Wireshark dissector that
loads on its own: the spec's tables, then runtime/lua/<name>_*.lua joined in, from the plan."""
from __future__ import annotations

import json

from ...emit import environment, runtime_section
from ...naming import column_name
from .model import Reply
from .plan import LinesPlan

RUNTIME = ("match.lua", "dissect.lua")


def _string(text: str) -> str:
    """A Lua string literal (the schema keeps spec texts printable ASCII; JSON escapes suit Lua)."""
    return json.dumps(text)


def _reply(reply: Reply) -> str:
    pieces = ", ".join(_string(p) for p in reply.pieces)
    return f"{{name = {_string(reply.name)}, pieces = {{{pieces}}}, error = {'true' if reply.error else 'false'}}}"


def _number(n) -> str:
    return "nil" if n is None else str(n)


def view(p: LinesPlan) -> dict:
    m = p.model
    return dict(
        name=_string(m.name), title=_string(m.title), short=_string(column_name(m.name)), doc=f"{m.title}: {m.doc}", max_line=m.max_line,
        ports=", ".join(str(port) for port in m.ports), filters=f"{m.name}.command_name == \"load\", "
        f"{m.name}.reply, {m.name}.error == 1",
        banner_reply=_reply(m.banner) if m.banner else "nil",
        requests_from_robot="true" if m.requests_from_robot else "false",
        one_reply_per_request="true" if m.one_reply_per_request else "false",
        robot_is_client="true" if m.robot_is_client else "false", common=[_reply(r) for r in m.common_replies],
        commands=[dict(comment=f"{c.command.text}: {c.command.doc} ({c.command.since_text()})",
                       entries=[f"name = {_string(c.command.name)}", f"text = {_string(c.command.text)}",
                             f"argument = {'true' if c.command.argument else 'false'}",
                             f"since_cb = {_number(c.since_cb)}", f"since_e_series = {_number(c.since_e_series)}"],
                       replies=[_reply(r) for r in c.command.replies])
                  for c in p.commands],
        lookup=[str(c.index + 1) for c in p.lookup],
        version_command=_number(p.version_command.index + 1 if p.version_command else None),
        version_prefix=_string(m.version_prefix), e_series_from=p.e_series_from,
        labels=[dict(name=name, label=_string(f.label), doc=_string(f.doc)) for name, f in m.fields.items()],
        runtime=[runtime_section("lua", f"lines_{name}") for name in RUNTIME],
    )


def render(p: LinesPlan, banner: list[str]) -> dict[str, str]:
    text = environment("lua").get_template("lines/lines.lua.j2").render(banner=banner, **view(p))
    return {f"lua/{p.model.name}.lua": text}
