"""LoadedSpec (framing.kind: lines) -> LinesProtocol, with every problem at its YAML path."""
from __future__ import annotations

import re
from typing import Optional

from ... import ir, series
from ...errors import SpecError
from ...load import LoadedSpec
from ...resolve import Resolver
from .model import Command, LinesProtocol, RecordField, Reply

_PLACEHOLDER = re.compile(r"<[a-z][a-z0-9_. ]*>")


def pattern_pieces(pattern: str) -> tuple[str, ...]:
    """"Loading program: <program>" -> ("Loading program: ", ""): the literal text around each
    placeholder, which a line must hold in order, the first at its start and the last at its end."""
    return tuple(_PLACEHOLDER.split(pattern))


class _LinesResolver(Resolver):
    def reply(self, raw: dict, parts) -> Reply:
        pattern = raw["pattern"]
        pieces = pattern_pieces(pattern)
        if any("<" in piece or ">" in piece for piece in pieces):
            self.fail(parts + ["pattern"], f"'<' and '>' only enclose a placeholder name: {pattern!r}")
        return Reply(raw["name"], pattern, pieces, raw.get("error", False), raw.get("doc", ""), self.where(parts))

    def replies(self, raws: list, parts) -> tuple[Reply, ...]:
        out = []
        for i, raw in enumerate(raws):
            reply = self.reply(raw, parts + [i])
            if any(r.name == reply.name for r in out):
                self.fail(parts + [i, "name"], f"duplicate reply name {reply.name}")
            out.append(reply)
        return tuple(out)

    def command(self, raw: dict, parts, follows: Optional[ir.Version]) -> Command:
        since = raw.get("since", {"cb": "1.0", "e_series": "5.0"})   # no since: from the first software
        cb = ir.parse_version(since["cb"]) if "cb" in since else None
        e_series = ir.parse_version(since["e_series"]) if "e_series" in since else None
        if cb and cb[0] >= LinesProtocol.E_SERIES_MAJOR:
            self.fail(parts + ["since", "cb"], f"{since['cb']} is not a CB-series version (below 5.0)")
        if e_series and e_series[0] < LinesProtocol.E_SERIES_MAJOR:
            self.fail(parts + ["since", "e_series"], f"{since['e_series']} is not an e-Series version (5.0 or later)")
        polyscope_x = series.POLYSCOPE_X_FROM
        if "since" in raw:   # PolyScope X reads the e-Series column only as far as it is known to follow it
            polyscope_x, problem = series.polyscope_x_first(e_series or series.NONE, since.get("polyscope_x"), follows)
            if problem:
                self.fail(parts + ["since"] + (["polyscope_x"] if "polyscope_x" in since else []), problem)
        return Command(raw["name"], raw["text"], raw.get("argument"), cb, e_series,
                       None if polyscope_x == series.NONE else polyscope_x, "since" not in raw, raw["doc"],
                       self.replies(raw["replies"], parts + ["replies"]), self.where(parts))

    def protocol(self) -> LinesProtocol:
        data = self.spec.data
        follows = data["protocol"].get("polyscope_x_follows")
        follows = ir.parse_version(follows) if follows else None
        commands: list[Command] = []
        for i, raw in enumerate(data["commands"]):
            command = self.command(raw, ["commands", i], follows)
            for earlier in commands:
                if earlier.name == command.name:
                    self.fail(["commands", i, "name"], f"duplicate command name {command.name}")
                if earlier.text == command.text:
                    self.fail(["commands", i, "text"], f"the text {command.text!r} is {earlier.name}'s too")
            commands.append(command)
        framing = data["framing"]
        version_reply = framing.get("version_reply")
        if version_reply and version_reply["command"] not in {c.name for c in commands}:
            self.fail(["framing", "version_reply", "command"], f"unknown command {version_reply['command']!r}")
        fields = {name: RecordField(name, raw["label"], raw["doc"]) for name, raw in data["fields"].items()}
        proto = data["protocol"]
        return LinesProtocol(
            name=proto["name"], title=proto["title"], doc=proto["doc"], ports=tuple(proto["ports"]),
            max_line=framing["max_line"],
            banner=self.reply(framing["banner"], ["framing", "banner"]) if "banner" in framing else None,
            robot_is_client=framing.get("robot_is_client", False),
            requests_from_robot=framing.get("requests_from", "client") == "robot",
            one_reply_per_request=framing.get("replies", "one_per_request") == "one_per_request",
            version_command=version_reply["command"] if version_reply else None,
            version_prefix=version_reply["prefix"] if version_reply else "",
            fields=fields, common_replies=self.replies(data["common_replies"], ["common_replies"]),
            commands=tuple(commands))


def resolve(spec: LoadedSpec) -> LinesProtocol:
    resolver = _LinesResolver(spec)
    model = resolver.protocol()
    if resolver.problems:
        raise SpecError(spec.source, resolver.problems)
    return model
