"""Robot->client (and, where asked, client->robot) byte streams out of .pcap/.pcapng captures,
reassembled from TCP segments.

dpkt reads the capture formats (a record at a time, see capture_records) and parses the link, IP and TCP layers; reassembly is ours:
segments in sequence order, retransmitted and overlapping bytes dropped, out-of-order ones
held (ordered by their place in the stream) until the gap closes, or until the streams together
hold MAX_PENDING bytes: then the stream holding the most gives up its gap. The capture is read
a record at a time.
"""
from __future__ import annotations

import heapq
from dataclasses import dataclass, field
from typing import BinaryIO, Iterator, Optional, Union

from .capture_records import CaptureFault, CaptureFrames

PCAP_MAGICS = {b"\xa1\xb2\xc3\xd4", b"\xd4\xc3\xb2\xa1", b"\xa1\xb2\x3c\x4d", b"\x4d\x3c\xb2\xa1"}
PCAPNG_MAGIC = b"\x0a\x0d\x0d\x0a"
MAX_PENDING = 16 << 20   # memory held for out-of-order segments, all streams together
SEGMENT_COST = 200       # what holding a segment costs beyond its bytes: its object and entries


def is_capture(head: bytes) -> bool:
    return head[:4] in PCAP_MAGICS or head[:4] == PCAPNG_MAGIC


@dataclass
class _Reassembly:
    next_seq: Optional[int] = None
    position: int = 0       # where next_seq is in the stream: the bytes delivered so far
    held: dict = field(default_factory=dict)    # stream position -> bytes, ahead of next_seq
    order: list = field(default_factory=list)   # the positions in `held`, as a heap
    held_bytes: int = 0     # the memory they take: their bytes and SEGMENT_COST each

    def add(self, seq: int, data: bytes) -> bytes:
        if self.next_seq is None:
            self.next_seq = seq  # the capture starts mid-stream
        ahead = _delta(seq, self.next_seq)
        if ahead > 0:
            return self._hold(self.position + ahead, data)
        if -ahead >= len(data):
            return b""  # a retransmission of bytes already delivered
        piece = data[-ahead:] if ahead < 0 else data
        self._advance(len(piece))
        if not self.order:
            return piece
        pieces = [piece]
        self._drain(pieces)
        return b"".join(pieces)

    def _hold(self, at: int, data: bytes) -> bytes:
        kept = self.held.get(at)
        if kept is None:
            heapq.heappush(self.order, at)
        elif len(kept) >= len(data):
            return b""  # a retransmission of bytes already held
        self.held[at] = data
        self.held_bytes += len(data) - (len(kept) if kept is not None else -SEGMENT_COST)
        return b""

    def _drain(self, pieces: list) -> None:
        """Append the held bytes the stream has reached, earliest first, each segment once."""
        while self.order and self.order[0] <= self.position:
            at = heapq.heappop(self.order)
            data = self.held.pop(at)
            self.held_bytes -= len(data) + SEGMENT_COST
            seen = self.position - at
            if seen < len(data):
                pieces.append(data[seen:] if seen else data)
                self._advance(len(data) - seen)

    def _advance(self, n: int) -> None:
        self.position += n
        self.next_seq = (self.next_seq + n) & 0xFFFFFFFF

    def skip_gap(self) -> bytes:
        """Give up on missing bytes: go on from the earliest segment held."""
        self._advance(self.order[0] - self.position)
        pieces: list = []
        self._drain(pieces)
        return b"".join(pieces)

    def flush(self) -> bytes:
        return self.skip_gap() if self.order else b""


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
    """(stream, bytes in order, stream ended) for each robot->client TCP stream on `ports`."""
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
        else:
            key, _, data, ended, ts = item
            yield key, data, ended, ts


def timed_streams(fh: BinaryIO, ports: set[int], both_ways: frozenset = frozenset()) -> Iterator[
        Union[tuple[StreamKey, bool, bytes, bool, float], CaptureFault]]:
    """(conversation, from robot, bytes in order, stream ended, capture time) for the TCP streams
    whose robot side is on `ports`: robot->client always, client->robot too for the ports in
    `both_ways` (the interfaces that read what clients send). The conversation is (robot address,
    robot port, client address, client port) in both directions; each direction is reassembled on
    its own. CaptureFaults as timed_robot_streams says."""
    import dpkt
    import socket

    head = fh.peek(4)[:4] if hasattr(fh, "peek") else b""
    reader = CaptureFrames(fh, pcapng=head == PCAPNG_MAGIC)
    streams: dict[tuple, _Reassembly] = {}   # by (conversation, from robot)
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
        if tcp.sport in ports:
            from_robot = True
        elif tcp.dport in both_ways:
            from_robot = False
        else:
            continue
        family = socket.AF_INET if isinstance(ip, dpkt.ip.IP) else socket.AF_INET6
        src, dst = socket.inet_ntop(family, ip.src), socket.inet_ntop(family, ip.dst)
        key = (src, tcp.sport, dst, tcp.dport) if from_robot else (dst, tcp.dport, src, tcp.sport)
        way = (key, from_robot)
        stream = streams.get(way)
        if stream is not None:
            held -= stream.held_bytes  # added back below, as the segment leaves it
        if tcp.flags & dpkt.tcp.TH_SYN:
            stream = streams[way] = _Reassembly((tcp.seq + 1) & 0xFFFFFFFF)
            continue
        if stream is None:
            stream = streams[way] = _Reassembly()
        data = stream.add(tcp.seq, bytes(tcp.data)) if tcp.data else b""
        ended = bool(tcp.flags & (dpkt.tcp.TH_FIN | dpkt.tcp.TH_RST))
        if ended:
            data += stream.flush()
            del streams[way]
        else:
            held += stream.held_bytes
        if data or ended:
            yield key, from_robot, data, ended, float(ts)
        while held > MAX_PENDING:  # the stream holding the most gives up its gap
            largest = max(streams, key=lambda k: streams[k].held_bytes)
            held -= streams[largest].held_bytes
            yield largest[0], largest[1], streams[largest].skip_gap(), False, float(ts)
            held += streams[largest].held_bytes
    for (key, from_robot), stream in streams.items():
        yield key, from_robot, stream.flush(), True, float(ts)
