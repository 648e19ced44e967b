"""Every interface of a UR cell in one capture, or one interface's raw stream(s): records with
the interface, direction and conversation they came from.

A capture's TCP conversations are told apart by their robot-side port (interfaces.py); each gets
its interface's `Conversation`, fed the bytes of each direction as they are reassembled. Records
of the primary interface keep the form they have always had, so that what `urwire decode` printed
for a capture of the primary interface does not change; every other interface's record comes in an
`Enveloped`, whose JSON opens with "interface", "direction" and "conversation"
(docs/canonical-json.md#records-of-the-other-interfaces).
"""
from __future__ import annotations

from typing import BinaryIO, Callable, Iterable, Iterator, Optional

from ._runtime import StreamError
from .arguments import VersionLike
from .capture import Differs, Gap, timed_streams
from .capture_records import CaptureFault
from .envelope import FROM_ROBOT, TO_ROBOT, Enveloped
from .interfaces import INTERFACES, Interface
from .text_lines import PENDING_KEPT_RAW

PRIMARY = "ur"


def ports_of(interfaces: Iterable[Interface]) -> dict[int, Interface]:
    return {port: i for i in interfaces for port in i.ports}


def _conversation_name(key: tuple) -> str:
    robot, robot_port, client, client_port = key
    def at(address: str, port: int) -> str:
        return f"[{address}]:{port}" if ":" in address else f"{address}:{port}"
    return f"{at(robot, robot_port)}-{at(client, client_port)}"


def timed_cell_records(fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                       advance: Callable[[int], None] = lambda n: None) -> Iterator[tuple]:
    """(capture time, record) of every conversation of the capture on the ports of `by_port`.
    A conversation closes when its listening side ends (or the capture does). The software version a
    robot's primary stream announces is passed on to its other conversations (the real-time one
    chooses among layouts of one size with it)."""
    for time, _, record in timed_robot_records(fh, hint, by_port, advance):
        yield time, record


def timed_robot_records(fh: BinaryIO, hint: VersionLike, by_port: dict[int, Interface],
                        advance: Callable[[int], None] = lambda n: None) -> Iterator[tuple]:
    """(capture time, robot address, record), as timed_cell_records gives them, with the address of
    the robot each record's conversation belongs to (None for a fault of the capture file)."""
    conversations: dict = {}
    versions: dict = {}      # robot address -> the software version one of its conversations learnt
    both_ways = {port for port, i in by_port.items() if i.both_directions}
    last = 0
    for item in timed_streams(fh, set(by_port), both_ways):
        if isinstance(item, CaptureFault):  # its offset is the capture file's, not a stream's
            yield None, None, StreamError(item.offset, item.error)
            continue
        key, from_port, piece, ended, time = item
        interface = by_port[key[1]]
        # The side that listens on the port is the robot, except on the ROS driver's sockets,
        # where the robot connects to the control PC.
        from_robot = from_port != interface.robot_is_client
        conv = conversations.get(key)
        if conv is None:
            if not piece:                       # the end of a conversation already closed
                continue
            conv = conversations[key] = interface.conversation(hint)
        learn = getattr(conv, "learn_version", None)
        if learn is not None and key[0] in versions:
            learn(versions[key[0]])
        at = getattr(conv, "at", None)
        if at is not None:      # a conversation that files its records itself (data/dataset_c_capture.py)
            at(time, key[0])
        tails: list = []
        if isinstance(piece, Gap):
            # Named first (a conversation that files its records itself numbers what follows after
            # it), then what the direction held before it given up, and its decoding started afresh.
            yield from _filed(interface, key, [(from_robot, [StreamError(piece.offset, piece.error)])], time)
            records = conv.lost(from_robot, piece.offset + piece.length)
        elif isinstance(piece, Differs):
            records = [StreamError(piece.offset, piece.error)]
        else:
            records = conv.feed(piece, from_robot) if piece else []
        learnt = getattr(conv, "software_version", None)
        if learnt is not None:
            versions[key[0]] = learnt
        if ended and from_port:
            # Each direction's tail is its own: to_robot's first, then the robot's.
            tails = [(False, conv.close(False)), (True, conv.close(True))]
            del conversations[key]
        yield from _filed(interface, key, [(from_robot, records)] + tails, time)
        if fh.seekable():
            pos = fh.tell()
            advance(pos - last)
            last = pos


def _filed(interface: Interface, key: tuple, sides: list, time) -> Iterator[tuple]:
    """(capture time, robot address, record) of each (from robot, records) side: the primary
    interface's records as they are, any other's in the envelope of its direction."""
    if interface.name == PRIMARY:
        for _, side in sides:
            for record in side:
                yield time, key[0], record
        return
    name = _conversation_name(key)
    for from_robot, side in sides:
        for record in side:
            yield time, key[0], Enveloped(interface.name, FROM_ROBOT if from_robot else TO_ROBOT, name, record)


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
