"""Modbus RTU: :class:`RtuFrame` (unit, PDU, CRC-16 low byte first) and :class:`RtuSplitter`, which finds
where each frame ends in a byte stream from the function code and the length fields.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from typing import ClassVar

from .. import pdu as _pdu
from ..codes import _hex
from ..crc import CRC_TABLE, crc16
from ..errors import CrcError, FrameLengthError, ModbusError
from .base import (
    _UNIT_BYTES,
    MAX_SERIAL_UNIT,
    _as_bytes,
    _check_pdu,
    _check_unit,
    _decode_pdu,
    _received,
    _span,
    _Splitter,
)

__all__ = ["RTU_MAX_FRAME", "RtuFrame", "RtuSplitter"]

RTU_MAX_FRAME = 256
"""Largest RTU frame: unit (1) + PDU (at most 253) + CRC (2)."""


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
