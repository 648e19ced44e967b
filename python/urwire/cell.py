"""Every interface of a UR cell in one capture, or one interface's raw stream(s): records with
the interface, direction and conversation they came from.

A capture's TCP conversations are told apart by their server-side port (interfaces.py); each gets
its interface's `Conversation`, fed the bytes of each direction as they are reassembled. Each
record comes in an `Enveloped` (cell_records), whose JSON opens with "interface", "direction" and
"conversation" (docs/canonical-json.md#records-of-a-capture), the primary interface's too; only
decode_file takes the primary interface's records bare (timed_cell_records).
"""
from __future__ import annotations

from typing import BinaryIO, Callable, Iterable, Iterator, Optional

from ._runtime import StreamError
from .arguments import VersionLike
from .capture import Differs, Gap, OtherConversations, timed_streams
from .capture_records import CaptureFault
from .envelope import FROM_ROBOT, TO_ROBOT, Endpoints, Enveloped
from .interfaces import INTERFACES, Interface
from .text_lines import PENDING_KEPT_RAW

PRIMARY = "ur"


def ports_of(interfaces: Iterable[Interface]) -> dict[int, Interface]:
    return {port: i for i in interfaces for port in i.ports}


def primary_ports(by_port: dict[int, Interface]) -> frozenset:
    """The ports of `by_port` of the primary interface: those whose segments a reader of large
    captures has joined (cell_records' `joined`)."""
    return frozenset(port for port, i in by_port.items() if i.name == PRIMARY)


def timed_cell_records(fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                       advance: Callable[[int], None] = lambda n: None) -> Iterator[tuple]:
    """(capture time, record) of every conversation of the capture on the ports of `by_port`, as
    decode_file gives them: the primary interface's records (and a fault of the capture file, which
    has no time) as they are, every other interface's Enveloped."""
    for item in cell_records(fh, hint, by_port, advance):
        yield item.capture_time, item.record if item.interface in (PRIMARY, None) else item


def cell_records(fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                 advance: Callable[[int], None] = lambda n: None,
                 others: Optional[OtherConversations] = None,
                 joined: frozenset = frozenset()) -> Iterator[Enveloped]:
    """Every record of the capture's conversations on the ports of `by_port`, each Enveloped with
    its interface, direction, conversation and capture time, the primary interface's too; a
    fault of the capture file with none of them. The conversations on other ports go to
    `others`, when given; those on the ports in `joined` may be fed capture.Segments."""
    ends = _EndpointsOf()
    for time, key, interface, from_robot, record in conversation_records(fh, hint, by_port, advance, others,
                                                                         joined):
        if key is None:
            yield Enveloped(None, None, None, record)
        else:
            yield Enveloped(interface.name, FROM_ROBOT if from_robot else TO_ROBOT, ends(key, interface), record, time)


class _EndpointsOf(dict):
    """Each conversation's Endpoints, made once: its records share it."""

    def __call__(self, key: tuple, interface: Interface) -> Endpoints:
        ends = self.get(key)
        if ends is None:
            ends = self[key] = Endpoints(*key, robot_is_client=interface.robot_is_client)
        return ends


def conversation_records(fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                         advance: Callable[[int], None] = lambda n: None,
                         others: Optional[OtherConversations] = None,
                         joined: frozenset = frozenset()) -> Iterator[tuple]:
    """(capture time, conversation, interface, from robot, record) of every conversation of the
    capture on the ports of `by_port`, the conversation being (server address, server port,
    client address, client port); a fault of the capture file comes as (None, None, None, None,
    error record). A conversation closes when its listening side ends (or the capture does). The
    software version a robot's primary stream announces is passed on to its other conversations
    (the real-time one chooses among layouts of one size with it)."""
    conversations: dict = {}     # key -> (conversation, its learn_version or None, its at or None)
    versions: dict = {}      # robot address -> the software version one of its conversations learnt
    both_ways = {port for port, i in by_port.items() if i.both_directions}
    last = 0
    seekable = fh.seekable()
    for item in timed_streams(fh, set(by_port), both_ways, others, joined):
        if isinstance(item, CaptureFault):  # its offset is the capture file's, not a stream's
            yield None, None, None, None, StreamError(item.offset, item.error)
            continue
        key, from_port, piece, ended, time = item
        interface = by_port[key[1]]
        # The side that listens on the port is the robot, except on the ROS driver's sockets,
        # where the robot connects to the control PC.
        from_robot = from_port != interface.robot_is_client
        entry = conversations.get(key)
        if entry is None:
            if not piece:                       # the end of a conversation already closed
                continue
            conv = interface.conversation(hint)
            # Its optional methods, looked up once: a capture has many items per conversation.
            entry = conversations[key] = conv, getattr(conv, "learn_version", None), getattr(conv, "at", None)
        conv, learn, at = entry
        if learn is not None and key[0] in versions:
            learn(versions[key[0]])
        if at is not None:      # a conversation that files its records itself (data/dataset_c_capture.py)
            at(time, key)
        if isinstance(piece, Gap):
            # Named first (a conversation that files its records itself numbers what follows after
            # it), then what the direction held before it given up, and its decoding started afresh.
            yield time, key, interface, from_robot, StreamError(piece.offset, piece.error)
            records = conv.lost(from_robot, piece.offset + piece.length)
        elif isinstance(piece, Differs):
            records = [StreamError(piece.offset, piece.error)]
        else:
            records = conv.feed(piece, from_robot) if piece else []
        learnt = getattr(conv, "software_version", None)
        if learnt is not None:
            versions[key[0]] = learnt
        tails: tuple = ()
        if ended and from_port:
            # Each direction's tail is its own: to_robot's first, then the robot's.
            tails = ((False, conv.close(False)), (True, conv.close(True)))
            del conversations[key]
        for record in records:
            yield time, key, interface, from_robot, record
        for side_from_robot, tail in tails:
            for record in tail:
                yield time, key, interface, side_from_robot, record
        if seekable:
            pos = fh.tell()
            if pos != last:
                advance(pos - last)
                last = pos


def records_of_raw_protocol(fh: BinaryIO, interface: Interface, hint: VersionLike, chunk: int,
                            advance: Callable[[int], None], to_robot: Optional[BinaryIO] = None,
                            names: tuple = ("", "")) -> Iterator:
    """One interface's raw stream from the robot, and optionally the client's stream to it, read
    first (what a client asks, an RTDE recipe, comes before what the robot sends for it). Alone,
    a stream's records are as the interface writes them; with `to_robot`, each is Enveloped with
    its direction, its conversation being the file it came from."""
    conv = interface.conversation(hint)
    keep_pending = getattr(conv, "keep_pending", None)
    if keep_pending is not None:        # the client's whole file comes before any reply
        keep_pending(PENDING_KEPT_RAW)

    def read(stream: BinaryIO, from_robot: bool, name: str) -> Iterator:
        while True:
            data = stream.read(chunk)
            if not data:
                break
            advance(len(data))
            for record in conv.feed(data, from_robot):
                yield record if to_robot is None else Enveloped(interface.name, FROM_ROBOT if from_robot
                                                                 else TO_ROBOT, name, record)

    if to_robot is not None:
        yield from read(to_robot, False, names[1])
    yield from read(fh, True, names[0])
    # Each stream's tail is its own, the client's first.
    for record in conv.close(False):
        yield record if to_robot is None else Enveloped(interface.name, TO_ROBOT, names[1], record)
    for record in conv.close(True):
        yield record if to_robot is None else Enveloped(interface.name, FROM_ROBOT, names[0], record)


def interface_named(name: str) -> Interface:
    if name not in INTERFACES:
        raise ValueError(f"unknown protocol {name!r} (known: {', '.join(sorted(INTERFACES))})")
    return INTERFACES[name]
