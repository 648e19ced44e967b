"""LoadedSpec (framing.kind: lines) -> LinesProtocol, with every problem at its YAML path."""
from __future__ import annotations

import re
from typing import Optional

from ... import ir, series
from ...errors import SpecError
from ...load import LoadedSpec
from ...resolve import Resolver
from .model import EFFECTS, ROBOT_STATES, Command, LinesProtocol, RecordField, Reply

_PLACEHOLDER = re.compile(r"<[a-z][a-z0-9_. ]*>")
_STATE_REF = re.compile(r"\{([^{}]*)\}")


def pattern_pieces(pattern: str) -> tuple[str, ...]:
    """"Loading program: <program>" -> ("Loading program: ", ""): the literal text around each
    placeholder, which a line must hold in order, the first at its start and the last at its end."""
    return tuple(_PLACEHOLDER.split(pattern))


def fill_parts(fill: Optional[str]) -> tuple[str, ...]:
    """"{software_version} ({build_date})" -> ("", "software_version", " (", "build_date", ")"): literal
    text and robot state names, alternately, the literal first (and last)."""
    return tuple(_STATE_REF.split(fill)) if fill is not None else ()


def _argument_fill(pattern: str, argument: Optional[str]) -> Optional[str]:
    """A reply whose one placeholder is named as the command's argument ("File not found: <program>"
    of `load <program>`) is filled with the argument unless its fill says otherwise."""
    return "{argument}" if argument is not None and _PLACEHOLDER.findall(pattern) == [f"<{argument}>"] else None


class _LinesResolver(Resolver):
    def reply(self, raw: dict, parts, argument: Optional[str] = None, served: bool = False) -> Reply:
        """`served`: a command's reply, which may say what the simulated robot answers with it."""
        pattern = raw["pattern"]
        pieces = pattern_pieces(pattern)
        if any("<" in piece or ">" in piece for piece in pieces):
            self.fail(parts + ["pattern"], f"'<' and '>' only enclose a placeholder name: {pattern!r}")
        for key in ("fill", "when"):
            if key in raw and not served:
                self.fail(parts + [key], f"only a command's reply says what the simulated robot answers ({key})")
        if "fill" in raw:
            self.check_fill(raw["fill"], len(pieces) - 1, argument, parts + ["fill"])
        when = tuple(raw.get("when", {}).items())
        for state, _ in when:
            self.check_state(state, argument, parts + ["when", state])
        fill = raw.get("fill", _argument_fill(pattern, argument) if served else None)
        return Reply(raw["name"], pattern, pieces, raw.get("error", False), raw.get("doc", ""), self.where(parts),
                     fill, fill_parts(fill), when)

    def check_fill(self, fill: str, placeholders: int, argument: Optional[str], parts) -> None:
        if placeholders != 1:
            self.fail(parts, f"fill gives the text of one placeholder; the pattern has {placeholders}")
        rest = _STATE_REF.sub("", fill)
        if "{" in rest or "}" in rest:
            self.fail(parts, f"'{{' and '}}' only enclose a robot state's name: {fill!r}")
        for state in fill_parts(fill)[1::2]:
            self.check_state(state, argument, parts)

    def check_state(self, state: str, argument: Optional[str], parts) -> None:
        if state not in ROBOT_STATES:
            self.fail(parts, f"unknown robot state {state!r}: one of {', '.join(ROBOT_STATES)}")
        elif state == "argument" and argument is None:
            self.fail(parts, "the command takes no argument")

    def replies(self, raws: list, parts, argument: Optional[str] = None, served: bool = False) -> tuple[Reply, ...]:
        out = []
        for i, raw in enumerate(raws):
            reply = self.reply(raw, parts + [i], argument, served)
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
        effect = raw.get("effect")
        if effect is not None and effect not in EFFECTS:
            self.fail(parts + ["effect"], f"unknown effect {effect!r}: one of {', '.join(EFFECTS)}")
        polyscope_x = series.POLYSCOPE_X_FROM
        if "since" in raw:   # PolyScope X reads the e-Series column only as far as it is known to follow it
            polyscope_x, problem = series.polyscope_x_first(e_series or series.NONE, since.get("polyscope_x"), follows)
            if problem:
                self.fail(parts + ["since"] + (["polyscope_x"] if "polyscope_x" in since else []), problem)
        argument = raw.get("argument")
        if "text" not in raw and argument is None:
            self.fail(parts, "a command with no text (any other line) takes the whole line as its argument")
        return Command(raw["name"], raw.get("text", ""), argument, cb, e_series,
                       None if polyscope_x == series.NONE else polyscope_x, "since" not in raw, raw["doc"],
                       self.replies(raw["replies"], parts + ["replies"], argument, served=True), self.where(parts),
                       effect)

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
                    what = f"the text {command.text!r} is" if command.text else "any other line is"
                    self.fail(["commands", i, "text"], f"{what} {earlier.name}'s too")
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
