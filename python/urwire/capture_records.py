"""Frames out of .pcap/.pcapng files that may be cut short or damaged, a record at a time.

dpkt reads each file's header and parses each record; the walk from record to record is ours,
so that one bad record costs that record and not the file:

- pcapng blocks carry their length at both ends. A block whose body does not parse is skipped
  (its length says where the next one starts); a block whose two lengths disagree, or that runs
  past the end of the file, leaves no safe place to go on: reading stops there.
- pcap records have no trailer: a record longer than the snap length, or than what is left of
  the file, ends the reading. Some writers (dpkt's among them) declare a snap length and then
  write longer frames, which Wireshark reads; so, as Wireshark does, the limit is never below
  PCAP_RECORD_MAX.

Each problem comes out as a CaptureFault at the file offset of the record where it was met: for
a file cut short, the offset where reading stopped (everything before it was read).
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import BinaryIO, Iterator, Union
# dpkt is imported by the functions that read a capture: `import urwire` needs the standard library only.

PCAP_RECORD_MAX = 262144       # Wireshark's largest record for Ethernet
PCAPNG_BLOCK_MIN = 12           # type, length, trailing length
PCAPNG_LITTLE_ENDIAN = b"\x4d\x3c\x2b\x1a"   # the byte-order magic of a section header, as stored


@dataclass
class CaptureFault:
    """A capture record that could not be read: where it starts in the file, and why."""

    offset: int
    error: str


class _CountingReader:
    """The file as dpkt reads it, counting the bytes taken, so every record has its offset."""

    def __init__(self, fh: BinaryIO) -> None:
        self._fh = fh
        self.name = getattr(fh, "name", "<capture>")
        self.offset = 0
        self.head = b""  # the file's first bytes: its magic and, in pcapng, its byte order

    def read(self, n: int = -1) -> bytes:
        data = self._fh.read(n)
        if self.offset < 12:
            self.head = (self.head + data)[:12]
        self.offset += len(data)
        return data


Frame = tuple  # (capture time in seconds since the epoch, frame bytes)


class CaptureFrames:
    """Iterate a capture's frames; `linktype` is known once the header is read (None if it is
    not), and a CaptureFault takes the place of each record that could not be read."""

    def __init__(self, fh: BinaryIO, pcapng: bool) -> None:
        self._file = _CountingReader(fh)
        self._pcapng = pcapng
        self.linktype = None

    def __iter__(self) -> Iterator[Union[Frame, CaptureFault]]:
        import dpkt

        try:
            reader = dpkt.pcapng.Reader(self._file) if self._pcapng else dpkt.pcap.Reader(self._file)
        except (dpkt.UnpackError, ValueError, struct.error) as exc:
            yield CaptureFault(0, f"capture header unreadable ({_reason(exc)}): nothing decoded")
            return
        self.linktype = reader.datalink()
        yield from (self._pcapng_frames(reader) if self._pcapng else self._pcap_frames(reader))

    def _pcapng_frames(self, reader) -> Iterator[Union[Frame, CaptureFault]]:
        import dpkt
        from dpkt import pcapng

        little = self._file.head[8:12] == PCAPNG_LITTLE_ENDIAN
        order = "<" if little else ">"
        packet_blocks = {pcapng.PCAPNG_BT_EPB: pcapng.EnhancedPacketBlockLE if little else pcapng.EnhancedPacketBlock,
                         pcapng.PCAPNG_BT_PB: pcapng.PacketBlockLE if little else pcapng.PacketBlock}
        while True:
            at = self._file.offset
            head = self._file.read(8)
            if not head:
                return
            if len(head) < 8:
                yield CaptureFault(at, "capture cut short in a block header: reading stopped")
                return
            kind, length = struct.unpack(order + "II", head)
            if length < PCAPNG_BLOCK_MIN or length % 4:
                yield CaptureFault(at, f"pcapng block length {length} is not valid: reading stopped")
                return
            body = self._file.read(length - 8)
            if len(body) < length - 8:
                yield CaptureFault(at, f"capture cut short in a block of {length} bytes: reading stopped")
                return
            (trailer,) = struct.unpack(order + "I", body[-4:])
            if trailer != length:
                yield CaptureFault(at, f"pcapng block lengths disagree ({length}, {trailer}): reading stopped")
                return
            block_class = packet_blocks.get(kind)
            if block_class is None:
                continue  # not a packet: interface, statistics, name resolution ...
            try:
                block = block_class(head + body)
                if block.caplen > length - block.__hdr_len__:
                    raise ValueError(f"captured length {block.caplen} exceeds the block")
            except (dpkt.UnpackError, ValueError, struct.error) as exc:
                yield CaptureFault(at, f"damaged pcapng packet block skipped ({_reason(exc)})")
                continue
            ts = reader._tsoffset + ((block.ts_high << 32) | block.ts_low) / reader._divisor
            yield ts, block.pkt_data

    def _pcap_frames(self, reader) -> Iterator[Union[Frame, CaptureFault]]:
        import dpkt

        header_class = dpkt.pcap.MAGIC_TO_PKT_HDR[int.from_bytes(self._file.head[:4], "big")]
        size = header_class.__hdr_len__
        while True:
            at = self._file.offset
            head = self._file.read(size)
            if not head:
                return
            if len(head) < size:
                yield CaptureFault(at, "capture cut short in a record header: reading stopped")
                return
            header = header_class(head)
            limit = max(reader.snaplen, PCAP_RECORD_MAX)
            if header.caplen > limit:
                yield CaptureFault(at, f"pcap record length {header.caplen} exceeds the snap length "
                                       f"{limit}: reading stopped")
                return
            frame = self._file.read(header.caplen)
            if len(frame) < header.caplen:
                yield CaptureFault(at, f"capture cut short in a record of {header.caplen} bytes: reading stopped")
                return
            yield header.tv_sec + header.tv_usec / float(reader._divisor), frame


def _reason(exc: Exception) -> str:
    return str(exc) or type(exc).__name__
