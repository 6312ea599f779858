"""Modbus/TCP: :class:`TcpFrame` (the MBAP header, then the PDU) and :class:`TcpSplitter`, which cuts frames
by the MBAP length field.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .. import pdu as _pdu
from ..codes import MAX_MBAP_LENGTH, MBAP, MBAP_HEADER_SIZE, MIN_MBAP_LENGTH, _hex
from ..errors import FrameLengthError, MbapError, shown
from .base import _as_bytes, _check_pdu, _check_unit, _decode_pdu, _span, _Splitter

__all__ = ["TCP_MAX_FRAME", "TcpFrame", "TcpSplitter", "is_one_frame"]

TCP_MAX_FRAME = 260
"""Largest Modbus/TCP frame: MBAP header (7) + PDU (at most 253)."""


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
            raise MbapError(f"protocol_id {shown(self.protocol_id)}: the MBAP protocol identifier "
                            f"of Modbus is 0")
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


def is_one_frame(data: bytes) -> bool:
    """Whether ``data`` is exactly one Modbus/TCP frame by its MBAP header: 8 to 260 bytes, protocol id 0
    and a length field equal to the bytes after it (what :meth:`TcpFrame.decode` checks before the PDU).
    The fast paths of the slave and the server ask it before they look at a request's bytes."""
    n = len(data)
    return 8 <= n <= TCP_MAX_FRAME and not data[2] and not data[3] and (data[4] << 8 | data[5]) == n - 6


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
