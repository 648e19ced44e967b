"""Robot->client (and, where asked, client->robot) byte streams out of .pcap/.pcapng captures,
reassembled from TCP segments.

dpkt reads the capture formats (a record at a time, see capture_records) and parses the link, IP and TCP layers; reassembly is ours:
segments in sequence order, retransmitted and overlapping bytes dropped, out-of-order ones
held (ordered by their place in the stream) until the gap closes, or until the capture shows the
gap is final: the peer acknowledges bytes held beyond it (so it got the gap's, which the capture
did not), or the bytes held reach further than the peer's largest window lets a sender go
unacknowledged (the acknowledgements were lost too). As a last bound, when the streams together hold MAX_PENDING bytes,
the stream holding the most gives up its gap. The capture is read a record at a time.

Under the C backend (extension.py) the same rules run in C (runtime/c/capture, urwire._ccore.CaptureStreams),
which reads the file in chunks and gives timed_streams' items; the Python reader here is the fallback, and
URWIRE_BACKEND=python selects it.
"""
from __future__ import annotations

import heapq
import socket
import struct
from dataclasses import dataclass, field
from typing import BinaryIO, Iterator, Optional, Union

from .capture_records import CaptureFault, CaptureFrames
from .extension import CCORE
# dpkt is imported by the functions that read a capture: `import urwire` needs the standard library only.

PCAP_MAGICS = {b"\xa1\xb2\xc3\xd4", b"\xd4\xc3\xb2\xa1", b"\xa1\xb2\x3c\x4d", b"\x4d\x3c\xb2\xa1"}
PCAPNG_MAGIC = b"\x0a\x0d\x0d\x0a"
PCAPNG_BYTE_ORDER = (b"\x1a\x2b\x3c\x4d", b"\x4d\x3c\x2b\x1a")
MAX_PENDING = 16 << 20   # memory held for out-of-order segments, all streams together
SEGMENT_COST = 200       # what holding a segment costs beyond its bytes: its object and entries


UNKNOWN_SHIFT = 14        # a window's scale when the handshake is not in the capture: the largest
HEAD_BYTES = 12           # what is_capture looks at


def is_capture(head: bytes) -> bool:
    """Whether a file that starts with `head` (its first HEAD_BYTES bytes) is a capture: a whole
    pcap file header (one of its four magics, then major version 2 in the magic's byte order) or the
    start of a pcapng section header block (its type, a length, then the byte-order magic in either
    order). A raw stream is anything else, though its first four bytes be a magic: a dashboard
    session may well start with the pcapng one, "\\n\\r\\r\\n"."""
    if head[:4] in PCAP_MAGICS:
        return head[4:6] == (b"\x00\x02" if head[:1] == b"\xa1" else b"\x02\x00")
    return head[:4] == PCAPNG_MAGIC and head[8:12] in PCAPNG_BYTE_ORDER


def head_of(fh: BinaryIO) -> bytes:
    """The first bytes of an open file, left to be read, as is_capture takes them."""
    return fh.peek(HEAD_BYTES)[:HEAD_BYTES] if hasattr(fh, "peek") else b""


HISTORY_KEPT = 256 << 10  # bytes of a stream kept after delivery, to compare retransmissions with


@dataclass(frozen=True)
class Gap:
    """Bytes of one direction the capture does not hold: the reader went on without them."""

    offset: int     # in the direction's stream, where the missing bytes start
    length: int

    @property
    def error(self) -> str:
        return f"{self.length} bytes missing from the capture at offset {self.offset}"


@dataclass(frozen=True)
class Differs:
    """Bytes the capture holds twice, differently: the first copy was delivered (or held), the other
    dropped; `length` bytes from `offset` on are at stake, of which `differing` differ."""

    offset: int
    length: int
    differing: int = 0      # 0: the first copy is no longer kept, so the two were not compared

    @property
    def error(self) -> str:
        if not self.differing:
            return (f"{self.length} retransmitted bytes at offset {self.offset} could not be compared: the "
                    f"bytes they repeat are no longer kept")
        return (f"retransmitted bytes at offset {self.offset} differ from those delivered first "
                f"({self.differing} of {self.length}); the first kept")


@dataclass(frozen=True)
class Segments:
    """Bytes of one direction that came in several segments in a row, joined by the C reader on the
    ports a reader asks it to join (timed_streams' `joined`), so that a large capture takes a Python
    step per run of segments, not per segment: `stamps` packs, per segment, where it ends in `data`
    and the capture time of its frame (ext/ccore/ccore_segments.h), for PrimaryColumns.feed_segments;
    `pieces` unpacks them."""

    data: bytes
    stamps: bytes

    def pieces(self) -> list[tuple[bytes, float]]:
        """Each segment's bytes and capture time, as the reader would have given them one by one."""
        out, start = [], 0
        for end, time in _STAMP.iter_unpack(self.stamps):
            out.append((self.data[start:end], time))
            start = end
        return out


_STAMP = struct.Struct("=qd")     # ccore_segment_stamp: the end (int64_t), the time (double)
Piece = Union[bytes, Gap, Differs, Segments]


@dataclass
class _Reassembly:
    """One direction of a TCP conversation: segments in, its stream out as pieces, in order: bytes,
    a Gap where bytes are given up as missing, a Differs where a retransmission disagrees with the
    bytes it repeats (identical retransmissions are dropped without a word)."""

    next_seq: Optional[int] = None
    position: int = 0       # where next_seq is in the stream: the bytes delivered so far
    held: dict = field(default_factory=dict)    # stream position -> bytes, ahead of next_seq
    order: list = field(default_factory=list)   # the positions in `held`, as a heap
    held_bytes: int = 0     # the memory they take: their bytes and SEGMENT_COST each
    history: bytearray = field(default_factory=bytearray)  # the last bytes delivered, up to `position`
    window: int = 0         # the peer's largest window, in bytes (0: none seen yet)
    furthest: int = 0       # the stream position where the bytes held end

    def add(self, seq: int, data: bytes) -> list:
        if self.next_seq is None:
            self.next_seq = seq  # the capture starts mid-stream
        ahead = _delta(seq, self.next_seq)
        out: list = []
        if ahead > 0:
            self._hold(self.position + ahead, data, out)
            out += self._beyond_window()
            return out
        if -ahead >= len(data):
            self._compare(self.position + ahead, data, out)  # a retransmission of bytes delivered
            return out
        if ahead < 0:
            self._compare(self.position + ahead, data[:-ahead], out)
        piece = data[-ahead:] if ahead < 0 else data
        self._deliver(piece, out)
        if self.order:
            self._drain(out)
        return out

    def _hold(self, at: int, data: bytes, out: list) -> None:
        kept = self.held.get(at)
        if kept is None:
            heapq.heappush(self.order, at)
        else:
            _same(at, kept, data, out)
            if len(kept) >= len(data):
                return  # a retransmission of bytes already held
            data = kept + data[len(kept):]      # the first copy stands, the longer one adds to it
        self.held[at] = data
        self.furthest = max(self.furthest, at + len(data))
        self.held_bytes += len(data) - (len(kept) if kept is not None else -SEGMENT_COST)

    def _drain(self, out: list) -> None:
        """Deliver the held bytes the stream has reached, earliest first, each segment once."""
        while self.order and self.order[0] <= self.position:
            at = heapq.heappop(self.order)
            data = self.held.pop(at)
            self.held_bytes -= len(data) + SEGMENT_COST
            seen = self.position - at
            if seen:
                self._compare(at, data[:seen], out)
            if seen < len(data):
                self._deliver(data[seen:] if seen else data, out)

    def _deliver(self, piece: bytes, out: list) -> None:
        out.append(piece)
        self._advance(len(piece))
        history = self.history
        history += piece
        if len(history) > 2 * HISTORY_KEPT:
            del history[:-HISTORY_KEPT]

    def _compare(self, at: int, data: bytes, out: list) -> None:
        """Bytes of the stream from `at` on, delivered before: said when they differ."""
        kept_from = self.position - len(self.history)
        if at < kept_from:
            out.append(Differs(at, len(data)))
            return
        start = at - kept_from
        _same(at, bytes(self.history[start:start + len(data)]), data, out)

    def _advance(self, n: int) -> None:
        self.position += n
        self.next_seq = (self.next_seq + n) & 0xFFFFFFFF

    def ack(self, seq: int, window: int) -> list:
        """The peer acknowledged the stream up to `seq` and offered `window` bytes. Acknowledging
        bytes held behind a gap, it shows it got the gap's bytes, which the capture missed: the gap
        is given up at once, as Wireshark's "ACKed segment that wasn't captured". One that covers
        no held byte decides nothing: a capture may show an acknowledgement before the segment it
        acknowledges (its two directions reordered), and that segment may yet come."""
        self.window = max(self.window, window)
        out: list = []
        while self.order and _delta(seq, self.next_seq) > self.order[0] - self.position:
            out += self.skip_gap()
        return out + self._beyond_window()

    def _beyond_window(self) -> list:
        """Give up the gaps behind held bytes that reach further than the peer's largest window:
        no sender goes that far past what was acknowledged, so the acknowledgements are lost too."""
        out: list = []
        while self.order and 0 < self.window < self.furthest - self.position:
            out += self.skip_gap()
        return out

    def skip_gap(self) -> list:
        """Give up on missing bytes: a Gap, then the stream from the earliest segment held."""
        gap = Gap(self.position, self.order[0] - self.position)
        self._advance(gap.length)
        self.history.clear()    # what came before the gap is not what a retransmission repeats
        out: list = [gap]
        self._drain(out)
        return out

    def flush(self) -> list:
        """The end of the stream: every gap before held bytes given up, every held byte delivered."""
        out: list = []
        while self.order:
            out += self.skip_gap()
        return out


def _same(at: int, first: bytes, second: bytes, out: list) -> None:
    """Two copies of the stream's bytes from `at` on: a Differs when their common part differs."""
    n = min(len(first), len(second))
    if first[:n] != second[:n]:
        out.append(Differs(at, n, sum(a != b for a, b in zip(first[:n], second[:n]))))


def _delta(seq: int, ref: int) -> int:
    """seq - ref in 32-bit sequence space, as a signed number."""
    d = (seq - ref) & 0xFFFFFFFF
    return d - (1 << 32) if d >= 1 << 31 else d


def _ip_layer(linktype: int, frame: bytes):
    import dpkt

    if linktype == 1:
        pkt = dpkt.ethernet.Ethernet(frame).data
    elif linktype == 113:
        pkt = dpkt.sll.SLL(frame).data
    elif linktype == 276:
        pkt = dpkt.sll2.SLL2(frame).data
    elif linktype == 0:
        pkt = dpkt.loopback.Loopback(frame).data
    elif linktype in (12, 14, 101, 228, 229):
        pkt = dpkt.ip.IP(frame) if frame[:1] and frame[0] >> 4 == 4 else dpkt.ip6.IP6(frame)
    else:
        return None
    return pkt if isinstance(pkt, (dpkt.ip.IP, dpkt.ip6.IP6)) else None


StreamKey = tuple  # (robot address, robot port, client address, client port)


def robot_streams(fh: BinaryIO, ports: set[int]) -> Iterator[tuple[StreamKey, bytes, bool]]:
    """(stream, bytes in order, stream ended) for each robot->client TCP stream on `ports`; bytes
    either side of a gap come out as they are, joined (timed_streams says where gaps are)."""
    for item in timed_robot_streams(fh, ports):
        if not isinstance(item, CaptureFault):
            key, data, ended, _ = item
            yield key, data, ended


def timed_robot_streams(fh: BinaryIO, ports: set[int]) -> Iterator[Union[tuple[StreamKey, bytes, bool, float],
                                                                        CaptureFault]]:
    """The same, each with the capture time (seconds since the epoch) of the frame that brought
    its bytes: what completes a message dates it. A record of the file that cannot be read comes
    out as a CaptureFault where it was met; the streams then end as at the end of the file."""
    for item in timed_streams(fh, ports):
        if isinstance(item, CaptureFault):
            yield item
        elif isinstance(item[2], bytes):
            key, _, data, ended, ts = item
            yield key, data, ended, ts


C_CHUNK = 1 << 20         # the bytes of the file the C reader takes at a time


class OtherConversations:
    """The TCP conversations of a capture on none of the ports read, as timed_streams meets them:
    each as (server address, server port, client address, client port) with the bytes it carried.
    The client is the side that sent the first SYN, when the capture holds it; else the side on
    the higher port, as clients take theirs from the ephemeral range."""

    def __init__(self) -> None:
        self.bytes: dict[StreamKey, int] = {}
        self._keys: dict[tuple, StreamKey] = {}    # either end first -> the conversation's key

    def add(self, src: tuple, dst: tuple, flags: int, length: int) -> None:
        key = self._keys.get((src, dst))
        if key is None:
            import dpkt

            syn = flags & dpkt.tcp.TH_SYN
            src_is_client = not flags & dpkt.tcp.TH_ACK if syn else src[1] > dst[1]
            key = (*dst, *src) if src_is_client else (*src, *dst)
            self._keys[src, dst] = self._keys[dst, src] = key
            self.bytes[key] = 0
        self.bytes[key] += length

    def counted(self, rows: list) -> None:
        """The conversations as the C reader counted them: (server address, server port, client
        address, client port, bytes), first seen first."""
        self.bytes = {tuple(row[:4]): row[4] for row in rows}


def timed_streams(fh: BinaryIO, ports: set[int], both_ways: frozenset = frozenset(),
                  others: Optional[OtherConversations] = None, joined: frozenset = frozenset()) -> Iterator[
        Union[tuple[StreamKey, bool, Piece, bool, float], CaptureFault]]:
    """(conversation, from robot, piece, stream ended, capture time) for the TCP streams whose
    robot side is on `ports`: robot->client always, client->robot too for the ports in `both_ways`
    (the interfaces that read what clients send). The conversation is (robot address, robot port,
    client address, client port) in both directions; each direction is reassembled on its own. A
    piece is the bytes that came next (b"" when a stream ends with nothing more), or a Gap where
    the reader gave up bytes the capture does not hold and went on after them, or a Differs where
    a retransmission disagrees with the bytes it repeats. CaptureFaults as timed_robot_streams
    says. The TCP conversations on none of `ports` go to `others`, when given. On the ports in
    `joined`, the C reader may give a run of segments as one piece, a Segments (dated by its last
    segment's time); the Python reader gives every segment alone."""
    if CCORE is not None:
        return _timed_streams_in_c(fh, ports, both_ways, others, joined)
    return _timed_streams_in_python(fh, ports, both_ways, others)


def _timed_streams_in_c(fh: BinaryIO, ports: set[int], both_ways: frozenset,
                        others: Optional[OtherConversations], joined: frozenset) -> Iterator:
    streams = CCORE.CaptureStreams(ports, both_ways, others is not None, Gap, Differs, CaptureFault, joined,
                                   Segments)
    while True:
        chunk = fh.read(C_CHUNK)
        items = streams.feed(chunk) if chunk else streams.finish()
        if others is not None:
            others.counted(streams.others())
        yield from items
        if not chunk:
            return


def _timed_streams_in_python(fh: BinaryIO, ports: set[int], both_ways: frozenset,
                             others: Optional[OtherConversations]) -> Iterator:
    import dpkt

    head = fh.peek(4)[:4] if hasattr(fh, "peek") else b""
    reader = CaptureFrames(fh, pcapng=head == PCAPNG_MAGIC)
    streams: dict[tuple, _Reassembly] = {}   # by (conversation, from robot)
    shifts: dict[tuple, int] = {}   # the window scale each side's SYN asked for, the same way
    held = 0  # bytes held out of order by all the streams, as held_bytes counts them
    ts = 0.0
    for item in reader:
        if isinstance(item, CaptureFault):
            yield item
            continue
        ts, frame = item
        linktype = reader.linktype
        try:
            ip = _ip_layer(linktype, frame)
        except (dpkt.UnpackError, ValueError, IndexError):
            continue
        tcp = getattr(ip, "data", None)
        if not isinstance(tcp, dpkt.tcp.TCP):
            continue
        family = socket.AF_INET if isinstance(ip, dpkt.ip.IP) else socket.AF_INET6
        if tcp.sport in ports:
            from_robot = True
        elif tcp.dport in ports:
            from_robot = False      # read for its acknowledgements, and for its bytes where asked
        else:
            if others is not None:
                others.add((socket.inet_ntop(family, ip.src), tcp.sport), (socket.inet_ntop(family, ip.dst), tcp.dport),
                           tcp.flags, len(tcp.data))
            continue
        src, dst = socket.inet_ntop(family, ip.src), socket.inet_ntop(family, ip.dst)
        key = (src, tcp.sport, dst, tcp.dport) if from_robot else (dst, tcp.dport, src, tcp.sport)
        way = (key, from_robot)
        if tcp.flags & dpkt.tcp.TH_SYN:
            shifts[way] = _window_shift(tcp)
        elif tcp.flags & dpkt.tcp.TH_ACK:
            peer = streams.get((key, not from_robot))
            if peer is not None:    # its gaps this acknowledgement decides came before this segment
                held -= peer.held_bytes
                window = tcp.win << shifts.get(way, UNKNOWN_SHIFT)
                yield from _items(key, not from_robot, peer.ack(tcp.ack, window), False, float(ts))
                held += peer.held_bytes
        if not from_robot and tcp.dport not in both_ways:
            continue
        stream = streams.get(way)
        if stream is not None:
            held -= stream.held_bytes  # added back below, as the segment leaves it
        if tcp.flags & dpkt.tcp.TH_SYN:
            if stream is not None and stream.order:    # a new connection on the same ports
                yield from _items(key, from_robot, stream.flush(), True, float(ts))
            streams[way] = _Reassembly((tcp.seq + 1) & 0xFFFFFFFF)
            continue
        if stream is None:
            stream = streams[way] = _Reassembly()
        data = bytes(tcp.data)
        pieces = [] if not data or _keep_alive(stream, tcp.seq, data) else stream.add(tcp.seq, data)
        ended = bool(tcp.flags & (dpkt.tcp.TH_FIN | dpkt.tcp.TH_RST))
        if ended:
            pieces += stream.flush()
            del streams[way]
        else:
            held += stream.held_bytes
        yield from _items(key, from_robot, pieces, ended, float(ts))
        while held > MAX_PENDING:  # the stream holding the most gives up its gap
            largest = max(streams, key=lambda k: streams[k].held_bytes)
            held -= streams[largest].held_bytes
            yield from _items(largest[0], largest[1], streams[largest].skip_gap(), False, float(ts))
            held += streams[largest].held_bytes
    for (key, from_robot), stream in streams.items():
        yield from _items(key, from_robot, stream.flush(), True, float(ts))


def _window_shift(tcp) -> int:
    """The window scale a SYN segment asks for (RFC 7323: at most 14), 0 without the option."""
    import dpkt

    try:
        options = dpkt.tcp.parse_opts(tcp.opts)
    except (dpkt.UnpackError, ValueError, IndexError):
        return UNKNOWN_SHIFT
    for option in options:
        if option is None:
            return 0    # an option cut short ends them (dpkt marks it None)
        kind, value = option
        if kind == dpkt.tcp.TCP_OPT_WSCALE and len(value) == 1:
            return min(value[0], 14)
    return 0


def _keep_alive(stream: _Reassembly, seq: int, data: bytes) -> bool:
    """A TCP keep-alive probe: one byte (of any value) just before the next expected one."""
    return len(data) == 1 and stream.next_seq is not None and _delta(seq, stream.next_seq) == -1


def _items(key: StreamKey, from_robot: bool, pieces: list, ended: bool, ts: float) -> Iterator[tuple]:
    """timed_streams' items for one segment's pieces: the bytes between faults joined; the last item
    says whether the stream ended (an empty one when it ended with nothing more)."""
    run: list = []
    for piece in pieces:
        if isinstance(piece, bytes):
            run.append(piece)
            continue
        if run:
            yield key, from_robot, b"".join(run), False, ts
            run = []
        yield key, from_robot, piece, False, ts
    if run or ended:
        yield key, from_robot, b"".join(run), ended, ts
