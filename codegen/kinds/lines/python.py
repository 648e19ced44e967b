"""The Python target of a text-line interface: generated/python/urwire/generated/<name>.py, the
tables urwire.text_lines reads and the record classes, from the plan."""
from __future__ import annotations

from typing import Optional

from ... import ir
from ...emit import environment
from .model import Command, Reply
from .plan import LinesPlan


def _version(version: Optional[ir.Version]) -> str:
    return repr(version) if version else "None"


def _reply_arguments(reply: Reply) -> list[str]:
    """ReplySpec's arguments: what the simulated robot answers with it only where the spec says."""
    served = [f"fill={reply.fill_parts!r}"] if reply.fill_parts else []
    served += [f"when={reply.when!r}"] if reply.when else []
    return [repr(reply.name), repr(reply.pieces), repr(reply.error)] + served


def _reply(reply: Reply) -> str:
    return f"_rt.ReplySpec({', '.join(_reply_arguments(reply))})"


def _command_end(command: Command) -> str:
    """What closes a command's table entry: its effect on the simulated robot, if it has one."""
    return f"), effect={command.effect!r})" if command.effect else "))"


def view(p: LinesPlan) -> dict:
    m = p.model
    return dict(
        name=m.name, title=m.title, doc=m.doc, ports=repr(m.ports), max_line=m.max_line,
        banner_reply=_reply(m.banner) if m.banner else "None", requests_from_robot=repr(m.requests_from_robot),
        one_reply_per_request=repr(m.one_reply_per_request), common_replies=[_reply(r) for r in m.common_replies],
        commands=[dict(constant=c.command.name.upper(), doc=f"{c.command.doc} ({c.command.since_text()})",
                       arguments=[repr(c.command.name), repr(c.command.text), repr(c.command.argument is not None),
                                  _version(c.command.since_cb), _version(c.command.since_e_series),
                                  _version(c.command.since_polyscope_x), "SERIES_FROM"],
                       replies=[_reply_arguments(r) for r in c.command.replies], end=_command_end(c.command))
                  for c in p.commands],
        lookup=[c.command.name.upper() for c in p.lookup],
        series_from=repr((ir.version_of_number(p.e_series_from), ir.version_of_number(p.polyscope_x_from))),
        version_command=repr(m.version_command), version_prefix=repr(m.version_prefix),
        fields={name: dict(label=f.label, doc=f.doc) for name, f in m.fields.items()},
    )


def render(p: LinesPlan, banner: list[str]) -> dict[str, str]:
    text = environment("python").get_template("lines/module.py.j2").render(banner=banner, **view(p))
    return {f"python/urwire/generated/{p.model.name}.py": text}
