"""Modbus ASCII: :class:`AsciiFrame` (``:``, the bytes as uppercase hex, the LRC, CR LF) and
:class:`AsciiSplitter`, which cuts frames at ``:`` and CR LF.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .. import pdu as _pdu
from ..codes import _hex
from ..crc import lrc
from ..errors import AsciiFormatError, FrameLengthError, LrcError
from .base import (
    _HEX_DIGITS,
    MAX_SERIAL_UNIT,
    _as_bytes,
    _char_span,
    _check_pdu,
    _check_unit,
    _decode_pdu,
    _describe_char,
    _received,
    _span,
    _Splitter,
)

__all__ = ["ASCII_MAX_FRAME", "AsciiFrame", "AsciiSplitter"]

ASCII_MAX_FRAME = 513
"""Largest ASCII frame in characters: ':' (1) + 2 hex digits for each of unit, 253 PDU bytes and the LRC
(2 x 255 = 510) + CR LF (2)."""


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
