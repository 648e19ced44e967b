"""A file's records as the data tools read them: every record of a .pcap or .pcapng Enveloped with
its interface, direction and conversation, the primary interface's too (cell.cell_records), and a
raw primary stream's records as they are, since a raw stream has no conversation."""
from __future__ import annotations

import functools
from typing import BinaryIO, Iterator, Optional

from ..arguments import VersionLike
from ..capture import head_of, is_capture
from ..cell import cell_records, ports_of
from ..envelope import Enveloped
from ..interfaces import INTERFACES, Interface
from ..reading import records_of_raw


def records_of_file(fh: BinaryIO, version_hint: VersionLike = None,
                    by_port: Optional[dict[int, Interface]] = None) -> Iterator:
    """The records of an open file, in order: a capture's conversations on the ports of `by_port`
    (default: every interface's by its ports), or a raw primary stream."""
    if is_capture(head_of(fh)):
        return cell_records(fh, version_hint, by_port or ports_of(INTERFACES.values()))
    return records_of_raw(fh, version_hint, lambda n: None)


def conversation_text(item: Enveloped) -> Optional[str]:
    """A record's conversation as the tables' `conversation` column holds it: plain text (the spill
    files' marshal takes no str subclass, such as Endpoints), None for a fault of the capture file."""
    return None if item.conversation is None else _plain(item.conversation)


@functools.lru_cache(maxsize=1 << 10)
def _plain(conversation: str) -> str:
    # One text for all the rows of a conversation, which marshal then writes once per chunk.
    return str(conversation)


def robot_address(item: Enveloped) -> Optional[str]:
    """The address of the robot a capture's record came from; None for a fault of the capture file."""
    return None if item.conversation is None else item.conversation.robot_address
