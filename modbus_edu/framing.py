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

import re
import warnings
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, ClassVar

from . import pdu as _pdu
from .codes import MAX_MBAP_LENGTH, MBAP, MBAP_HEADER_SIZE, MIN_MBAP_LENGTH, ROLES, _hex
from .crc import CRC_TABLE, crc16, lrc
from .errors import (
    AsciiFormatError,
    ConfigError,
    CrcError,
    FrameError,
    FrameLengthError,
    LrcError,
    MbapError,
    ModbusError,
    PduError,
    ReservedUnitWarning,
    UnitError,
    shown,
)

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

MODES: tuple[str, ...] = ("rtu", "ascii", "tcp")
"""The three transmission modes, by the names used everywhere in the library."""

RTU_MAX_FRAME = 256
"""Largest RTU frame: unit (1) + PDU (at most 253) + CRC (2)."""

ASCII_MAX_FRAME = 513
"""Largest ASCII frame in characters: ':' (1) + 2 hex digits for each of unit, 253 PDU bytes and the LRC
(2 x 255 = 510) + CR LF (2)."""

TCP_MAX_FRAME = 260
"""Largest Modbus/TCP frame: MBAP header (7) + PDU (at most 253)."""

BROADCAST = 0
"""Serial unit address 0: every slave acts on the request (writes only) and none answers."""

MAX_SERIAL_UNIT = 247
"""Highest slave address on a serial line; 248..255 are reserved."""

_UNIT_BYTES = tuple(bytes([unit]) for unit in range(256))  # one-byte unit fields, built once


# --- small helpers ---------------------------------------------------------------------------------
def _span(first: int, last: int) -> str:
    """'byte 3' or 'bytes 3-5'."""
    return f"byte {first}" if first == last else f"bytes {first}-{last}"


def _char_span(first: int, last: int) -> str:
    return f"char {first}" if first == last else f"chars {first}-{last}"


def _as_bytes(data: object, what: str) -> bytes:
    """Accept bytes, bytearray, memoryview (or a list of ints); anything else is a FrameError."""
    if isinstance(data, bytes):
        return data
    if isinstance(data, (bytearray, memoryview)):
        return bytes(data)
    if isinstance(data, str):
        raise FrameError(
            f"{what} expects bytes, got the text {data[:40]!r}; turn hex text into bytes with "
            f"parse_hex(), e.g. parse_hex('01 03 00 00 00 01 84 0A')"
        )
    if isinstance(data, int):  # bytes(5) would quietly make five zero bytes
        raise FrameError(f"{what} expects bytes, got the number {data!r}; bytes([{data!r}]) is one byte")
    try:
        return bytes(data)  # type: ignore[call-overload]
    except (TypeError, ValueError):
        raise FrameError(f"{what} expects bytes (values 0..255), got {type(data).__name__}") from None


def _check_mode(mode: object) -> str:
    if isinstance(mode, str) and mode.lower() in MODES:
        return mode.lower()
    raise ConfigError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")


def _check_unit(unit: object, highest: int, mode: str) -> int:
    """Validate a unit given to a constructor: one byte; a reserved serial address (248..255) warns."""
    if isinstance(unit, bool) or not isinstance(unit, int):
        raise UnitError(f"{mode} unit must be an int, got {shown(unit)}")
    if not 0 <= unit <= 255:
        raise UnitError(f"{mode} unit {shown(unit)} does not fit its one byte: expected 0..255")
    if unit > highest:
        warnings.warn(
            f"{mode} unit {unit} (0x{unit:02X}) is in the reserved range 248..255: standard slaves use "
            f"1..247 (0 = broadcast); some devices answer a reserved address (an 'any address' or a "
            f"configuration address), so the frame is built anyway",
            ReservedUnitWarning, stacklevel=4)
    return unit


def _received(cls: type, unit: int, pdu: _pdu.Pdu) -> Any:
    """A serial frame as it came off the wire: any address byte, with no warning (a sniffer shows all)."""
    if unit <= MAX_SERIAL_UNIT:
        return cls(unit, pdu)
    frame = object.__new__(cls)
    object.__setattr__(frame, "unit", unit)
    object.__setattr__(frame, "pdu", pdu)
    return frame


def _check_pdu(pdu: object, cls_name: str) -> None:
    if not isinstance(pdu, _pdu.Pdu):
        raise FrameError(
            f"{cls_name}.pdu must be a PDU object such as ReadHoldingRegistersRequest(address=0, count=1), "
            f"got {type(pdu).__name__}"
        )


def _decode_pdu(data: bytes, role: str, first: int, ascii_chars: bool = False) -> _pdu.Pdu:
    """Decode the PDU part of a frame, whose function code is byte ``first`` of the frame.

    :func:`pdu.decode_pdu` counts the offsets in its messages from ``first``, so they are frame offsets.
    In ASCII those are offsets in the decoded bytes; a note says which characters they are.
    """
    try:
        return _pdu.decode_pdu(data, role, first)
    except PduError as exc:
        if ascii_chars and exc.args and isinstance(exc.args[0], str):
            exc.args = (f"{exc.args[0]} (bytes of the decoded ASCII frame: byte k is written in chars "
                        f"2k+1 and 2k+2)", *exc.args[1:])
        raise


# --- the frames --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RtuFrame:
    """A Modbus RTU frame: the unit address, the PDU, and a CRC-16 over both.

    Layout (the read-one-register request ``01 03 00 00 00 01 84 0A``)::

        offset  size  field                       example
        0       1     unit (slave address)        01
        1       1     function code               03
        2..n-3  n-4   data of the PDU             00 00 00 01
        n-2     1     CRC low byte                84
        n-1     1     CRC high byte               0A      (crc16 = 0x0A84, low byte first)

    The CRC covers bytes 0..n-3 (unit and PDU).  A frame has 4..256 bytes.  Unit 0 is broadcast (every
    slave acts, none answers), 1..247 are slave addresses, 248..255 are reserved.  On the wire the frame
    is delimited by silence (3.5 character times); when reading a stream without timing, the
    :class:`RtuSplitter` finds the end from the function code instead.
    """

    unit: int
    pdu: _pdu.Pdu

    mode: ClassVar[str] = "rtu"

    def __post_init__(self) -> None:
        if not (type(self.unit) is int and 0 <= self.unit <= MAX_SERIAL_UNIT
                and isinstance(self.pdu, _pdu.Pdu)):  # the usual case, checked in one go
            _check_unit(self.unit, MAX_SERIAL_UNIT, "RTU")
            _check_pdu(self.pdu, "RtuFrame")

    def encode(self) -> bytes:
        """The frame in wire order: unit, PDU, CRC low byte, CRC high byte."""
        body = _UNIT_BYTES[self.unit] + self.pdu.encode()
        return body + crc16(body).to_bytes(2, "little")

    @classmethod
    def decode(cls, data: bytes, role: str = "request") -> RtuFrame:
        """Check and decode one complete RTU frame.

        Checks, in the order a receiving device makes them: length (4..256 bytes), CRC, unit address
        (0..247), then the PDU (``pdu.decode_pdu(role)``).  Raises :class:`FrameLengthError`,
        :class:`CrcError`, :class:`UnitError` or a :class:`PduError` subclass.
        """
        data = _as_bytes(data, "RtuFrame.decode")
        role = _pdu._check_role(role)
        n = len(data)
        if n < 4:
            raise FrameLengthError(
                f"RTU frame too short: {n} byte{'s' if n != 1 else ''}; expected at least 4 "
                f"(unit at byte 0, function code at byte 1, CRC at bytes 2-3)"
            )
        if n > RTU_MAX_FRAME:
            raise FrameLengthError(
                f"RTU frame too long: {n} bytes; expected at most {RTU_MAX_FRAME} "
                f"(unit 1 + PDU at most {_pdu.MAX_PDU_SIZE} + CRC 2)"
            )
        body, carried = data[:-2], int.from_bytes(data[-2:], "little")
        computed = crc16(body)
        if carried != computed:
            _check_lost_bytes(data, role)
            raise CrcError(
                f"CRC mismatch: frame carries 0x{carried:04X}, computed 0x{computed:04X} over "
                f"{_span(0, n - 3)} (the CRC is {_span(n - 2, n - 1)}, low byte first: "
                f"expected {_hex(computed.to_bytes(2, 'little'))}, found {_hex(data[-2:])})",
                received=carried,
                computed=computed,
            )
        return _received(cls, data[0], _decode_pdu(data[1:-2], role, 1))


def _check_lost_bytes(data: bytes, role: str) -> None:
    """Raise :class:`FrameLengthError` if a frame whose CRC failed is shorter than its own header says.

    A byte lost on the line shifts the bytes after it, so the CRC check fails; but the real fault is the
    missing byte, and the byte count (or the function's fixed length) shows it.  If one flipped bit in
    the function code or the byte count would explain the length as well, the frame was damaged rather
    than cut, and the CRC error stands.
    """
    n = len(data)

    def length(header: bytes) -> int | None:
        try:
            return _pdu.pdu_length(header, role)
        except ModbusError:
            return None

    expected = length(data[1:-2])
    if expected is None or expected + 3 <= n:
        return
    count_at = 2 if role == "response" else 6  # where a byte count would sit, if the function has one
    for at in {1, count_at} & set(range(1, n - 2)):
        for bit in range(8):
            header = bytearray(data[1:-2])
            header[at - 1] ^= 1 << bit
            if length(bytes(header)) == n - 3:
                return
    lost = expected + 3 - n
    function = data[1]
    if _pdu.pdu_class(function, role).byte_count_at == count_at - 1:  # the byte count tells
        what = f"byte count (byte {count_at}) says {data[count_at]} data bytes, {n - count_at - 3} arrived"
    else:
        what = f"an FC{function} {role} is {expected + 3} bytes, {n} arrived"
    gone = "a byte was" if lost == 1 else f"{lost} bytes were"
    raise FrameLengthError(f"RTU frame too short: {what}: {gone} lost "
                           "(which is why the CRC does not match)")


@dataclass(frozen=True)
class AsciiFrame:
    """A Modbus ASCII frame: ``:``, unit + PDU + LRC written as hex digits, CR LF.

    Layout (unit 5 writes 0x0200 into register 0x1001: ``:050610010200E2`` CR LF)::

        chars    field                               example
        0        start                               ':'  (0x3A)
        1-2      unit (slave address), 2 hex digits  05
        3-4      function code                       06
        5..m-5   data of the PDU, 2 digits a byte     10 01 02 00
        m-4..m-3 LRC, 2 hex digits                   E2
        m-2..m-1 end                                 CR LF (0x0D 0x0A)

    Every byte becomes two characters, and the 2-byte CRC becomes a 1-byte LRC: a frame that has n bytes
    in RTU has 2n + 1 characters in ASCII (``:`` and CR LF included).  The LRC is the
    two's complement of the 8-bit sum of the *bytes* (not the characters) of unit and PDU.  A frame has
    9..513 characters.  :meth:`encode` writes uppercase digits; :meth:`decode` also accepts lowercase.
    """

    unit: int
    pdu: _pdu.Pdu

    mode: ClassVar[str] = "ascii"

    def __post_init__(self) -> None:
        _check_unit(self.unit, MAX_SERIAL_UNIT, "ASCII")
        _check_pdu(self.pdu, "AsciiFrame")

    def encode(self) -> bytes:
        """The frame as ASCII bytes: ``b":" + HEX(unit + PDU + LRC) + b"\\r\\n"``."""
        body = bytes([self.unit]) + self.pdu.encode()
        return b":" + (body + bytes([lrc(body)])).hex().upper().encode("ascii") + b"\r\n"

    @classmethod
    def decode(cls, data: bytes | str, role: str = "request") -> AsciiFrame:
        """Check and decode one complete ASCII frame (the ASCII characters, CR LF included).

        Text (``str``) is accepted too.  Checks, in order: length (at most 513 characters), the ':'
        start, the CR LF end, hex digits, an even number of them, at least 3 bytes (unit, function code,
        LRC), the LRC, the unit address (0..247), then the PDU.  Offsets in messages are character
        positions in the frame, with the byte index of the decoded bytes where it helps.
        """
        if isinstance(data, str):
            try:
                data = data.encode("ascii")
            except UnicodeEncodeError as exc:
                raise AsciiFormatError(
                    f"ASCII frame holds the non-ASCII character {data[exc.start]!r} at char {exc.start}; "
                    f"expected ':' then hex digits 0-9 A-F then CR LF"
                ) from None
        data = _as_bytes(data, "AsciiFrame.decode")
        role = _pdu._check_role(role)
        n = len(data)
        if n == 0:
            raise FrameLengthError("ASCII frame is empty; expected ':' + hex digits + CR LF (9..513 chars)")
        if n > ASCII_MAX_FRAME:
            raise FrameLengthError(
                f"ASCII frame too long: {n} chars; expected at most {ASCII_MAX_FRAME} "
                f"(':' + 2 x 255 hex digits + CR LF)"
            )
        if data[0] != 0x3A:
            raise AsciiFormatError(
                f"ASCII frame must start with ':' (0x3A) at char 0, found {_describe_char(data[0])}"
            )
        if not data.endswith(b"\r\n"):
            found = _hex(data[-2:]) if n >= 2 else _hex(data[-1:])
            raise AsciiFormatError(
                f"ASCII frame must end with CR LF (0D 0A) at {_char_span(max(n - 2, 0), n - 1)}, "
                f"found {found}"
            )
        digits = data[1:-2]
        for i, ch in enumerate(digits):
            if ch not in _HEX_DIGITS:
                raise AsciiFormatError(
                    f"ASCII frame: {_describe_char(ch)} at char {i + 1} is not a hex digit; between ':' "
                    f"and CR LF only 0-9 and A-F are allowed"
                )
        if len(digits) % 2:
            raise AsciiFormatError(
                f"ASCII frame has an odd number of hex digits ({len(digits)}, chars 1-{len(digits)}): each "
                f"byte is written as two digits, so the count must be even"
            )
        raw = bytes.fromhex(digits.decode("ascii"))
        if len(raw) < 3:
            raise FrameLengthError(
                f"ASCII frame too short: {len(raw)} byte{'s' if len(raw) != 1 else ''} "
                f"({len(digits)} hex digits); expected at least 3 (unit, function code, LRC), 9 chars "
                f"in all"
            )
        body, carried = raw[:-1], raw[-1]
        computed = lrc(body)
        if carried != computed:
            m = len(raw)
            raise LrcError(
                f"LRC mismatch: frame carries 0x{carried:02X} (chars {2 * m - 1}-{2 * m}), computed "
                f"0x{computed:02X} over {_span(0, m - 2)} of the decoded bytes ({_hex(body)})",
                received=carried,
                computed=computed,
            )
        return _received(cls, raw[0], _decode_pdu(raw[1:-1], role, 1, ascii_chars=True))


@dataclass(frozen=True)
class TcpFrame:
    """A Modbus/TCP frame: the 7-byte MBAP header, then the PDU.  No checksum: TCP already has one.

    Layout (``01 18 00 00 00 06 01 03 00 00 00 01``, transaction 280 reads one register)::

        offset  size  field                    example   note
        0-1     2     transaction identifier   01 18     chosen by the client, echoed by the server
        2-3     2     protocol identifier      00 00     always 0 for Modbus
        4-5     2     length                   00 06     bytes that follow: unit (1) + PDU
        6       1     unit identifier          01        a device behind a gateway; often 1 or 255
        7..     n-7   PDU                      03 00 00 00 01

    Every MBAP field is big-endian (high byte first), unlike the RTU CRC.  The length is 2..254, so a
    frame has 8..260 bytes.  The unit identifier is any of 0..255.
    """

    transaction_id: int
    unit: int
    pdu: _pdu.Pdu
    protocol_id: int = 0

    mode: ClassVar[str] = "tcp"

    def __post_init__(self) -> None:
        tid = self.transaction_id
        if (type(tid) is int and 0 <= tid <= 0xFFFF and self.protocol_id == 0 and type(self.unit) is int
                and 0 <= self.unit <= 255 and isinstance(self.pdu, _pdu.Pdu)):
            return  # the usual case, checked in one go; the checks below name what is wrong
        if isinstance(tid, bool) or not isinstance(tid, int) or not 0 <= tid <= 0xFFFF:
            raise MbapError(f"transaction_id {shown(tid)} does not fit the MBAP's two bytes: "
                            "expected 0..65535")
        if self.protocol_id != 0:
            raise MbapError(f"protocol_id {self.protocol_id!r}: the MBAP protocol identifier of Modbus is 0")
        _check_unit(self.unit, 255, "TCP")
        _check_pdu(self.pdu, "TcpFrame")

    def encode(self) -> bytes:
        """MBAP header (big-endian fields) followed by the PDU."""
        body = self.pdu.encode()
        return MBAP.pack(self.transaction_id, self.protocol_id, 1 + len(body), self.unit) + body

    @classmethod
    def decode(cls, data: bytes, role: str = "request") -> TcpFrame:
        """Check and decode one complete Modbus/TCP frame.

        Checks, in order: length (8..260 bytes), protocol identifier (0), the length field (2..254 and
        equal to the bytes that follow it), then the PDU.  Raises :class:`FrameLengthError`,
        :class:`MbapError` or a :class:`PduError` subclass.
        """
        data = _as_bytes(data, "TcpFrame.decode")
        role = _pdu._check_role(role)
        n = len(data)
        if n < MBAP_HEADER_SIZE + 1:
            raise FrameLengthError(
                f"TCP frame too short: {n} byte{'s' if n != 1 else ''}; expected at least 8 "
                f"(the MBAP header is bytes 0-6, the function code byte 7)"
            )
        if n > TCP_MAX_FRAME:
            raise FrameLengthError(
                f"TCP frame too long: {n} bytes; expected at most {TCP_MAX_FRAME} "
                f"(MBAP header 7 + PDU at most {_pdu.MAX_PDU_SIZE})"
            )
        protocol = int.from_bytes(data[2:4], "big")
        if protocol != 0:
            raise MbapError(
                f"MBAP protocol identifier at bytes 2-3 is {protocol} (0x{protocol:04X}, {_hex(data[2:4])}); "
                f"expected 0 (00 00) for Modbus"
            )
        length = int.from_bytes(data[4:6], "big")
        if not MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH:
            raise MbapError(
                f"MBAP length at bytes 4-5 is {length} ({_hex(data[4:6])}); expected 2..254 "
                f"(unit identifier + a PDU of 1..{_pdu.MAX_PDU_SIZE} bytes)"
            )
        if length != n - 6:
            raise MbapError(
                f"MBAP length at bytes 4-5 is {length} ({_hex(data[4:6])}) but {n - 6} bytes follow it "
                f"({_span(6, n - 1)}); expected {n - 6} = unit identifier (1) + PDU ({n - 7}), big-endian "
                f"{_hex((n - 6).to_bytes(2, 'big'))}"
            )
        return cls(int.from_bytes(data[0:2], "big"), data[6], _decode_pdu(data[7:], role, 7))


Frame = RtuFrame | AsciiFrame | TcpFrame
"""Any of the three frame types."""

_FRAME_CLASSES: dict[str, type] = {"rtu": RtuFrame, "ascii": AsciiFrame, "tcp": TcpFrame}
_HEX_DIGITS = frozenset(b"0123456789ABCDEFabcdef")


def _describe_char(ch: int) -> str:
    """How to name one received byte in a message: 0x41 'A', 0x0D (CR)."""
    names = {0x0D: "CR", 0x0A: "LF", 0x20: "space", 0x3A: "':'"}
    if ch in names:
        return f"0x{ch:02X} ({names[ch]})"
    if 0x21 <= ch < 0x7F:
        return f"0x{ch:02X} '{chr(ch)}'"
    return f"0x{ch:02X}"


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


_TOKEN = re.compile(r"[^\s,;\-]+")


def parse_hex(text: str | bytes) -> bytes:
    """Turn hex as people write it into bytes.

    Accepted: ``"01 03 00 00"``, ``"01030000"``, ``"0x01,0x03"``, ``"01-03"``, ``"0x1, 0x3"`` (a lone
    digit is a byte only when written ``0x``: in ``"01 3"`` it is more likely a typing slip), any mix
    of upper and lower case; separators are spaces, tabs, newlines, commas,
    semicolons and dashes.  Text that starts with ``:`` is an ASCII frame and is returned as its ASCII
    characters, with CR LF appended when missing (a typed ``\\r\\n`` is understood as CR LF too).

    >>> parse_hex("01 03 00 00 00 01 84 0A")
    b'\\x01\\x03\\x00\\x00\\x00\\x01\\x84\\n'

    A character that is not a hex digit raises :class:`AsciiFormatError` naming its position.
    """
    if isinstance(text, (bytes, bytearray, memoryview)):
        try:
            text = bytes(text).decode("ascii")
        except UnicodeDecodeError as exc:
            raise AsciiFormatError(
                f"hex text holds the non-ASCII byte 0x{bytes(text)[exc.start]:02X} at position {exc.start}"
            ) from None
    if not isinstance(text, str):
        raise AsciiFormatError(
            f"parse_hex expects text such as '01 03 00 00 00 01', got {type(text).__name__}"
        )
    stripped = text.strip()
    if stripped.startswith(":"):
        frame = stripped
        for typed in ("\\r\\n", "\\n", "\\r"):
            if frame.endswith(typed):
                frame = frame[: -len(typed)]
                break
        frame = frame.rstrip("\r\n")
        try:
            raw = frame.encode("ascii")
        except UnicodeEncodeError as exc:
            pos = text.index(stripped) + exc.start
            raise AsciiFormatError(
                f"ASCII frame holds the non-ASCII character {frame[exc.start]!r} at position {pos}; "
                f"expected ':' then hex digits then CR LF"
            ) from None
        return raw + b"\r\n"
    out = bytearray()
    for match in _TOKEN.finditer(text):
        token, start = match.group(), match.start()
        digits_at = start
        prefixed = token[:2] in ("0x", "0X")
        if prefixed:
            token, digits_at = token[2:], start + 2
            if not token:
                raise AsciiFormatError(f"'0x' at position {start} is not followed by hex digits in {text!r}")
        for i, ch in enumerate(token):
            if ch not in "0123456789abcdefABCDEF":
                raise AsciiFormatError(
                    f"not a hex digit: {ch!r} at position {digits_at + i} in {text!r}; expected 0-9 or A-F "
                    f"(bytes separated by spaces, commas or dashes, optionally written 0x..)"
                )
        if len(token) == 1 and prefixed:
            token = "0" + token
        elif len(token) % 2:
            raise AsciiFormatError(
                f"odd number of hex digits ({len(token)}) in {token!r} at position {digits_at} of {text!r}; "
                f"each byte is two digits"
            )
        out += bytes.fromhex(token)
    return bytes(out)


# --- stream splitters -------------------------------------------------------------------------------
class _Splitter:
    """Common state of the splitters: the buffer and the count of dropped bytes."""

    mode: ClassVar[str] = ""

    def __init__(self) -> None:
        self._buffer = bytearray()
        self.discarded = 0
        """Junk bytes dropped so far (bytes that could not start or belong to a frame)."""
        self.error = ""
        """Why the stream cannot be framed any further ('' while it can; only a strict splitter stops)."""

    @property
    def pending(self) -> bytes:
        """The bytes received but not yet part of a complete frame (``len(s.pending)`` counts them)."""
        return bytes(self._buffer)

    def reset(self) -> None:
        """Forget buffered bytes and the discarded count (a new connection, a reopened port)."""
        self._buffer.clear()
        self.discarded = 0
        self.error = ""

    def _drop(self, count: int) -> None:
        del self._buffer[:count]
        self.discarded += count

    def feed(self, chunk: bytes) -> list[bytes]:
        """Add received bytes; return the complete raw frames they finish (possibly none)."""
        self._buffer += _as_bytes(chunk, f"{type(self).__name__}.feed")
        return self._cut()

    def flush(self) -> list[bytes]:
        """The stream has ended (or the line gone silent): nothing will complete the pending bytes.

        Returns any frames that can still be cut; what remains is counted as discarded.
        """
        frames = self._cut()
        self._drop(len(self._buffer))
        return frames

    def _cut(self) -> list[bytes]:  # pragma: no cover - overridden
        raise NotImplementedError


class _Scan:
    """What :meth:`RtuSplitter._complete_frame_after` has worked out while one start waits for bytes."""

    __slots__ = ("start", "known", "seen", "ends")

    def __init__(self, start: int) -> None:
        self.start = start
        self.known = start + 1  # offsets before this have a known expected length
        self.seen = start       # candidates whose frame ends at or before this were CRC-checked
        self.ends: dict[int, list[int]] = {}  # end of a candidate frame -> the offsets it starts at


@lru_cache(maxsize=2)
def _function_classes(role: str) -> dict[int, type[_pdu.Pdu]]:
    """The class of each function-code byte that can start a PDU of ``role`` (a response: also 0x80-0xFF,
    the exception responses)."""
    classes: dict[int, type[_pdu.Pdu]] = {}
    for code in range(256):
        try:
            classes[code] = _pdu.pdu_class(code, role)
        except ModbusError:
            continue
    return classes


@lru_cache(maxsize=2)
def _start_pattern(role: str) -> re.Pattern[bytes]:
    """Two bytes that can begin an RTU frame of ``role``: a unit 0..247, then a known function code."""
    codes = b"".join(re.escape(bytes([code])) for code in sorted(_function_classes(role)))
    return re.compile(b"[\\x00-\\xf7][" + codes + b"]", re.DOTALL)


_OPEN = -2  # RtuSplitter._frame_length: a frame whose bytes do not say its length
#: The longest frame with a function code this library does not know that an open-ended splitter looks
#: for: every junk byte may look like the start of one, and each costs a CRC over this many bytes.
UNKNOWN_FUNCTION_MAX_FRAME = 64


class RtuSplitter(_Splitter):
    """Cut RTU frames out of a byte stream by their expected length.

    A real RTU receiver ends a frame after 3.5 character times of silence.  Without timing (a pipe, a
    recording, a TCP tunnel) the length has to come from the content: the function code, and for some
    functions a byte count, say how long the PDU is (:func:`modbus_edu.pdu.pdu_length`).  That depends on
    the direction, hence ``role``: ``"request"`` for what a slave hears, ``"response"`` for a master.

    Resynchronising: when the first buffered byte cannot start a frame (a unit address above 247, an
    unknown function code, an impossible length) or the CRC at the expected length is wrong, the splitter
    drops that one byte, counts it in :attr:`discarded`, and tries again from the next byte.  Junk can
    also look like the start of a long frame (``01 10 ...`` announcing an FC16 request) and make the
    splitter wait for bytes that never come; so while it waits, it also looks further on, and a complete
    frame with a correct CRC there wins: the bytes before it are dropped as junk.  (A correct CRC by
    chance inside a real frame's data is about 1 in 65536 per candidate: the price of cutting frames
    without timing.)  A valid frame behind junk is therefore found as soon as it is complete.  ``feed``
    never raises for any bytes.
    Frames are returned as cut, CRC verified; decode them with :meth:`RtuFrame.decode`.

    :meth:`flush` is the silence: it tells the splitter that the pending bytes will not be continued, so
    a frame that junk made look longer than it is can still be found.

    Some frames do not say their length: FC 8 Return Query Data echoes data of any length
    (:data:`~modbus_edu.pdu.OPEN_LENGTH`).  Such a frame ends at the first byte where the CRC of what
    precedes checks out, worked out byte by byte as they come (linear), or at a silence.  With
    ``open_ended=True`` (a server on a socket, where every byte is meant as Modbus) the same goes for
    a function code this library does not implement and for a byte count that disagrees with its
    quantity (whether the data that follows has as many bytes as that count says, or as the quantity
    says, or neither): the frame is cut, and the slave answers it with exception 01 or 03 as the
    specification says, instead of the bytes being skipped as junk.
    """

    mode: ClassVar[str] = "rtu"

    def __init__(self, role: str = "request", open_ended: bool = False) -> None:
        super().__init__()
        self.role = _pdu._check_role(role)
        self.open_ended = bool(open_ended)
        self._classes = _function_classes(self.role)
        self._next_start = _start_pattern(self.role)
        self._scan: _Scan | None = None
        self._open: list[int] | None = None  # a frame of unknown length: [bytes under the CRC, CRC so far]

    def _drop(self, count: int) -> None:
        super()._drop(count)
        self._scan = None
        self._open = None

    def reset(self) -> None:
        super().reset()
        self._scan = None
        self._open = None

    def _open_end(self) -> int | None:
        """The length of the frame of unknown length at the start of the buffer: where the CRC of the
        bytes before two bytes equals those two bytes; None while no such place has come; -1 when none
        came within the longest such frame (the start was junk)."""
        buf = self._buffer
        state = self._open
        if state is None:
            state = self._open = [0, 0xFFFF]
        k, register = state
        table = CRC_TABLE
        longest = RTU_MAX_FRAME if buf[1] in self._classes else UNKNOWN_FUNCTION_MAX_FRAME
        limit = min(len(buf), longest) - 2
        while k < limit:
            register = (register >> 8) ^ table[(register ^ buf[k]) & 0xFF]
            k += 1
            if k >= 2 and register == buf[k] | buf[k + 1] << 8:
                self._open = None
                return k + 2
        if len(buf) >= longest:
            return -1  # no CRC checked out within the longest such frame: this start was junk
        state[0], state[1] = k, register
        return None

    def _frame_length(self, start: int) -> int | None:
        """Expected frame length at ``start``: an int, None (need more bytes) or -1 (cannot be a frame)."""
        buf = self._buffer
        if buf[start] > MAX_SERIAL_UNIT:
            return -1  # a reserved address: too rare to take for the start of a frame in a byte stream
        if len(buf) - start < 2:
            return None
        cls = self._classes.get(buf[start + 1])
        if cls is None:  # a function this library does not implement (1..127; above are exceptions)
            return _OPEN if self.open_ended and 0 < buf[start + 1] < 0x80 else -1
        # the function's class reads the length from the first bytes it needs (FC 23: byte count at 9; an
        # FC 43 response: its object headers) and tests the byte count before the CRC is computed
        head = bytes(buf[start + 1 : start + 1 + cls.length_prefix()])
        try:
            size = cls.length_from(head)
        except ModbusError:
            return -1
        if size is None:
            return None
        if size == _pdu.OPEN_LENGTH:
            return _OPEN
        if not 1 <= size <= _pdu.MAX_PDU_SIZE:
            return -1
        if not cls.plausible(head):
            # a byte count at odds with its quantity: junk in a stream, but on a socket (open_ended) a
            # request the slave answers with 03, and its byte count cannot be trusted to say where it ends
            return _OPEN if self.open_ended else -1
        return 1 + size + 2

    def _cut(self, final: bool = False) -> list[bytes]:
        frames: list[bytes] = []
        buf = self._buffer
        exceptions = self.role == "response"
        while buf:
            if exceptions and len(buf) >= 5 and buf[1] > 0x80 and buf[0] <= MAX_SERIAL_UNIT:
                # an exception response (5 bytes): half the byte values start one, so check it here,
                # with the CRC of its 3 bytes worked out inline
                table = CRC_TABLE
                register = (0xFFFF >> 8) ^ table[(0xFFFF ^ buf[0]) & 0xFF]
                register = (register >> 8) ^ table[(register ^ buf[1]) & 0xFF]
                register = (register >> 8) ^ table[(register ^ buf[2]) & 0xFF]
                if register == buf[3] | buf[4] << 8:
                    frames.append(bytes(buf[:5]))
                    del buf[:5]
                    self._scan = None
                else:
                    self._drop(1)
                continue
            total = self._frame_length(0)
            if total == _OPEN:
                end = self._open_end()
                if end is None and not final:
                    break  # its end has not come yet
                if end is None or end < 0:
                    self._drop(1)  # no CRC within a frame's length: this start was not a frame
                    continue
                frames.append(bytes(buf[:end]))
                del buf[:end]
                self._scan = None
                continue
            if total is None or (total > 0 and total > len(buf)):
                later = self._complete_frame_after(0)
                if later is not None:  # what we wait for is junk: a whole frame stands behind it
                    self._drop(later)
                    continue
                if not final:
                    break
                self._drop(1)  # no more bytes will come: this start cannot be completed
                continue
            if total < 0:
                following = self._next_start.search(buf, 1)  # skip what cannot start a frame, in C
                self._drop(following.start() if following else max(1, len(buf) - 1))
                continue
            if crc16(bytes(buf[: total - 2])) != int.from_bytes(buf[total - 2 : total], "little"):
                self._drop(1)
                continue
            frames.append(bytes(buf[:total]))
            del buf[:total]
            self._scan = None
        return frames

    def _complete_frame_after(self, start: int) -> int | None:
        """The first offset after ``start`` where a complete frame with a correct CRC is buffered.

        Called while the frame at ``start`` waits for bytes.  The buffer then only grows, so the work is
        kept in :attr:`_scan`: each offset's expected length is worked out once, and each candidate's CRC
        is checked once, when its last byte arrives.  Fed byte by byte, the splitter stays linear.
        """
        buf = self._buffer
        size = len(buf)
        scan = self._scan
        if scan is None or scan.start != start:
            scan = self._scan = _Scan(start)
        found: list[int] = []

        def check(offset: int, end: int) -> None:
            if crc16(bytes(buf[offset:end - 2])) == int.from_bytes(buf[end - 2:end], "little"):
                found.append(offset)

        offset = scan.known
        while offset < size - 3:
            total = self._frame_length(offset)
            if total is None:
                break  # this offset needs more bytes to say its length: look again next time
            if total > 0:
                end = offset + total
                if end <= scan.seen:
                    check(offset, end)  # its last byte came before this offset was looked at
                else:
                    scan.ends.setdefault(end, []).append(offset)
            offset += 1
        scan.known = offset
        for end in range(scan.seen + 1, size + 1):
            for candidate in scan.ends.pop(end, ()):
                check(candidate, end)
        scan.seen = size
        return min(found) if found else None

    def flush(self) -> list[bytes]:
        """End of frame by silence: cut what can be cut from the pending bytes, discard the rest."""
        return self._cut(final=True)


class AsciiSplitter(_Splitter):
    """Cut ASCII frames out of a character stream: from ``:`` to CR LF.

    Anything before a ``:`` is junk and dropped; a new ``:`` before the CR LF restarts the frame (the
    spec's rule: the start character always begins a new message), and the half frame is dropped; a
    frame that reaches 513 characters without its CR LF is dropped.  Dropped bytes are counted in
    :attr:`discarded`.

    By default frames are returned **as cut**, without looking inside: decode them with
    :meth:`AsciiFrame.decode` to check hex digits and the LRC and get a teaching error.  With
    ``strict=True`` the splitter checks hex digits and the LRC itself and drops (and counts) frames
    that fail.  ``feed`` never raises for any bytes.
    """

    mode: ClassVar[str] = "ascii"

    def __init__(self, strict: bool = False) -> None:
        super().__init__()
        self.strict = strict

    def _cut(self) -> list[bytes]:
        frames: list[bytes] = []
        buf = self._buffer
        while buf:
            start = buf.find(b":")
            if start < 0:
                self._drop(len(buf))
                break
            if start > 0:
                self._drop(start)
            # look for the end only up to the next ':' (and a frame's size): linear on any input
            restart = buf.find(b":", 1, ASCII_MAX_FRAME + 1)
            end = buf.find(b"\r\n", 0, restart + 1 if restart > 0 else ASCII_MAX_FRAME + 1)
            if restart > 0 and (end < 0 or restart < end):
                self._drop(restart)  # a new ':' begins a new frame
                continue
            if end < 0:
                if len(buf) >= ASCII_MAX_FRAME:  # cannot end within 513 characters: junk up to the next ':'
                    following = buf.find(b":", 1)
                    self._drop(following if following > 0 else len(buf))
                    continue
                break
            size = end + 2
            if size > ASCII_MAX_FRAME:
                self._drop(size)
                continue
            frame = bytes(buf[:size])
            if self.strict and not _ascii_frame_checks(frame):
                self._drop(size)
                continue
            frames.append(frame)
            del buf[:size]
        return frames


def _ascii_frame_checks(frame: bytes) -> bool:
    """True when an ASCII frame's digits are hex, even in number, at least 3 bytes, and the LRC agrees."""
    digits = frame[1:-2]
    if len(digits) < 6 or len(digits) % 2 or any(ch not in _HEX_DIGITS for ch in digits):
        return False
    raw = bytes.fromhex(digits.decode("ascii"))
    return lrc(raw[:-1]) == raw[-1]


class TcpSplitter(_Splitter):
    """Cut Modbus/TCP frames out of a TCP byte stream by the MBAP length field.

    TCP delivers a stream, not messages: one ``recv`` may hold half a frame or three frames.  The MBAP
    length (bytes 4-5) says how many bytes follow it, so a frame is 6 + length bytes.

    A header with a protocol identifier other than 0 or a length outside 2..254 cannot start a frame.
    This splitter then drops one byte, counts it in :attr:`discarded` and looks for a valid header at the
    next byte, which lets it read captures and recordings with junk in them.  A real Modbus/TCP server
    does not guess like this: on a stream it cannot frame it closes the connection, because after one
    wrong length it can no longer know where any later frame starts.  ``feed`` never raises for any bytes.

    ``strict=True`` is that server's splitter: at a header it cannot frame it stops, and :attr:`error`
    says why, with the header's bytes (the frames before it are still returned); it judges a header once all
    seven bytes are in.
    """

    mode: ClassVar[str] = "tcp"

    def __init__(self, strict: bool = False) -> None:
        super().__init__()
        self.strict = strict

    def _cut(self) -> list[bytes]:
        if self.strict:
            return self._cut_strict()
        frames: list[bytes] = []
        buf = self._buffer
        while len(buf) >= 3:
            if buf[2] != 0 or (len(buf) >= 4 and buf[3] != 0):
                self._drop(1)
                continue
            if len(buf) < 6:
                break
            length = int.from_bytes(buf[4:6], "big")
            if not MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH:
                self._drop(1)
                continue
            if len(buf) < 6 + length:
                break
            frames.append(bytes(buf[: 6 + length]))
            del buf[: 6 + length]
        return frames

    def _cut_strict(self) -> list[bytes]:
        frames: list[bytes] = []
        buf = self._buffer
        while not self.error and len(buf) >= MBAP_HEADER_SIZE:
            _tid, protocol, length, _unit = MBAP.unpack_from(buf, 0)
            if protocol != 0:
                why = f"MBAP protocol identifier is {protocol}, Modbus/TCP requires 0"
            elif not MIN_MBAP_LENGTH <= length <= MAX_MBAP_LENGTH:
                why = (f"MBAP length field is {length}, must be {MIN_MBAP_LENGTH}..{MAX_MBAP_LENGTH} "
                       "(unit id + PDU of at most 253 bytes)")
            elif len(buf) < 6 + length:
                break
            else:
                frames.append(bytes(buf[: 6 + length]))
                del buf[: 6 + length]
                continue
            self.error = f"{why} (header bytes {bytes(buf[:MBAP_HEADER_SIZE]).hex(' ')})"
        return frames


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
