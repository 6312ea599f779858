"""Field-by-field dissection of any Modbus frame.

``explain(data)`` answers the question a learner asks of every frame: *which byte is what?*  It returns a
:class:`Dissection` whose rows cover every byte (in ASCII mode every character) of the frame, in order,
each with its offset, its raw bytes, the field's name, its value and what it means::

    >>> print(explain(bytes.fromhex("010300000001840A")))
    RTU request: unit 1, Read Holding Registers, address 0, count 1
    offset  bytes  field                 value   meaning
    0       01     unit (slave address)  1       the frame is to slave 1
    1       03     function code         3       Read Holding Registers (request)
    2       00 00  starting address      0       0-based register address
    4       00 01  quantity              1       number of registers to read (1-125)
    6       84 0A  CRC                   0x0A84  CRC-16 over bytes 0-5, sent low byte first (84 0A): correct

The dissection goes as far as the bytes allow.  A frame with a wrong CRC still gets all its rows (the
CRC row says what the CRC should have been); a frame that breaks a rule records the first error the
strict decoder (:func:`modbus_edu.framing.decode_frame`) raises in :attr:`Dissection.error`, instead of
raising it.  ``explain(..., strict=True)`` raises that error.

The same dissection feeds the notebooks (``_repr_html_``: a table), the command line (``to_text`` and
``to_dict``) and the widgets.  A PDU object shows as its table in a notebook too: this module gives
:class:`~modbus_edu.pdu.Pdu` its ``_repr_html_`` when it is imported (the PDU classes import nothing
from here).

A bare PDU (function code first, no unit and no check) gets the same table from ``explain_pdu``: give
it a PDU object or its bytes.  Its offsets count from the function code::

    >>> print(explain_pdu(bytes.fromhex("03 06 02 2B 00 00 00 64")))
    PDU response: Read Holding Registers, registers [555, 0, 100]
    offset  bytes  field          value  meaning
    0       03     function code  3      Read Holding Registers (response)
    1       06     byte count     6      2 bytes per register
    2       02 2B  register 0     555    0x022B = 555 (high byte first)
    4       00 00  register 1     0      0x0000 = 0 (high byte first)
    6       00 64  register 2     100    0x0064 = 100 (high byte first)
"""

from __future__ import annotations

import dataclasses
import html
from dataclasses import dataclass, field
from typing import Any

from . import pdu as _pdu
from .codes import _hex
from .crc import crc16, lrc
from .errors import ConfigError, FrameError, ModbusError
from .framing import (
    MAX_SERIAL_UNIT,
    ROLES,
    Frame,
    TcpFrame,
    decode_frame,
    detect_mode,
    detect_mode_why,
    parse_hex,
)
from .framing.base import _HEX_DIGITS, _as_bytes, _check_mode

__all__ = ["Row", "Dissection", "explain", "explain_pdu"]

_MODE_NAMES = {"rtu": "RTU", "ascii": "ASCII", "tcp": "TCP", "pdu": "PDU"}


@dataclass(frozen=True)
class Row:
    """One field of a frame.

    ``offset`` is where the field starts in the frame: a byte offset for RTU and TCP, a character offset
    for ASCII.  ``raw`` is what is on the wire there (in ASCII: the hex characters, e.g. ``b"05"``).
    ``ok`` is False for a field that breaks a rule (a wrong CRC, a reserved unit, undecodable bytes).
    """

    offset: int
    raw: bytes
    field: str
    value: Any
    meaning: str
    ok: bool = True


@dataclass
class Dissection:
    """The result of :func:`explain`: rows, the decoded frame (or None) and the first error (or None).

    ``mode`` is the mode used (given or detected), ``role`` the role used (given, or the one that
    decodes when none was given; None when the bytes could not even be read).  A dissection of a bare
    PDU (:func:`explain_pdu`) has the mode ``"pdu"``, no frame, and the decoded PDU in ``pdu``.
    """

    data: bytes
    mode: str
    role: str | None
    rows: list[Row] = field(default_factory=list)
    frame: Frame | None = None
    error: ModbusError | None = None
    pdu: _pdu.Pdu | None = None
    detected: str = ""
    """Why the mode was chosen, when it was detected (:func:`~modbus_edu.framing.detect_mode_why`);
    empty when the caller gave the mode."""

    @property
    def ok(self) -> bool:
        """True when the frame decoded without error."""
        return self.error is None

    def __repr__(self) -> str:
        return f"<Dissection {self.summary}>"

    @property
    def summary(self) -> str:
        """One line: ``RTU request: unit 1, Read Holding Registers, address 0, count 1``."""
        mode = _MODE_NAMES.get(self.mode, self.mode.upper())
        if self.pdu is not None and self.frame is None:
            return f"{mode} {self.role}: {_pdu_summary(self.pdu)}"
        if self.frame is not None:
            head = f"{mode} {self.role}: "
            if isinstance(self.frame, TcpFrame):
                head += f"transaction {self.frame.transaction_id}, "
            unit = f"unit {self.frame.unit}"
            if self.frame.unit == 0 and not isinstance(self.frame, TcpFrame):
                unit += " (broadcast)"
            return f"{head}{unit}, {_pdu_summary(self.frame.pdu)}"
        what = f"{mode} {self.role}" if self.role else mode if self.mode == "pdu" else f"{mode} frame"
        return f"{what}, not valid: {self.error}"

    # --- views ---------------------------------------------------------------------------------------
    @property
    def _heading(self) -> str:
        """The summary, or for a broken frame a short title (the error is shown below the table)."""
        if self.frame is not None or self.pdu is not None:
            return self.summary
        mode = _MODE_NAMES.get(self.mode, self.mode.upper())
        if self.mode == "pdu" and not self.role:
            return f"{mode}: not valid"
        return f"{mode} {self.role or 'frame'}: not valid"

    def raw_text(self, row: Row) -> str:
        """A row's bytes as shown: hex for RTU and TCP, the characters (with CR, LF) for ASCII."""
        if self.mode == "ascii":
            return _ascii_text(row.raw)
        return _hex(row.raw)

    def to_text(self) -> str:
        """The dissection as an aligned plain-text table, the summary above it and any error below it."""
        header = ("offset", "bytes" if self.mode != "ascii" else "chars", "field", "value", "meaning")
        table = [header] + [
            (str(r.offset), self.raw_text(r), r.field, _value_text(r.value), r.meaning) for r in self.rows
        ]
        widths = [max(len(line[i]) for line in table) for i in range(4)]
        lines = [self._heading]
        for index, line in enumerate(table):
            cells = [line[i].ljust(widths[i]) for i in range(4)] + [line[4]]
            mark = "" if index == 0 or self.rows[index - 1].ok else "  <-- problem"
            lines.append("  ".join(cells).rstrip() + mark)
        if self.error is not None:
            lines.append(f"error ({type(self.error).__name__}): {self.error}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.to_text()

    def _repr_html_(self) -> str:
        """An HTML table for Jupyter: header row, bytes in a monospaced font, problems highlighted."""
        esc = html.escape
        mono = "font-family: monospace; white-space: pre"
        out = [
            '<table class="modbus-edu-dissection" style="border-collapse: collapse">',
            f'<caption style="text-align: left; font-weight: bold">{esc(self._heading)}</caption>',
            "<thead><tr><th>offset</th><th>{}</th><th>field</th><th>value</th><th>meaning</th></tr></thead>"
            .format("chars" if self.mode == "ascii" else "bytes"),
            "<tbody>",
        ]
        for r in self.rows:
            style = "" if r.ok else ' style="background-color: #fdd"'
            out.append(
                f"<tr{style}><td>{r.offset}</td><td style=\"{mono}\">{esc(self.raw_text(r))}</td>"
                f"<td>{esc(r.field)}</td><td style=\"{mono}\">{esc(_value_text(r.value))}</td>"
                f"<td>{esc(r.meaning)}</td></tr>"
            )
        out.append("</tbody>")
        out.append("</table>")
        if self.error is not None:
            out.append(
                f'<p style="color: #a00"><b>{esc(type(self.error).__name__)}</b>: {esc(str(self.error))}</p>'
            )
        return "\n".join(out)

    def to_dict(self) -> dict[str, Any]:
        """A JSON-serialisable dict: mode, role, data, rows (bytes as hex), error, frame, summary.

        A PDU's dissection (mode ``"pdu"``) has ``"pdu"`` (its class, function code and fields) in
        place of the frame's details.
        """
        rows = []
        for r in self.rows:
            item: dict[str, Any] = {
                "offset": r.offset,
                "raw": _hex(r.raw),
                "field": r.field,
                "value": _jsonable(r.value),
                "meaning": r.meaning,
                "ok": r.ok,
            }
            if self.mode == "ascii":
                item["chars"] = _ascii_text(r.raw)
            rows.append(item)
        out = {
            "mode": self.mode,
            "role": self.role,
            "data": _hex(self.data),
            "length": len(self.data),
            "ok": self.ok,
            "summary": self.summary,
            "frame": _frame_dict(self.frame),
            "error": None if self.error is None else str(self.error),
            "error_type": None if self.error is None else type(self.error).__name__,
            "rows": rows,
        }
        if self.mode == "pdu":
            out["pdu"] = None if self.pdu is None else _pdu_dict(self.pdu)
        return out


# --- formatting helpers ----------------------------------------------------------------------------
def _ascii_text(raw: bytes) -> str:
    """ASCII characters as a learner should see them: ``05``, ``:``, ``CR LF``, ``<0x80>``."""
    parts: list[str] = []
    for ch in raw:
        if ch == 0x0D:
            parts.append(" CR")
        elif ch == 0x0A:
            parts.append(" LF")
        elif 0x20 < ch < 0x7F:
            parts.append(chr(ch))
        else:
            parts.append(f" <{ch:02X}>")
    return "".join(parts).strip()


def _value_text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, (list, tuple)):
        return ", ".join(_value_text(v) for v in value)
    if isinstance(value, bool):
        return "ON" if value else "OFF"
    if isinstance(value, int):
        return str(int(value))
    return str(value)


def _jsonable(value: Any) -> Any:
    if value is None or isinstance(value, (bool, str, float)):
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, (bytes, bytearray)):
        return _hex(bytes(value))
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return str(value)


def _frame_dict(frame: Frame | None) -> dict[str, Any] | None:
    if frame is None:
        return None
    out: dict[str, Any] = {"type": type(frame).__name__, "unit": frame.unit}
    if isinstance(frame, TcpFrame):
        out["transaction_id"] = frame.transaction_id
        out["protocol_id"] = frame.protocol_id
    out.update(_pdu_dict(frame.pdu))
    return out


def _pdu_dict(pdu: _pdu.Pdu) -> dict[str, Any]:
    """``{"function_code": 3, "pdu": "ReadHoldingRegistersRequest", "fields": {...}}``."""
    return {
        "function_code": pdu.function_code,
        "pdu": type(pdu).__name__,
        "fields": {f.name: _jsonable(getattr(pdu, f.name)) for f in dataclasses.fields(pdu)},
    }


def _pdu_summary(pdu: _pdu.Pdu) -> str:
    """``Read Holding Registers, address 0, count 1`` (the PDU part of the summary line)."""
    if isinstance(pdu, _pdu.ExceptionResponse):
        return (f"exception response to {_pdu.function_title(pdu.function)}: code {pdu.code:02X}, "
                f"{pdu.meaning}")
    items = getattr(pdu, "_summary_items", lambda: [])()
    parts = [pdu.title] + [f"{name} {_summary_value(value)}" for name, value in items]
    return ", ".join(parts)


def _summary_value(value: Any) -> str:
    if isinstance(value, (list, tuple)):
        shown = ", ".join(str(v) for v in value[:8])
        return f"[{shown}{', ...' if len(value) > 8 else ''}]"
    text = str(value)
    return text if len(text) <= 40 else text[:37] + "..."


# --- the pieces of a message, in byte units --------------------------------------------------------
@dataclass
class _Piece:
    """A field in byte units of the binary message (for ASCII: of the decoded bytes)."""

    start: int
    length: int
    field: str
    value: Any
    meaning: str
    ok: bool = True


def _unit_piece(unit: int, mode: str, role: str | None) -> _Piece:
    if mode == "tcp":
        return _Piece(6, 1, "unit identifier", unit,
                      "the device behind a gateway; a server that is the device itself takes 0xFF "
                      "(recommended) or 0 as 'you' (no broadcast on TCP)")
    if unit == 0:
        meaning = "broadcast: every slave carries out the write, none answers"
        if role == "response":
            meaning += " (so no response can carry address 0)"
        return _Piece(0, 1, "unit (slave address)", unit, meaning, ok=role != "response")
    if unit > MAX_SERIAL_UNIT:
        return _Piece(0, 1, "unit (slave address)", unit,
                      "reserved address (248-255): standard slaves use 1-247, 0 = broadcast; some devices "
                      "answer one (an 'any address' or a configuration address)")
    word = "to" if role == "request" else "from" if role == "response" else "of"
    return _Piece(0, 1, "unit (slave address)", unit, f"the frame is {word} slave {unit}")


def _function_fallback(function: int, role: str | None) -> tuple[str, bool]:
    """The meaning of a function-code byte when the PDU does not decode."""
    if function & 0x80:
        if role == "request":
            return (f"0x{function:02X} has its top bit set: an exception response code, never a request",
                    False)
        title = _pdu.function_title(function & 0x7F)
        return f"0x{function & 0x7F:02X} + 0x80: exception response to {title}", True
    try:
        return f"{_pdu.FunctionCode(function).title} ({role or 'request or response'})", True
    except ValueError:
        return f"function code {function} is not one of 1, 2, 3, 4, 5, 6, 15, 16", False


def _pdu_pieces(data: bytes, role: str | None, base: int) -> list[_Piece]:
    """Pieces for PDU bytes starting at message byte ``base``: decoded fields, or as much as possible."""
    if not data:
        return []
    roles = [role] if role else list(ROLES)
    for r in roles:
        try:
            decoded = _pdu.decode_pdu(data, r)
        except ModbusError:
            continue
        return [_Piece(base + f.offset, len(f.raw), f.name, f.value, f.meaning) for f in decoded.fields()]
    # the whole PDU does not decode; perhaps a complete PDU followed by extra bytes
    for r in roles:
        try:
            size = _pdu.pdu_length(data, r)
            if size is None or size >= len(data):
                continue
            decoded = _pdu.decode_pdu(data[:size], r)
        except ModbusError:
            continue
        pieces = [_Piece(base + f.offset, len(f.raw), f.name, f.value, f.meaning) for f in decoded.fields()]
        pieces.append(_Piece(base + size, len(data) - size, "extra bytes", _hex(data[size:]),
                             f"the {decoded.title} PDU ends after {size} bytes; these do not belong to it",
                             ok=False))
        return pieces
    meaning, ok = _function_fallback(data[0], role)
    pieces = [_Piece(base, 1, "function code", data[0], meaning, ok)]
    if len(data) > 1:
        pieces.append(_Piece(base + 1, len(data) - 1, "data (not decoded)", _hex(data[1:]),
                             "these bytes do not form a valid PDU of this function (see the error)",
                             ok=False))
    return pieces


def _serial_message_pieces(msg: bytes, mode: str, role: str | None, check_size: int,
                           check_piece: Any) -> list[_Piece]:
    """Unit, PDU and check pieces of a serial message (RTU bytes, or the decoded bytes of ASCII)."""
    pieces: list[_Piece] = []
    if not msg:
        return pieces
    pieces.append(_unit_piece(msg[0], mode, role))
    if len(msg) >= 2 + check_size:
        pieces += _pdu_pieces(msg[1:-check_size], role, 1)
        pieces.append(check_piece(msg))
    elif len(msg) > 1:
        pieces.append(_Piece(1, len(msg) - 1, "incomplete", _hex(msg[1:]),
                             "too few bytes for a function code and the error check", ok=False))
    return pieces


def _crc_piece(msg: bytes) -> _Piece:
    n = len(msg)
    carried = int.from_bytes(msg[-2:], "little")
    computed = crc16(msg[:-2])
    over = f"bytes 0-{n - 3}" if n > 3 else "byte 0"
    if carried == computed:
        return _Piece(n - 2, 2, "CRC", f"0x{carried:04X}",
                      f"CRC-16 over {over}, sent low byte first ({_hex(msg[-2:])}): correct")
    return _Piece(n - 2, 2, "CRC", f"0x{carried:04X}",
                  f"mismatch: computed 0x{computed:04X} over {over}, which goes on the wire as "
                  f"{_hex(computed.to_bytes(2, 'little'))} (low byte first)", ok=False)


def _lrc_piece(msg: bytes) -> _Piece:
    n = len(msg)
    carried, computed = msg[-1], lrc(msg[:-1])
    if carried == computed:
        return _Piece(n - 1, 1, "LRC", f"0x{carried:02X}",
                      "two's complement of the sum of the bytes before it: correct")
    return _Piece(n - 1, 1, "LRC", f"0x{carried:02X}",
                  f"mismatch: computed 0x{computed:02X} (two's complement of the sum of the bytes before it)",
                  ok=False)


def _tcp_pieces(data: bytes, role: str | None) -> list[_Piece]:
    n = len(data)
    pieces: list[_Piece] = []

    def header(start: int, size: int, name: str, meaning_of) -> bool:
        if n <= start:
            return False
        got = data[start:start + size]
        if len(got) < size:
            pieces.append(_Piece(start, len(got), f"{name} (incomplete)", _hex(got),
                                 f"the MBAP header needs {size} bytes here", ok=False))
            return False
        value = int.from_bytes(got, "big")
        meaning, ok = meaning_of(value)
        pieces.append(_Piece(start, size, name, value, meaning, ok))
        return True

    def tid_meaning(value: int):
        return (f"0x{value:04X}, big-endian (high byte first): chosen by the client, echoed by the server "
                f"so the client can pair response and request"), True

    def pid_meaning(value: int):
        if value == 0:
            return "0 = Modbus", True
        return f"must be 0 for Modbus, found 0x{value:04X}", False

    def len_meaning(value: int):
        follow = n - 6
        if not 2 <= value <= 254:
            return f"bytes after this field; must be 2..254, and {follow} bytes follow", False
        if value == follow:
            return f"bytes that follow: unit identifier (1) + PDU ({value - 1}); big-endian", True
        return (f"bytes that follow should be {value}, but {follow} do: "
                f"{'frame truncated' if follow < value else 'extra bytes after the frame'}"), False

    if not (header(0, 2, "transaction identifier", tid_meaning)
            and header(2, 2, "protocol identifier", pid_meaning)
            and header(4, 2, "length", len_meaning)):
        return pieces
    if n <= 6:
        return pieces
    pieces.append(_unit_piece(data[6], "tcp", role))
    length = int.from_bytes(data[4:6], "big")
    end = 6 + length if 2 <= length and 6 + length < n else n
    pieces += _pdu_pieces(data[7:end], role, 7)
    if end < n:
        pieces.append(_Piece(end, n - end, "extra bytes", _hex(data[end:]),
                             f"beyond the {length} bytes the MBAP length announces (a next frame?)",
                             ok=False))
    return pieces


# --- rows from pieces ------------------------------------------------------------------------------
def _binary_rows(data: bytes, pieces: list[_Piece]) -> list[Row]:
    return [Row(p.start, data[p.start:p.start + p.length], p.field, p.value, p.meaning, p.ok) for p in pieces]


def _fill_gaps(rows: list[Row], data: bytes, unit: str) -> list[Row]:
    """Make the rows cover every byte exactly once: uncovered stretches become 'not explained' rows."""
    out: list[Row] = []
    at = 0
    for r in sorted(rows, key=lambda r: r.offset):
        if r.offset < at or not r.raw:
            continue  # overlapping or empty: drop (should not happen)
        if r.offset > at:
            out.append(Row(at, data[at:r.offset], "not explained", _hex(data[at:r.offset]),
                           f"{unit} not covered by any field", ok=False))
        out.append(r)
        at = r.offset + len(r.raw)
    if at < len(data):
        out.append(Row(at, data[at:], "not explained", _hex(data[at:]),
                       f"{unit} not covered by any field", ok=False))
    return out


def _rtu_rows(data: bytes, role: str | None) -> list[Row]:
    pieces = _serial_message_pieces(data, "rtu", role, 2, _crc_piece)
    if pieces and not pieces[-1].ok and pieces[-1].field == "CRC":
        # a wrong CRC at the end, but perhaps a complete frame with a good CRC followed by extra bytes
        # (two frames run together, or noise after the frame): show that frame and the extra bytes
        for r in [role] if role else list(ROLES):
            try:
                size = _pdu.pdu_length(data[1:], r)
            except ModbusError:
                continue
            if size is None or 3 + size >= len(data):
                continue
            total = 3 + size
            if crc16(data[:total - 2]) != int.from_bytes(data[total - 2:total], "little"):
                continue
            pieces = _serial_message_pieces(data[:total], "rtu", r, 2, _crc_piece)
            pieces.append(_Piece(total, len(data) - total, "extra bytes", _hex(data[total:]),
                                 f"after a complete frame of {total} bytes whose CRC is correct "
                                 f"(a next frame, or noise on the line)", ok=False))
            break
    return _binary_rows(data, pieces)


def _tcp_rows(data: bytes, role: str | None) -> list[Row]:
    return _binary_rows(data, _tcp_pieces(data, role))


def _ascii_rows(data: bytes, role: str | None) -> list[Row]:
    rows: list[Row] = []
    n = len(data)
    start = 0
    if data[:1] == b":":
        rows.append(Row(0, b":", "start", ":", "start of frame (0x3A)"))
        start = 1
    tail = 2 if data.endswith(b"\r\n") and n - start >= 2 else 1 if data[-1:] in (b"\r", b"\n") else 0
    tail = min(tail, n - start)
    body = data[start:n - tail]
    valid = 0
    while valid < len(body) and body[valid] in _HEX_DIGITS:
        valid += 1
    pairs = valid // 2
    decoded = bytes.fromhex(body[:2 * pairs].decode("ascii")) if pairs else b""
    complete = valid == len(body) and len(body) % 2 == 0
    if complete:
        pieces = _serial_message_pieces(decoded, "ascii", role, 1, _lrc_piece)
    else:
        pieces = []
        if decoded:
            pieces.append(_unit_piece(decoded[0], "ascii", role))
            if len(decoded) > 1:
                pieces.append(_Piece(1, len(decoded) - 1, "bytes (not decoded)", _hex(decoded[1:]),
                                     "hex pairs before the bad character; not decoded", ok=False))
    for p in pieces:
        at = start + 2 * p.start
        rows.append(Row(at, data[at:at + 2 * p.length], p.field, p.value, p.meaning, p.ok))
    rest = start + 2 * pairs
    if not complete and rest < n - tail:
        bad = data[rest:n - tail]
        if valid >= len(body):
            meaning = "a lone hex digit: every byte is written as two digits"
        else:
            at = start + valid
            meaning = f"not hex: {_ascii_text(data[at:at + 1]) or repr(chr(data[at]))} at char {at}"
        rows.append(Row(rest, bad, "not hex digits", _ascii_text(bad), meaning, ok=False))
    if tail:
        end = data[n - tail:]
        if end == b"\r\n":
            rows.append(Row(n - tail, end, "end", "CR LF", "end of frame (0x0D 0x0A)"))
        else:
            rows.append(Row(n - tail, end, "end (incomplete)", _ascii_text(end),
                            "an ASCII frame ends with CR LF (0x0D 0x0A)", ok=False))
    return rows


_ROW_BUILDERS = {"rtu": _rtu_rows, "ascii": _ascii_rows, "tcp": _tcp_rows}


def _pdu_bytes(data: bytes, mode: str) -> bytes:
    """Best guess of where the PDU is in a frame (for choosing a role when none decodes)."""
    if mode == "rtu":
        return data[1:-2] if len(data) >= 4 else data[1:]
    if mode == "tcp":
        return data[7:]
    body = data[1:-2] if data.endswith(b"\r\n") else data[1:]
    try:
        raw = bytes.fromhex(body.decode("ascii"))
    except ValueError:
        return b""
    return raw[1:-1]


def _guess_role(data: bytes, mode: str) -> str:
    """When neither role decodes: the one whose expected PDU length fits, else 'request'."""
    return _guess_pdu_role(_pdu_bytes(data, mode))


def _guess_pdu_role(pdu_bytes: bytes) -> str:
    """For PDU bytes that decode in neither role: the role whose expected length fits, else 'request'."""
    if pdu_bytes and pdu_bytes[0] & 0x80:
        return "response"
    for role in ROLES:
        try:
            if _pdu.pdu_length(pdu_bytes, role) == len(pdu_bytes):
                return role
        except ModbusError:
            continue
    return "request"


def explain(data: bytes | str, mode: str | None = None, role: str | None = None, *,
            strict: bool = False) -> Dissection:
    """Dissect a frame field by field.

    ``data`` is the raw frame (for ASCII the characters, CR LF included) or hex text, which goes
    through :func:`~modbus_edu.framing.parse_hex`.  ``mode`` is ``"rtu"``, ``"ascii"`` or ``"tcp"``;
    None guesses it with :func:`~modbus_edu.framing.detect_mode`.  ``role`` is ``"request"`` or
    ``"response"``; None tries request, then response, and keeps the one that decodes.

    Never raises for any bytes: the first error found is in ``.error`` (``strict=True`` raises it).
    A mode or role that is not one of the names above raises :class:`~modbus_edu.errors.ConfigError`.
    """
    if mode is not None:
        mode = _check_mode(mode)
    if role is not None:
        role = _pdu._check_role(role)
    if isinstance(data, str):
        try:
            raw = parse_hex(data)
        except FrameError as exc:
            if strict:
                raise
            return Dissection(data=b"", mode=mode or detect_mode(data), role=role, error=exc)
    else:
        try:
            raw = _as_bytes(data, "explain")
        except FrameError as exc:
            if strict:
                raise
            return Dissection(data=b"", mode=mode or "rtu", role=role, error=exc)
    detected = ""
    if mode is None:
        mode, detected = detect_mode_why(raw)

    frame: Frame | None = None
    error: ModbusError | None = None
    roles = [role] if role else list(ROLES)
    errors: dict[str, ModbusError] = {}
    for r in roles:
        try:
            frame = decode_frame(raw, mode, r)
        except ModbusError as exc:
            errors[r] = exc
            continue
        role = r
        break
    if frame is None:
        if role is None:
            role = _guess_role(raw, mode)
        error = errors[role]
    rows = _fill_gaps(_ROW_BUILDERS[mode](raw, role), raw, "characters" if mode == "ascii" else "bytes")
    result = Dissection(data=raw, mode=mode, role=role, rows=rows, frame=frame, error=error,
                        detected=detected)
    if strict and error is not None:
        raise error
    return result



def explain_pdu(pdu: _pdu.Pdu | bytes | str, role: str | None = None, *, strict: bool = False) -> Dissection:
    """Dissect a bare PDU field by field: the same table as :func:`explain`, without unit and check.

    ``pdu`` is a PDU object (``mb.ReadHoldingRegistersRequest(address=107, count=3)``), its bytes
    (function code first) or hex text.  ``role`` is ``"request"`` or ``"response"``; None takes the
    object's own role, or for bytes tries request, then response, and keeps the one that decodes.  The
    result is a :class:`Dissection` of mode ``"pdu"``: offsets count from the function code, ``.pdu``
    is the decoded PDU (None if the bytes do not decode), and the views are those of a frame's
    dissection (``to_text``, ``_repr_html_`` in a notebook, ``to_dict``).

    Never raises for any bytes: the first error is in ``.error`` (``strict=True`` raises it).  A role
    that is not one of the names above, or a PDU object given another role than its own, raises
    :class:`~modbus_edu.errors.ConfigError`.
    """
    if role is not None:
        role = _pdu._check_role(role)
    if isinstance(pdu, _pdu.Pdu):
        if role is not None and role != pdu.role:
            raise ConfigError(f"{type(pdu).__name__} is a {pdu.role}, not a {role}: leave role out for a "
                              f"PDU object")
        data = pdu.encode()
        rows = [Row(f.offset, f.raw, f.name, f.value, f.meaning) for f in pdu.fields()]
        return Dissection(data=data, mode="pdu", role=pdu.role, rows=_fill_gaps(rows, data, "bytes"),
                          pdu=pdu)
    try:
        data = parse_hex(pdu) if isinstance(pdu, str) else _as_bytes(pdu, "explain_pdu")
    except FrameError as exc:
        if strict:
            raise
        return Dissection(data=b"", mode="pdu", role=role, error=exc)
    decoded: _pdu.Pdu | None = None
    errors: dict[str, ModbusError] = {}
    for r in [role] if role else list(ROLES):
        try:
            decoded = _pdu.decode_pdu(data, r)
        except ModbusError as exc:
            errors[r] = exc
            continue
        role = r
        break
    if decoded is not None:
        rows = [Row(f.offset, f.raw, f.name, f.value, f.meaning) for f in decoded.fields()]
        return Dissection(data=data, mode="pdu", role=role, rows=_fill_gaps(rows, data, "bytes"), pdu=decoded)
    if role is None:
        role = _guess_pdu_role(data)
    error = errors[role]
    if strict:
        raise error
    rows = _fill_gaps(_binary_rows(data, _pdu_pieces(data, role, 0)), data, "bytes")
    return Dissection(data=data, mode="pdu", role=role, rows=rows, error=error)


def _pdu_html(pdu: _pdu.Pdu) -> str:
    """In a notebook a PDU shows as its dissection table (:func:`explain_pdu`)."""
    return explain_pdu(pdu)._repr_html_()


# PDUs do not explain themselves: explain gives every PDU its notebook view when it is imported (and
# ``import modbus_edu`` imports it), so that pdu/ needs nothing from here.
_pdu.Pdu._repr_html_ = _pdu_html  # type: ignore[attr-defined]
