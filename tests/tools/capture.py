"""Write TCP sessions of the UR interface into .pcap/.pcapng files, for tests and samples.

A session is a handshake, then data segments in either direction with real sequence and
acknowledgement numbers and correct checksums (dpkt computes them), then a FIN exchange.
"""
from __future__ import annotations

import random
import socket
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Optional, Sequence

import dpkt

ROBOT = "192.168.56.101"
CLIENT = "192.168.56.1"
ROBOT_MAC = b"\x00\x30\x64\x11\x22\x33"
CLIENT_MAC = b"\x02\x00\x00\x00\x00\x01"


@dataclass
class Segment:
    from_robot: bool
    payload: bytes


def _frame(src, dst, sport, dport, seq, ack, flags, payload, src_mac, dst_mac, opts: bytes = b"") -> bytes:
    tcp = dpkt.tcp.TCP(sport=sport, dport=dport, seq=seq, ack=ack, flags=flags, win=65535, data=payload,
                       opts=opts, off=5 + len(opts) // 4)
    ip = dpkt.ip.IP(src=socket.inet_aton(src), dst=socket.inet_aton(dst), p=dpkt.ip.IP_PROTO_TCP, ttl=64,
                    data=tcp)
    ip.len = len(ip)
    eth = dpkt.ethernet.Ethernet(src=src_mac, dst=dst_mac, type=dpkt.ethernet.ETH_TYPE_IP, data=ip)
    return bytes(eth)


def session_frames(segments: Iterable[Segment], port: int = 30001, client_port: int = 50123,
                   handshake: bool = True, robot_isn: int = 1000, client_isn: int = 5000,
                   retransmit: Sequence[int] = (), robot: str = ROBOT, client: str = CLIENT,
                   window_shift: Optional[int] = None) -> list[bytes]:
    """Ethernet frames of one TCP session between `robot` and `client` (IPv4 addresses);
    indices in `retransmit` are sent twice. Each side offers a 65,535-byte window, scaled by
    2**window_shift when given (the window scale option in both SYNs)."""
    ROBOT, CLIENT = robot, client  # noqa: N806 (the module's defaults, or the addresses given)
    A, PA, S, SA, F = (dpkt.tcp.TH_ACK, dpkt.tcp.TH_PUSH | dpkt.tcp.TH_ACK, dpkt.tcp.TH_SYN,
                       dpkt.tcp.TH_SYN | dpkt.tcp.TH_ACK, dpkt.tcp.TH_FIN | dpkt.tcp.TH_ACK)
    r_seq, c_seq = robot_isn, client_isn

    def robot(flags, data=b""):
        return _frame(ROBOT, CLIENT, port, client_port, r_seq, c_seq, flags, data, ROBOT_MAC, CLIENT_MAC)

    def client(flags, data=b""):
        return _frame(CLIENT, ROBOT, client_port, port, c_seq, r_seq, flags, data, CLIENT_MAC, ROBOT_MAC)

    frames = []
    # Window scale (kind 3, length 3), then a no-operation to end the options on a 32-bit word.
    opts = b"" if window_shift is None else bytes([3, 3, window_shift, 1])
    if handshake:
        frames.append(_frame(CLIENT, ROBOT, client_port, port, c_seq - 1, 0, S, b"", CLIENT_MAC, ROBOT_MAC, opts))
        frames.append(_frame(ROBOT, CLIENT, port, client_port, r_seq - 1, c_seq, SA, b"", ROBOT_MAC, CLIENT_MAC,
                             opts))
        frames.append(client(A))
    for i, seg in enumerate(segments):
        if seg.from_robot:
            frames.append(robot(PA, seg.payload))
            if i in retransmit:
                frames.append(robot(PA, seg.payload))
            r_seq = (r_seq + len(seg.payload)) & 0xFFFFFFFF
            frames.append(client(A))
        else:
            frames.append(client(PA, seg.payload))
            c_seq = (c_seq + len(seg.payload)) & 0xFFFFFFFF
            frames.append(robot(A))
    frames.append(robot(F))
    r_seq += 1
    frames.append(client(F))
    c_seq += 1
    frames.append(robot(A))
    return frames


FIN = None      # in exchange_frames' steps: the side closes its half of the connection


def exchange_frames(steps: Sequence[tuple], port: int, client_port: int = 50123, lose: Optional[int] = None,
                    robot: str = ROBOT, client: str = CLIENT) -> list[bytes]:
    """Ethernet frames of one TCP session of (from robot, payload or FIN) steps in this order, each
    acknowledged by the other side, either side free to close first; the frame of step `lose`, if
    any, is not in the capture (its acknowledgement is), as a capture that missed a segment."""
    A, PA, F = dpkt.tcp.TH_ACK, dpkt.tcp.TH_PUSH | dpkt.tcp.TH_ACK, dpkt.tcp.TH_FIN | dpkt.tcp.TH_ACK
    seq = {True: 1000, False: 5000}
    ends = {True: (robot, port, ROBOT_MAC), False: (client, client_port, CLIENT_MAC)}

    def frame(from_robot: bool, flags: int, data: bytes = b"") -> bytes:
        (src, sport, smac), (dst, dport, dmac) = ends[from_robot], ends[not from_robot]
        return _frame(src, dst, sport, dport, seq[from_robot], seq[not from_robot], flags, data, smac, dmac)

    frames = session_frames([], port=port, client_port=client_port, robot=robot, client=client)[:3]  # handshake
    for i, (from_robot, payload) in enumerate(steps):
        sent = frame(from_robot, F if payload is FIN else PA, payload or b"")
        if i != lose:
            frames.append(sent)
        seq[from_robot] += 1 if payload is FIN else len(payload)
        frames.append(frame(not from_robot, A))
    return frames


def write(path: Path, frames: Iterable[bytes], pcapng: bool = False, start: float = 1_700_000_000.0,
          step: float = 0.1, times: Optional[Sequence[float]] = None) -> Path:
    """Write frames, 100 ms apart (the robot-state rate), or at `times` (seconds after `start`,
    one per frame), as .pcap or .pcapng."""
    path = Path(path)
    frames = list(frames)
    if times is not None and len(times) != len(frames):
        raise ValueError(f"{len(times)} times for {len(frames)} frames")
    with path.open("wb") as fh:
        writer = dpkt.pcapng.Writer(fh) if pcapng else dpkt.pcap.Writer(fh)
        for i, frame in enumerate(frames):
            writer.writepkt(frame, ts=start + (times[i] if times is not None else i * step))
    return path


# ---- how a robot's byte stream is cut into segments ----

def whole(messages: Sequence[bytes]) -> list[bytes]:
    """One message per segment."""
    return list(messages)


def bytewise(messages: Sequence[bytes]) -> list[bytes]:
    """One byte per segment."""
    data = b"".join(messages)
    return [data[i:i + 1] for i in range(len(data))]


def random_cuts(messages: Sequence[bytes], seed: int = 0, max_len: int = 700) -> list[bytes]:
    """Cut anywhere, with segment sizes from 1 to max_len."""
    data = b"".join(messages)
    rng = random.Random(seed)
    out, pos = [], 0
    while pos < len(data):
        n = rng.randint(1, max_len)
        out.append(data[pos:pos + n])
        pos += n
    return out


def packed(messages: Sequence[bytes], per_segment: int = 3) -> list[bytes]:
    """Several whole messages per segment."""
    return [b"".join(messages[i:i + per_segment]) for i in range(0, len(messages), per_segment)]


def robot_session(payloads: Sequence[bytes], **kwargs) -> list[bytes]:
    """Frames of a session in which the robot sends the given segment payloads."""
    return session_frames([Segment(True, p) for p in payloads], **kwargs)
