"""The three modes by name: :func:`frame_class`, :func:`make_frame`, :func:`encode_frame`,
:func:`decode_frame`, :func:`detect_mode` (which mode some bytes are) and :func:`splitter_for`.
"""

from __future__ import annotations

from .. import pdu as _pdu
from ..codes import MAX_MBAP_LENGTH, MBAP_HEADER_SIZE, MIN_MBAP_LENGTH
from ..crc import crc16
from ..errors import FrameError
from .ascii import AsciiFrame, AsciiSplitter
from .base import _HEX_DIGITS, _as_bytes, _check_mode, parse_hex
from .rtu import RtuFrame, RtuSplitter
from .tcp import TcpFrame, TcpSplitter

__all__ = ["Frame", "frame_class", "make_frame", "encode_frame", "decode_frame", "detect_mode",
           "detect_mode_why", "splitter_for"]

Frame = RtuFrame | AsciiFrame | TcpFrame
"""Any of the three frame types."""

_FRAME_CLASSES: dict[str, type] = {"rtu": RtuFrame, "ascii": AsciiFrame, "tcp": TcpFrame}


def frame_class(mode: str) -> type:
    """The frame class of a mode: ``frame_class("rtu") is RtuFrame``."""
    return _FRAME_CLASSES[_check_mode(mode)]


def make_frame(mode: str, unit: int, pdu: _pdu.Pdu, transaction_id: int = 0) -> Frame:
    """Wrap a PDU in the frame of a mode (``transaction_id`` is used by TCP only)."""
    mode = _check_mode(mode)
    if mode == "tcp":
        return TcpFrame(transaction_id=transaction_id, unit=unit, pdu=pdu)
    return _FRAME_CLASSES[mode](unit=unit, pdu=pdu)


def encode_frame(mode: str, unit: int, pdu: _pdu.Pdu, transaction_id: int = 0) -> bytes:
    """The bytes of a PDU framed for a mode: ``encode_frame("rtu", 1, ReadHoldingRegistersRequest(0, 1))``."""
    return make_frame(mode, unit, pdu, transaction_id).encode()


def decode_frame(data: bytes, mode: str, role: str = "request") -> Frame:
    """Decode a complete frame of the given mode; see the ``decode`` of each frame class."""
    return _FRAME_CLASSES[_check_mode(mode)].decode(data, role)


def _looks_like_mbap(data: bytes) -> bool:
    if len(data) < MBAP_HEADER_SIZE + 1 or data[2:4] != b"\x00\x00":
        return False
    length = int.from_bytes(data[4:6], "big")
    return MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH and length == len(data) - 6


def _mbap_length_swapped(data: bytes) -> bool:
    """Protocol 0, and bytes 4-5 read low byte first count the bytes that follow: an MBAP header whose
    length was written little-endian (the slip of a published tool), not an RTU frame."""
    if len(data) < MBAP_HEADER_SIZE + 1 or data[2:4] != b"\x00\x00":
        return False
    length = int.from_bytes(data[4:6], "little")
    return MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH and length == len(data) - 6


def detect_mode_why(data: bytes | str) -> tuple[str, str]:
    """:func:`detect_mode` and the reason, in words: ``("tcp", "bytes 2-3 are protocol 0 and ...")``."""
    if isinstance(data, str):
        try:
            data = parse_hex(data)
        except FrameError:
            return "rtu", "not hex text: RTU, the mode without a marker"
    try:
        data = _as_bytes(data, "detect_mode")
    except FrameError:
        return "rtu", "not bytes: RTU, the mode without a marker"
    rtu_crc_ok = len(data) >= 4 and crc16(data[:-2]) == int.from_bytes(data[-2:], "little")
    crc = "its last two bytes are its RTU CRC"
    if data.startswith(b":"):
        body = data[1:-2] if data.endswith(b"\r\n") else data[1:]
        if not all(ch in _HEX_DIGITS for ch in body):
            if rtu_crc_ok:
                return "rtu", f"':' in front but not hex text, and {crc} (unit 58 is 0x3A, ':')"
            if _looks_like_mbap(data):
                return "tcp", "':' in front but not hex text, and its first 6 bytes are an MBAP header"
        return "ascii", "it starts with ':'"
    follow = len(data) - MBAP_HEADER_SIZE + 1
    if _looks_like_mbap(data):
        if rtu_crc_ok:
            return "rtu", f"{crc} (its first 6 bytes could also be an MBAP header)"
        return "tcp", f"protocol 0 in bytes 2-3, and the length counts the {follow} bytes that follow"
    if _mbap_length_swapped(data) and not rtu_crc_ok:
        return "tcp", (f"protocol 0 in bytes 2-3, and the length, read low byte first, counts the {follow} "
                       f"bytes that follow")
    if rtu_crc_ok:
        return "rtu", crc
    return "rtu", "no ':' in front, no MBAP header"


def detect_mode(data: bytes | str) -> str:
    """Best guess of a raw frame's mode: ``"ascii"``, ``"tcp"`` or ``"rtu"``.

    * it starts with ``:``: ASCII, unless its characters are not hex digits and it is really an RTU
      frame for unit 58 (0x3A; a correct RTU CRC) or a TCP frame whose transaction id starts with 0x3A
      (a valid MBAP header);
    * its first 6 bytes are a valid MBAP header (protocol 0, a length of 2..254 equal to the bytes that
      follow): TCP, unless the last two bytes are also a correct RTU CRC (then RTU);
    * protocol 0 and a length that counts the bytes that follow when read low byte first: TCP too (a
      length written little-endian is a TCP slip to show, not an RTU frame with a wrong CRC), unless
      the last two bytes are a correct RTU CRC;
    * anything else: RTU (the mode without a marker).

    Hex text is accepted too (read with :func:`parse_hex`; text that is not hex counts as RTU).
    :func:`detect_mode_why` also says why.
    """
    return detect_mode_why(data)[0]

_SPLITTERS: dict[str, type] = {"rtu": RtuSplitter, "ascii": AsciiSplitter, "tcp": TcpSplitter}


def splitter_for(mode: str, role: str = "request", open_ended: bool = False
                 ) -> RtuSplitter | AsciiSplitter | TcpSplitter:
    """A fresh splitter for a mode (``role`` and ``open_ended`` matter to RTU only, which cuts by expected
    length; see :class:`RtuSplitter`)."""
    mode = _check_mode(mode)
    if mode == "rtu":
        return RtuSplitter(role, open_ended)
    _pdu._check_role(role)
    return _SPLITTERS[mode]()
