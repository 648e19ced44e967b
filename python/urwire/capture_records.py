"""Frames out of .pcap/.pcapng files that may be cut short or damaged, a record at a time.

dpkt reads each file's header and parses each record; the walk from record to record is ours,
so that one bad record costs that record and not the file:

- pcapng: each section (section header block) has its byte order, and each interface
  (interface description block) its link type and timestamp resolution (if_tsresol, if_tsoffset);
  a packet is read by its interface's.
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
PCAPNG_BYTE_ORDERS = (PCAPNG_LITTLE_ENDIAN, b"\x1a\x2b\x3c\x4d")
PCAPNG_SECTION = 0x0A0D0D0A     # a section header block's type, the same in either byte order
PCAPNG_INTERFACE_MIN = 20       # an interface description block up to its options, and its trailer
PCAPNG_INTERFACES_MAX = 1024    # interfaces kept per section (runtime/c/capture keeps as many)


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
        # Each interface's (link type, timestamp units per second, offset in seconds); a section starts none.
        faces = [(reader.idb.linktype, reader._divisor, reader._tsoffset)]
        while True:
            order = "<" if little else ">"
            at = self._file.offset
            head = self._file.read(8)
            if not head:
                return
            if len(head) < 8:
                yield CaptureFault(at, "capture cut short in a block header: reading stopped")
                return
            kind, length = struct.unpack(order + "II", head)
            bom = b""
            if kind == PCAPNG_SECTION:        # a section of its own byte order: its length needs it
                bom = self._file.read(4)
                if len(bom) < 4:
                    yield CaptureFault(at, "capture cut short in a block header: reading stopped")
                    return
                if bom in PCAPNG_BYTE_ORDERS:
                    order = "<" if bom == PCAPNG_LITTLE_ENDIAN else ">"
                    (length,) = struct.unpack(order + "I", head[4:])
            if length < PCAPNG_BLOCK_MIN or length % 4:
                yield CaptureFault(at, f"pcapng block length {length} is not valid: reading stopped")
                return
            body = bom + self._file.read(length - 8 - len(bom))
            if len(body) < length - 8:
                yield CaptureFault(at, f"capture cut short in a block of {length} bytes: reading stopped")
                return
            (trailer,) = struct.unpack(order + "I", body[-4:])
            if trailer != length:
                yield CaptureFault(at, f"pcapng block lengths disagree ({length}, {trailer}): reading stopped")
                return
            if kind == PCAPNG_SECTION:
                little, faces = order == "<", []
                continue
            if kind == pcapng.PCAPNG_BT_IDB:
                fault = _describe(head + body, order, faces)
                if fault:
                    yield CaptureFault(at, fault)
                continue
            block_class = {pcapng.PCAPNG_BT_EPB: pcapng.EnhancedPacketBlockLE if little else pcapng.EnhancedPacketBlock,
                           pcapng.PCAPNG_BT_PB: pcapng.PacketBlockLE if little else pcapng.PacketBlock}.get(kind)
            if block_class is None:
                continue  # not a packet: statistics, name resolution ...
            try:
                block = block_class(head + body)
                if block.caplen > length - block.__hdr_len__:
                    raise ValueError(f"captured length {block.caplen} exceeds the block")
                if block.iface_id >= len(faces):
                    raise ValueError(f"interface {block.iface_id} is not described")
            except (dpkt.UnpackError, ValueError, struct.error) as exc:
                yield CaptureFault(at, f"damaged pcapng packet block skipped ({_reason(exc)})")
                continue
            self.linktype, divisor, offset = faces[block.iface_id]
            yield offset + ((block.ts_high << 32) | block.ts_low) / divisor, block.pkt_data

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


def _describe(block: bytes, order: str, faces: list) -> str:
    """An interface description block's link type and timestamp options added to `faces`; the
    fault's text if it cannot be."""
    if len(block) < PCAPNG_INTERFACE_MIN:
        return f"damaged pcapng interface block skipped (got {len(block)}, {PCAPNG_INTERFACE_MIN} needed at least)"
    if len(faces) >= PCAPNG_INTERFACES_MAX:
        return f"pcapng interface block skipped: more than {PCAPNG_INTERFACES_MAX} interfaces"
    (linktype,) = struct.unpack(order + "H", block[8:10])
    divisor, offset, at, end = 1e6, 0, PCAPNG_INTERFACE_MIN - 4, len(block) - 4
    while at + 4 <= end:
        code, size = struct.unpack(order + "HH", block[at:at + 4])
        value = block[at + 4:min(at + 4 + size, end)]
        if code == 0:
            break
        if code == 9 and value:     # if_tsresol: a power of 10, or of 2 with the top bit
            divisor = float((2 if value[0] & 0x80 else 10) ** (value[0] & 0x7F))
        elif code == 14 and len(value) >= 8:    # if_tsoffset
            (offset,) = struct.unpack(order + "q", value[:8])
        at += 4 + ((len(value) + 3) & ~3)
    faces.append((linktype, divisor, offset))
    return ""


def _reason(exc: Exception) -> str:
    return str(exc) or type(exc).__name__
