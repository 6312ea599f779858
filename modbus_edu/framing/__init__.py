"""Frames (application data units) of the three Modbus modes, and splitters that cut them from a stream.

A Modbus *PDU* (function code + data, see :mod:`modbus_edu.pdu`) never travels alone.  Each mode wraps
it in an *ADU* that says who it is for and, on serial lines, protects it with an error check:

=======  ===========================================================  ===========================
mode     frame                                                        error check
=======  ===========================================================  ===========================
RTU      unit, PDU, CRC (2 bytes, low byte first)                     CRC-16/MODBUS
ASCII    ``:``, the same bytes as uppercase hex, LRC as hex, CR LF    LRC (8-bit)
TCP      MBAP header (transaction, protocol, length, unit), PDU       none: TCP already checks
=======  ===========================================================  ===========================

The frame classes (:class:`RtuFrame`, :class:`AsciiFrame`, :class:`TcpFrame`) build and check complete
frames.  Their ``decode`` is strict: every rule of the mode is checked and a broken rule raises a
:class:`~modbus_edu.errors.FrameError` subclass whose message says what was wrong, at which byte
(or character) and what was expected.  Problems inside the PDU raise the
:class:`~modbus_edu.errors.PduError` subclasses of :func:`modbus_edu.pdu.decode_pdu`; their byte
offsets count from the start of the frame.

The splitters (:class:`RtuSplitter`, :class:`AsciiSplitter`, :class:`TcpSplitter`) solve the other half
of the problem: bytes arrive from a wire in arbitrary pieces, and a receiver has to find where each frame
starts and ends.  They are sans-I/O: feed them bytes, they hand back complete raw frames.

Serial words and TCP words: on a serial line the course says *master* and *slave* and the address byte is
the *slave address*; on TCP the spec says *client* and *server* and the same byte is the *unit
identifier*.  In this module the field is called ``unit`` in all three modes.
"""

from __future__ import annotations

from .ascii import ASCII_MAX_FRAME, AsciiFrame, AsciiSplitter
from .base import BROADCAST, MAX_SERIAL_UNIT, MBAP_HEADER_SIZE, MODES, ROLES, parse_hex
from .modes import (
    Frame,
    decode_frame,
    detect_mode,
    detect_mode_why,
    encode_frame,
    frame_class,
    make_frame,
    splitter_for,
)
from .rtu import RTU_MAX_FRAME, RtuFrame, RtuSplitter
from .tcp import TCP_MAX_FRAME, TcpFrame, TcpSplitter

__all__ = [
    "MODES",
    "ROLES",
    "RTU_MAX_FRAME",
    "ASCII_MAX_FRAME",
    "TCP_MAX_FRAME",
    "MBAP_HEADER_SIZE",
    "BROADCAST",
    "MAX_SERIAL_UNIT",
    "RtuFrame",
    "AsciiFrame",
    "TcpFrame",
    "Frame",
    "frame_class",
    "make_frame",
    "encode_frame",
    "decode_frame",
    "detect_mode",
    "detect_mode_why",
    "parse_hex",
    "RtuSplitter",
    "AsciiSplitter",
    "TcpSplitter",
    "splitter_for",
]
