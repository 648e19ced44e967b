"""`urwire listen --rtde NAMES`: the RTDE client side of one connection, for listen to record.

On connecting it asks for protocol 2; a robot that refuses it (software before 3.5 speaks only 1)
gets protocol 1. Then it sets up the output recipe (at --frequency under protocol 2; protocol 1 has
no frequency) and starts it once the robot accepts. Every message the robot sends comes out as a
record (the replies, text messages and the data packages with their values by name). A recipe or
a start the robot refuses ends the recording (`Refused`): asking again would get the same answer.
A request that cannot be sent (the robot reset the connection) never costs a record: every message
received is decoded first, and the failure is kept in `send_failed` for listen to act on after
writing them.
"""
from __future__ import annotations

from typing import Callable, Optional

from .. import rtde
from ..generated import rtde as _g

PORT = 30004


class RtdeRecorder:
    """One connection: `opening()` is what to send first; `feed(chunk)` the records of what the
    robot sent, sending the next request through `send` as each reply arrives."""

    def __init__(self, names: list[str], frequency: float, send: Callable[[bytes], None]):
        self.refused: Optional[str] = None       # why the robot refused, once it has
        self.names = names
        self.frequency = frequency
        self.send = send
        self.conversation = rtde.Conversation(protocol=1)     # a robot starts in protocol 1
        self.asked_protocol = 2
        self.send_failed: Optional[OSError] = None
        self.streaming = False                   # a data package came: the session worked

    def _send(self, data: bytes) -> None:
        self.conversation.feed(data, False)
        self.send(data)

    def opening(self) -> None:
        self._send(rtde.request_protocol_version(self.asked_protocol))

    def feed(self, chunk: bytes) -> list:
        records = self.conversation.feed(chunk, True)
        try:
            for record in records:
                self._follow(record)
        except OSError as exc:                   # the records stand; listen ends the connection
            self.send_failed = exc
        return records

    def close(self) -> list:
        return self.conversation.close()

    def _follow(self, record) -> None:
        kind = type(record)
        if self.send_failed is not None:
            return                               # nothing more can be asked on this connection
        if kind in (_g.DataPackage, _g.DataPackageV1):
            self.streaming = True
        elif kind is _g.RequestProtocolVersionReply:
            protocol = self.asked_protocol if record.accepted else 1
            self._send(rtde.setup_outputs(self.names, self.frequency, protocol=protocol))
        elif kind in (_g.SetupOutputsReply, _g.SetupOutputsReplyV1):
            refused = [f"{name} {type_name}" for name, type_name in zip(self.names, record.types)
                       if type_name in _g.REFUSALS]
            if refused or getattr(record, "recipe_id", 1) == 0:
                self.refused = f"the robot refused the recipe: {', '.join(refused) or 'recipe id 0'}"
                return
            self._send(rtde.start())
        elif kind is _g.StartReply and not record.accepted:
            self.refused = "the robot refused to start sending"
