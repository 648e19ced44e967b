"""`urwire listen --mcap FILE` and `--foxglove`: what a viewer sees of the records listen writes.

Each record is enveloped with its interface and the current connection's conversation (set by
listen on each connection), stamped with the time it was decoded, and made into its messages once
(mcap_recording.RecordMessages); the MCAP file writes them and the live view (foxglove_server)
sends them, so both hold the same channels, schemas, messages and log times (docs/mcap.md).
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
    """The MCAP file (when `mcap_path`) and the live view (when `live`, a started FoxgloveServer).
    An OSError from add() or close() is the MCAP file's: the live view never raises one."""

    def __init__(self, interface: str, mcap_path: Optional[str] = None, live=None) -> None:
        self.interface, self.mcap_path, self.live = interface, mcap_path, live
        self.conversation: Optional[Endpoints] = None
        self._messages = RecordMessages()
        self._fh = open(mcap_path, "wb") if mcap_path else None
        self._mcap = McapRecording(self._fh, self._messages) if self._fh else None

    def add(self, position: int, record) -> None:
        item = Enveloped(self.interface, FROM_ROBOT, self.conversation, record, time.time())
        for message in self._messages.of(position, item):
            if self.live:
                self.live.publish(message)
            if self._mcap:
                self._mcap.write(message)

    def close(self) -> None:
        """Ends the live view, then writes the MCAP file's summary."""
        try:
            if self.live:
                self.live.close()
        finally:
            if self._fh:
                try:
                    self._mcap.finish()
                finally:
                    self._fh.close()
