"""`urwire export`'s rows for the interfaces other than the primary one (docs/tables.md).

Each record of those comes Enveloped with its interface, direction and conversation, and goes to a
table named by its interface:

- RTDE data packages go to one table per recipe signature, `rtde_outputs_<hash>` or
  `rtde_inputs_<hash>`: the hash is of the recipe's variable names and types, so the same recipe
  lands in the same table across connections, reconnects and captures, while a recipe id is only
  its connection's own (every connection numbers from 0, and protocol 1 has none). A row holds the
  conversation and recipe id, then one column per variable (a vector's items as `actual_q_0` ...,
  as the primary tables lay out joints). `rtde_recipes` lists each table's recipe, once per
  conversation, with its variables and types. Every other RTDE message goes to `rtde_messages`.
- The dashboard server's commands and replies are paired, in order as the server answers them,
  into `ur_dashboard`: one row per command and its reply (the banner is a reply without a
  command; a command the capture holds no reply for keeps its reply columns empty).
- The real-time packets go to `ur_realtime`, one table for every layout (`type` names it; a field
  a layout lacks is null), and each ROS driver socket to a table of its name (`ur_reverse`, ...),
  with `type` naming the record.

Every value is the one `urwire decode` shows: rows are made from the record's canonical JSON,
lists of numbers one column per item, other lists and objects kept as their JSON text. Error
records go to `errors`, with their conversation and their JSON as decode prints it (the envelope
included): every record that makes `urwire decode` exit 1
(canonical.fails), among them a message kept raw with its reason (an RTDE data package of a recipe
the capture did not show being set up) and a reply a full queue could not pair.
"""
from __future__ import annotations

import hashlib
import json
from collections import deque
from typing import Callable, Optional

from ..canonical import fails, to_dict, to_json_line
from ..envelope import Enveloped
from ..generated.ur_dashboard import BANNER as _BANNER
from .records import conversation_text

ENVELOPE = ("interface", "direction", "conversation")
DASHBOARD = "ur_dashboard"
RTDE = "rtde"
# An RTDE value type's kind, as the table column it becomes.
_RTDE_KINDS = {"float": "f64", "bool": "bool", "int": "int"}
_UINT64_FROM = 1 << 63
BANNER = _BANNER.name


def recipe_table(recipe) -> str:
    """The table of a recipe's data packages: its kind and a short hash of its names and types."""
    signature = ",".join(recipe.names) + "|" + ",".join(recipe.types)
    return f"{RTDE}_{recipe.kind}_{hashlib.sha1(signature.encode('utf-8')).hexdigest()[:8]}"


def value_columns(name: str, value) -> list[tuple[str, str, object]]:
    """(column, kind, value) of one canonical JSON member: a number, bool or text as itself, a list
    of numbers or bools one column per item (`name_0` ...), anything else as its JSON text."""
    if value is None:
        return []
    if isinstance(value, list) and value and all(isinstance(v, (bool, int, float)) for v in value):
        return [(f"{name}_{j}", _kind(v), v) for j, v in enumerate(value)]
    if isinstance(value, (list, dict)):
        return [(name, "text", json.dumps(value, ensure_ascii=False))] if value else []
    return [(name, _kind(value), value)]


def _kind(value) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "uint64" if value >= _UINT64_FROM else "int"
    return "f64" if isinstance(value, float) else "text"


def record_columns(fields: dict) -> list[tuple[str, str, object]]:
    out = []
    for name, value in fields.items():
        if name not in ENVELOPE:
            out += value_columns(name, value)
    return out


class CellRows:
    """Turns Enveloped records into rows of `add(table, position, columns, time)`; `finish()` writes
    what is still waiting (commands no reply answered)."""

    def __init__(self, add: Callable) -> None:
        self._add = add
        self._recipes_seen: set = set()
        self._pending: dict[str, deque] = {}     # dashboard conversation -> commands awaiting a reply
        self._greeted: set = set()               # dashboard conversations past their first reply

    def add(self, position: int, item: Enveloped, time=None) -> None:
        record, conversation = item.record, conversation_text(item)
        if fails(record):
            self._add("errors", position, [("conversation", "text", conversation),
                                           ("record", "text", to_json_line(item))], time)
            return
        recipe = getattr(record, "notes", {}).get("recipe") if item.interface == RTDE else None
        if recipe is not None:
            self._rtde_data(position, conversation, record, recipe, time)
            return
        fields = to_dict(item)
        if item.interface == DASHBOARD:
            self._dashboard(position, conversation, fields, time)
        else:
            table = f"{RTDE}_messages" if item.interface == RTDE else item.interface
            columns = [("conversation", "text", conversation), ("direction", "text", item.direction)]
            self._add(table, position, columns + record_columns(fields), time)

    # ---- RTDE ----

    def _rtde_data(self, position: int, conversation: str, record, recipe, time) -> None:
        table = recipe_table(recipe)
        key = (conversation, recipe.kind, recipe.id, recipe.defined_at)
        if key not in self._recipes_seen:
            self._recipes_seen.add(key)
            self._add(f"{RTDE}_recipes", position, [
                ("conversation", "text", conversation), ("kind", "text", recipe.kind),
                ("recipe_id", "int", recipe.id), ("table", "text", table),
                ("variables", "text", ",".join(recipe.names)), ("types", "text", ",".join(recipe.types))], time)
        values = record.values
        columns = [("conversation", "text", conversation), ("recipe_id", "int", recipe.id)]
        seen: dict[str, int] = {}
        for (name, shape), value in zip(recipe.json_kinds(), values.in_order()):
            kind = "uint64" if shape.name == "UINT64" else _RTDE_KINDS[shape.kind]
            seen[name] = seen.get(name, 0) + 1
            if seen[name] > 1:              # a name the recipe repeats: a column for each of its values
                name = f"{name}#{seen[name]}"
            if shape.count == 1:
                columns.append((name, kind, _plain(kind, value)))
            else:
                columns += [(f"{name}_{j}", kind, _plain(kind, v)) for j, v in enumerate(value)]
        self._add(table, position, columns, time)

    # ---- the dashboard server ----

    def _dashboard(self, position: int, conversation: str, fields: dict, time) -> None:
        """Pairs as the decoder does (text_lines.LinesConversation): each command waits in turn;
        each reply answers the oldest, except a banner as the first reply."""
        pending, greeted = self._pending.setdefault(conversation, deque()), conversation in self._greeted
        if fields["type"] == "command":     # one the decoder did not keep is an error record
            pending.append((position, time, fields))
            return
        self._greeted.add(conversation)
        banner = not greeted and fields.get("reply_name") == BANNER and fields.get("command_name") is None
        command = pending.popleft() if pending and not banner else None
        self._dashboard_row(conversation, command, (position, time, fields))

    def _dashboard_row(self, conversation: str, command: Optional[tuple], reply: Optional[tuple]) -> None:
        position, time = (command or reply)[:2]
        said = command[2] if command else {}
        answer = reply[2] if reply else {}
        self._add(DASHBOARD, position, [
            ("conversation", "text", conversation),
            ("command", "text", said.get("command")), ("command_name", "text", said.get("command_name")),
            ("argument", "text", said.get("argument")), ("available", "bool", said.get("available")),
            ("reply_position", "int", reply[0] if reply else None),
            ("reply_time", "f64", reply[1] if reply else None),
            ("reply", "text", answer.get("reply")), ("reply_name", "text", answer.get("reply_name")),
            ("error", "bool", answer.get("error"))], time if command else reply[1])

    def finish(self) -> None:
        for conversation, pending in self._pending.items():
            while pending:
                self._dashboard_row(conversation, pending.popleft(), None)


def _plain(kind: str, value):
    """An RTDE value as the table takes it: a BOOL's byte as true or false, as decode shows it."""
    return bool(value) if kind == "bool" else value
