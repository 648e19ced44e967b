"""`urwire listen --mcap FILE`: what a viewer sees of the records listen writes.

Each record is enveloped with its interface and the current connection's conversation (set by
listen on each connection), stamped with the time it was decoded, and made into its messages once
(mcap_recording.RecordMessages), which the MCAP file writes (docs/mcap.md).
"""
from __future__ import annotations

import time
from typing import Optional

from ..envelope import FROM_ROBOT, Endpoints, Enveloped
from ..mcap_recording import McapRecording, RecordMessages


def endpoints_of(sock) -> Endpoints:
    """The conversation of a connection this side opened: the peer listens."""
    peer, own = sock.getpeername(), sock.getsockname()
    return Endpoints(peer[0], peer[1], own[0], own[1])


class Views:
    """The MCAP file (when `mcap_path`). An OSError from add() or close() is the MCAP file's."""

    def __init__(self, interface: str, mcap_path: Optional[str] = None) -> None:
        self.interface, self.mcap_path = interface, mcap_path
        self.conversation: Optional[Endpoints] = None
        self._messages = RecordMessages()
        self._fh = open(mcap_path, "wb") if mcap_path else None
        self._mcap = McapRecording(self._fh, self._messages) if self._fh else None

    def add(self, position: int, record) -> None:
        item = Enveloped(self.interface, FROM_ROBOT, self.conversation, record, time.time())
        for message in self._messages.of(position, item):
            if self._mcap:
                self._mcap.write(message)

    def close(self) -> None:
        """Writes the MCAP file's summary."""
        if self._fh:
            try:
                self._mcap.finish()
            finally:
                self._fh.close()
