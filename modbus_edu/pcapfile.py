"""What a capture file must be before its packets are read: a known magic number, and nothing cut short.

:mod:`modbus_edu.capture` reads the packets with scapy, which stops quietly at a pcapng block cut short
and takes an enhanced packet block's captured length even when it runs past the block.  So the file's
structure is checked here first, on its bytes alone: every :class:`~modbus_edu.errors.CaptureError`
says what is wrong and at which byte.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .errors import CaptureError

__all__ = ["MAGICS", "MAX_PACKET", "bad_magic", "check_blocks", "cut_short"]

#: The largest snapshot length libpcap and Wireshark accept (bytes of one packet).
MAX_PACKET = 262_144

_SECTION_HEADER = 0x0A0D0D0A
_ENHANCED_PACKET = 6
_BYTE_ORDERS = {b"\x4d\x3c\x2b\x1a": "little", b"\x1a\x2b\x3c\x4d": "big"}


def check_blocks(path: Path, handle: Any, size: int) -> None:
    """Walk a pcapng file's blocks before scapy reads it: each block whole, its length the same at both
    ends, and each enhanced packet block's captured bytes inside it (scapy stops quietly at a block cut
    short, and takes a captured length that runs past its block)."""
    order: Any = "little"
    where, number = 0, 0
    while where < size:
        number += 1
        handle.seek(where)
        head = handle.read(28)
        if len(head) < 12:
            raise CaptureError(f"{path.name}: the file ends inside block {number} (at byte {where}): "
                               f"{len(head)} bytes, where a block has at least 12; the capture was cut short")
        kind = int.from_bytes(head[:4], "little")
        if kind == _SECTION_HEADER:
            order = _BYTE_ORDERS.get(head[8:12], "")
            if not order:
                raise CaptureError(f"{path.name}: the section header at byte {where} has the byte-order "
                                   f"magic {head[8:12].hex(' ').upper()}, where pcapng has 1A 2B 3C 4D "
                                   f"(either way round): the file is damaged")
        else:
            kind = int.from_bytes(head[:4], order)
        length = int.from_bytes(head[4:8], order)
        if length < 12 or length % 4:
            raise CaptureError(f"{path.name}: block {number} (at byte {where}) says it is {length} bytes "
                               f"long, where a block is a multiple of 4 and at least 12: the file is damaged")
        if where + length > size:
            raise CaptureError(f"{path.name}: the file ends inside block {number} (at byte {where}): its "
                               f"header says {length} bytes, only {size - where} are there; the capture "
                               f"was cut short")
        handle.seek(where + length - 4)
        if handle.read(4) != head[4:8]:
            raise CaptureError(f"{path.name}: block {number} (at byte {where}) ends with another length "
                               f"than it starts with ({length}): the file is damaged")
        if kind == _ENHANCED_PACKET:
            room = length - 32  # 12 bytes of type and lengths, 20 of interface, time and lengths
            captured = int.from_bytes(head[20:24], order) if room >= 0 else 0
            if room < 0 or captured > room:
                raise CaptureError(f"{path.name}: packet block {number} (at byte {where}) says it holds "
                                   f"{captured} captured bytes, where its {length} bytes have room for "
                                   f"{max(room, 0)}: its length field is damaged")
        where += length


MAGICS = {
    b"\xd4\xc3\xb2\xa1": "pcap", b"\xa1\xb2\xc3\xd4": "pcap",
    b"\x4d\x3c\xb2\xa1": "pcap", b"\xa1\xb2\x3c\x4d": "pcap",
    b"\x0a\x0d\x0d\x0a": "pcapng",
}


def bad_magic(path: Path, magic: bytes) -> str:
    shown = magic.hex(" ").upper() or "nothing (the file is empty)"
    if magic[:2] == b"\x1f\x8b":
        return f"{path.name} is gzip-compressed (starts 1F 8B): unpack it first (gunzip), then read it"
    return (f"{path.name} is not a capture file: it starts with {shown}, where a pcap file starts with "
            f"D4 C3 B2 A1 or 4D 3C B2 A1 (or the same reversed) and a pcapng file with 0A 0D 0D 0A")


def cut_short(path: Path, count: int, where: int, caplen: int, got: int) -> str:
    if caplen > MAX_PACKET:
        return (f"{path.name}: packet {count + 1} (record at byte {where}) claims {caplen} bytes, more than "
                f"any capture holds (at most {MAX_PACKET}): its length field is damaged")
    return (f"{path.name}: the file ends inside packet {count + 1} (record at byte {where}): its header "
            f"says {caplen} bytes, only {got} are there; the capture was cut short")
