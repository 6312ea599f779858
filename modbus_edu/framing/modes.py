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
           "splitter_for"]

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


def detect_mode(data: bytes) -> str:
    """Best guess of a raw frame's mode: ``"ascii"``, ``"tcp"`` or ``"rtu"``.

    * it starts with ``:``: ASCII, unless its characters are not hex digits and it is really an RTU
      frame for unit 58 (0x3A; a correct RTU CRC) or a TCP frame whose transaction id starts with 0x3A
      (a valid MBAP header);
    * its first 6 bytes are a valid MBAP header (protocol 0, a length of 2..254 equal to the bytes that
      follow): TCP, unless the last two bytes are also a correct RTU CRC (then RTU);
    * anything else: RTU (the mode without a marker).

    Hex text is accepted too (read with :func:`parse_hex`; text that is not hex counts as RTU).
    """
    if isinstance(data, str):
        try:
            data = parse_hex(data)
        except FrameError:
            return "rtu"
    try:
        data = _as_bytes(data, "detect_mode")
    except FrameError:
        return "rtu"
    rtu_crc_ok = len(data) >= 4 and crc16(data[:-2]) == int.from_bytes(data[-2:], "little")
    if data.startswith(b":"):
        body = data[1:-2] if data.endswith(b"\r\n") else data[1:]
        if not all(ch in _HEX_DIGITS for ch in body):
            if rtu_crc_ok:
                return "rtu"
            if _looks_like_mbap(data):
                return "tcp"
        return "ascii"
    if _looks_like_mbap(data) and not rtu_crc_ok:
        return "tcp"
    return "rtu"


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
