"""What the three modes share: the mode names, the unit address rules, the checks of bytes, units and
PDUs, the PDU decode with offsets counted from the frame's start, :func:`parse_hex`, and the base of the
stream splitters.
"""

from __future__ import annotations

import re
import warnings
from typing import Any, ClassVar

from .. import pdu as _pdu
from ..codes import MBAP_HEADER_SIZE, ROLES
from ..errors import (
    AsciiFormatError,
    ConfigError,
    FrameError,
    PduError,
    ReservedUnitWarning,
    UnitError,
    shown,
)

__all__ = ["MODES", "ROLES", "MBAP_HEADER_SIZE", "BROADCAST", "MAX_SERIAL_UNIT", "parse_hex"]

MODES: tuple[str, ...] = ("rtu", "ascii", "tcp")
"""The three transmission modes, by the names used everywhere in the library."""

BROADCAST = 0
"""Serial unit address 0: every slave acts on the request (writes only) and none answers."""
MAX_SERIAL_UNIT = 247
"""Highest slave address on a serial line; 248..255 are reserved."""

_UNIT_BYTES = tuple(bytes([unit]) for unit in range(256))  # one-byte unit fields, built once


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
        raise FrameError(f"{what} expects bytes, got the number {shown(data)}; "
                         f"bytes([{shown(data)}]) is one byte")
    try:
        return bytes(data)  # type: ignore[call-overload]
    except (TypeError, ValueError):
        raise FrameError(f"{what} expects bytes (values 0..255), got {type(data).__name__}") from None


def _check_mode(mode: object) -> str:
    if isinstance(mode, str) and mode.lower() in MODES:
        return mode.lower()
    raise ConfigError(f"mode must be one of {', '.join(MODES)}, got {shown(mode)}")


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


_HEX_DIGITS = frozenset(b"0123456789ABCDEFabcdef")


def _describe_char(ch: int) -> str:
    """How to name one received byte in a message: 0x41 'A', 0x0D (CR)."""
    names = {0x0D: "CR", 0x0A: "LF", 0x20: "space", 0x3A: "':'"}
    if ch in names:
        return f"0x{ch:02X} ({names[ch]})"
    if 0x21 <= ch < 0x7F:
        return f"0x{ch:02X} '{chr(ch)}'"
    return f"0x{ch:02X}"


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
