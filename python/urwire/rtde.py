"""RTDE (port 30004): one connection's state and the client's side of it.

`Conversation` decodes both directions of one connection, fed per direction as bytes arrive. It
keeps what RTDE's messages depend on: the negotiated protocol version (1 or 2) and the recipes,
each made from a setup request's variable names and its reply's types (urwire.generated.rtde's
RECIPE_KINDS say which messages those are). Data packages come out with their values by variable
name; one of a recipe the connection never set up is kept raw with an error; a setup reply that
refuses names (NOT_FOUND, IN_USE) is noted and makes no recipe, and one whose recipe cannot be made
otherwise (its request unknown, names and types differing in number) removes its id's old one. Data packages may arrive between
a request and its reply: replies are matched to requests of their own kind, in order. A bounded
number of requests await their replies (`Awaiting`): one beyond is not kept, and both it and its
reply say so, rather than a reply taking another request's names. After bytes lost from a capture,
a reply whose request the gap leaves unknown pairs with none and says so (text_lines.Pending).

The functions at the end build what a client sends: `setup_outputs(["actual_q"], 125.0)`.
"""
from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Optional

from .generated import rtde as _g
from .text_lines import NOT_KEPT, UNKNOWN, Pending, reply_unknown
from .typed_records import DecodeError, Framer, Message, RawMessage, Recipe, Values

__all__ = ["Conversation", "Recipe", "Values", "VARIABLES", "VariableTable", "variable", "request_protocol_version",
           "setup_outputs", "setup_inputs", "start", "pause", "input_data", "send_text_message"]

NAME, TITLE, PORTS = _g.NAME, _g.TITLE, _g.PORTS


class VariableTable(Mapping[str, _g._r.Variable]):
    """The variable table by name: `VARIABLES["actual_q"]` is its row (type, direction, label,
    unit, first versions). A name the client writes and the robot also sends back (the input
    registers) has two rows: here the one the robot sends (what a data package from the robot
    carries), `variable(name, "input")` the other. `rows` is every row, in the spec's order."""

    def __init__(self, rows: tuple):
        self.rows: tuple = rows
        self._by_name: dict = {}
        for v in rows:      # each name where it first comes, by the row the robot sends if it has one
            if v.direction == "output" or v.name not in self._by_name:
                self._by_name[v.name] = v

    def __getitem__(self, name: str) -> _g._r.Variable:
        return self._by_name[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._by_name)

    def __len__(self) -> int:
        return len(self._by_name)

    def __repr__(self) -> str:
        return f"<RTDE variable table: {len(self._by_name)} names, {len(self.rows)} rows>"


VARIABLES = VariableTable(_g.VARIABLES)
_KNOWN_CODES = frozenset({code for code, _, _ in _g.MESSAGES} | set(_g.UNDOCUMENTED))
_KIND_OF_REQUEST = {cls: kind for kind in _g.RECIPE_KINDS for cls in kind.requests}
_KIND_OF_REPLY = {cls: kind for kind in _g.RECIPE_KINDS for cls in kind.replies}
_DATA = 85  # 'U'
# Each data package layout: the kind of recipe it follows, and whether it carries a recipe id.
_RECIPE_OF_DATA = {cls: ((_g.OUTPUTS if cls.FROM_ROBOT else _g.INPUTS).name, cls.JSON[0][0] == "recipe_id")
                   for (code, _, _), cls in _g.MESSAGES.items() if code == _DATA}
_CUT_ID = -1    # a package cut before its recipe id: the key of no recipe


def variable(name: str, direction: str = "output") -> Optional[_g._r.Variable]:
    """The row of the variable table with this name and direction, if any."""
    return _VARIABLE_INDEX.get((name, direction))


_VARIABLE_INDEX = {(v.name, v.direction): v for v in VARIABLES.rows}


class Awaiting(Pending):
    """Requests of one kind awaiting their replies, oldest first, at most `size` kept: the
    dashboard's queue (text_lines.Pending), with what its errors name."""

    def __init__(self, size: int, what: str, request: str):
        super().__init__(size)
        self.what = what                # "setups", "protocol version requests": for the errors' texts
        self.request = request          # "setup", "protocol version request"

    def unpaired(self, why: str) -> str:
        """The error of a reply that pairs with none, for Pending.pop's reason."""
        if why == UNKNOWN:
            return reply_unknown(self.request)
        return f"reply to a {self.request} that was not kept: {self.overflow}"

    @property
    def overflow(self) -> str:
        return f"more than {self.limit} {self.what} awaited replies"


class Conversation:
    """One RTDE connection. `protocol` is the version in force: given, or negotiated, or until then
    DEFAULT_PROTOCOL_VERSION for a capture that starts after the version exchange."""

    def __init__(self, version_hint=None, protocol: Optional[int] = None):
        self.protocol: Optional[int] = protocol        # None until given or negotiated
        self._framers = {True: Framer(_KNOWN_CODES), False: Framer(_KNOWN_CODES)}
        self._asked_version = Awaiting(_g.MAX_PENDING_VERSION_REQUESTS, "protocol version requests",
                                       "protocol version request")
        self._pending = {kind.name: Awaiting(_g.MAX_PENDING_SETUPS, "setups", "setup") for kind in _g.RECIPE_KINDS}
        self.recipes: dict[str, dict[Optional[int], Recipe]] = {kind.name: {} for kind in _g.RECIPE_KINDS}
        self.count = 0                                 # records given out so far, both directions

    @property
    def protocol_in_force(self) -> int:
        return self.protocol if self.protocol is not None else _g.DEFAULT_PROTOCOL_VERSION

    def feed(self, data, from_robot: bool) -> list:
        out = []
        for item in self._framers[bool(from_robot)].feed(data):
            record = item if not isinstance(item, tuple) else self._message(item[1], item[2], bool(from_robot))
            out.append(record)
            self.count += 1
        return out

    def close(self, from_robot: Optional[bool] = None) -> list:
        """A message cut short at the end of one direction's stream (both, to_robot's first, when
        from_robot is None)."""
        out = self._framers[False].close() if from_robot is not True else []
        out += self._framers[True].close() if from_robot is not False else []
        self.count += len(out)
        return out

    def lost(self, from_robot: bool, offset: int) -> list:
        """Bytes of one direction are missing before `offset`: a message they cut short is given
        up, and that direction is framed afresh from there; protocol and recipes are kept (by
        their ids), but the requests the bytes may have held, or answered, leave each queue's
        pairing unknown (text_lines.Pending)."""
        for awaiting in (self._asked_version, *self._pending.values()):
            awaiting.replies_lost() if from_robot else awaiting.requests_lost()
        out = self._framers[bool(from_robot)].restart(offset)
        self.count += len(out)
        return out

    # ---- one message ----

    def _message(self, code: int, raw: bytes, from_robot: bool):
        protocol = self.protocol_in_force
        cls = _g.MESSAGES.get((code, from_robot, protocol))
        if cls is None:
            name = _g.UNDOCUMENTED.get(code, ("unknown",))[0]
            return RawMessage(name, code, raw)
        recipe = None
        if code == _DATA:
            kind, has_id = _RECIPE_OF_DATA[cls]
            recipe_id = (raw[3] if len(raw) > 3 else _CUT_ID) if has_id else None
            recipe = self.recipes[kind].get(recipe_id)
            if recipe is None:
                return RawMessage(cls.NAME, code, raw, "data package of a recipe this connection did not set up",
                                  None if recipe_id == _CUT_ID else recipe_id)
        try:
            record = cls.decode_body(raw, _g.HEADER.size, len(raw), recipe)
        except DecodeError as exc:
            return RawMessage(cls.NAME, code, raw, exc.text)
        if recipe is not None:
            record.note("recipe", recipe)
        self._follow(record)
        return record

    def _follow(self, record: Message) -> None:
        """What a message changes in the connection's state."""
        cls = type(record)
        if cls is _g.RequestProtocolVersion:
            if self._asked_version.push(record.protocol_version) == NOT_KEPT:
                record.note("error", f"protocol version request not kept: {self._asked_version.overflow}")
        elif cls is _g.RequestProtocolVersionReply:
            self._version_reply(record)
        elif cls in _KIND_OF_REQUEST:
            pending = self._pending[_KIND_OF_REQUEST[cls].name]
            if pending.push(record.variables) == NOT_KEPT:
                record.note("error", f"setup not kept: {pending.overflow}")
        elif cls in _KIND_OF_REPLY:
            self._make_recipe(_KIND_OF_REPLY[cls], record)
        elif cls is _g.StartReply and not record.accepted:
            record.note("warning", "the robot refused to start")

    def _version_reply(self, reply: Message) -> None:
        """Only a protocol that has layouts is taken: a robot accepting any other (0, 3, 300) leaves
        the one in force, and the reply says so."""
        asked, why = self._asked_version.pop()
        if why is not None:
            reply.note("error", self._asked_version.unpaired(why))
        if reply.accepted and asked is not None:
            if asked in _g.PROTOCOL_VERSIONS:
                self.protocol = asked
            else:
                reply.note("error", f"protocol version {asked} accepted, which has no layouts: "
                                    f"protocol {self.protocol_in_force} stays in force")
        elif not reply.accepted and self.protocol is None:
            self.protocol = 1                           # the robot keeps protocol 1 until one is accepted

    def _make_recipe(self, kind, reply: Message) -> None:
        """A reply's types against its request's names. A reply the robot set up something with
        but whose recipe cannot be made (its request unknown, or names and types differing in
        number) removes the recipe its id had: data packages of that id are kept raw from here on,
        rather than read by the recipe this reply replaced. A refusal (NOT_FOUND, IN_USE) sets up
        nothing (recipe id 0, in the RTDE guide), so the recipe in force stays."""
        pending = self._pending[kind.name]
        request, why = pending.pop()
        names = [n for n in request if n] if request is not None else []   # an empty name names nothing
        if why is not None:
            reply.note("error", pending.unpaired(why))
        elif request is None:
            reply.note("warning", "a setup reply without a request seen: its recipe's names are unknown")
        elif len(names) != len(reply.types):
            reply.note("warning", "names asked and types answered differ in number")
        else:
            self._recipe_from(kind, reply, names)
            return
        self.recipes[kind.name].pop(getattr(reply, "recipe_id", None), None)

    def _recipe_from(self, kind, reply: Message, names: list) -> None:
        refused = [(n, t) for n, t in zip(names, reply.types) if t in _g.REFUSALS or t not in _g.VALUE_TYPES]
        if refused:
            reply.note("refused", refused)
            return
        recipe_id = getattr(reply, "recipe_id", None)
        self.recipes[kind.name][recipe_id] = Recipe(recipe_id, kind.name, names, reply.types, _g.VALUE_TYPES,
                                                    self.count)


# ---- what a client sends -----------------------------------------------------------------------

def request_protocol_version(version: int = 2) -> bytes:
    return _g.RequestProtocolVersion(version).encode()


def get_controller_version() -> bytes:
    return _g.GetUrcontrolVersion().encode()


def setup_outputs(names: list[str], frequency: Optional[float] = 125.0, protocol: int = 2) -> bytes:
    """Ask for output variables (protocol 2: at `frequency` Hz; protocol 1 has no frequency)."""
    if protocol == 1:
        return _g.SetupOutputsV1(list(names)).encode()
    return _g.SetupOutputs(float(frequency), list(names)).encode()


def setup_inputs(names: list[str]) -> bytes:
    return _g.SetupInputs(list(names)).encode()


def start() -> bytes:
    return _g.Start().encode()


def pause() -> bytes:
    return _g.Pause().encode()


def send_text_message(message: str, source: str = "urwire", level: int = 3) -> bytes:
    return _g.SendTextMessage(message, source, level).encode()


def input_data(recipe: Recipe, values) -> bytes:
    """An input data package for an input recipe the robot accepted; `values` by variable name (a
    dict), or a Values of the recipe's names, one value each in order (for a name given twice)."""
    return _g.InputDataPackage(recipe.id, Values.of(values)).encode(recipe)
