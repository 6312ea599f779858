"""The procedure of building a frame byte by byte, and the frames a learner's slips make of it.

:func:`frame_procedure` reads the right frame's fields (its dissection by :func:`~modbus_edu.explain.explain`)
and makes, for any frame of any exercise, the frames one step changed gives:

* a **field** written wrong: a 2-byte field low byte first, in one byte, kept to its low byte, its decimal
  digits written as hex or its hex digits read as decimal; an address counted from 1, less 1 twice, or
  given as its reference number; the unit's or a byte's digits mixed up the same way; an exception's
  function code without its top bit; a read's quantity counted in bytes;
* the **envelope** changed: for an ASCII frame the LRC a plain sum, its one's complement, over the
  characters or the PDU alone, a CRC in its place or none, CR LF or ':' left out, LF alone, spaces between
  the bytes; for an RTU frame the CRC's bytes swapped, left out, over the PDU alone or one
  byte of it, the slave address left out, the PDU alone, a Modbus/TCP or an ASCII frame, CR LF at the end;
  for a Modbus/TCP frame a CRC after it, the MBAP header or the unit left out, the length missing or
  counting the wrong bytes, an RTU frame; for a PDU the unit in front of it, a checksum after it, a whole
  frame, the function code left out;
* and **one of each**: a field written wrong in a frame whose envelope is changed too (a frame with both
  the CRC's bytes swapped and the address counted from 1).

After a field change the learner's own checksum and length follow their own bytes (they computed them with
the library), or stay what the right frame carries (they copied them): both are tried.  Every exercise that
builds a frame asks this one procedure, so the same slip reads the same in each.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...crc import crc16, lrc
from ...errors import ModbusError
from ...explain import explain, explain_pdu
from .catalogue import detect
from .crcsteps import CRC_STEPS, REGISTER_SLIPS, hex_as_decimal
from .procedure import Choices, Perturbation, Procedure

MODES = ("rtu", "tcp", "pdu", "ascii")


def _rows(expected: bytes, mode: str) -> list | None:
    """The right frame's fields as (offset, length, field name, value) tuples, or None."""
    for role in ("request", "response", None):
        try:
            found = (explain_pdu(expected, role=role) if mode == "pdu"
                     else explain(expected, mode=mode, role=role))
        except (ModbusError, ValueError, TypeError):
            continue
        if found.error is None and found.rows and not any("not decoded" in row.field for row in found.rows):
            return [(row.offset, len(row.raw), row.field.lower(), row.raw) for row in found.rows]
    return None


def _decimal_as_hex(value: int) -> int | None:
    number = int(str(value), 16)
    return number if number != value else None


def _field_changes(offset: int, size: int, name: str, raw: bytes, mode: str,
                   function: int | None = None) -> list[tuple]:
    """The ways to write one field wrong: (key, step, misconception, new bytes); ``function`` is the
    frame's function code."""
    value = int.from_bytes(raw, "big")
    mbap = mode == "tcp" and offset < 7
    where = f"the {name}"
    changes: list[tuple] = []
    if size == 2:
        if raw[0] != raw[1]:
            changes.append(("low-first", f"{where} low byte first",
                            "mbap-little-endian" if mbap else "field-low-byte-first", raw[::-1]))
        if value < 256 and not (mbap and "length" in name):
            changes.append(("one-byte", f"{where} in one byte", "field-in-one-byte", raw[1:]))
        if value >= 256:
            changes.append(("low-byte-kept", f"{where} kept to its low byte", "field-in-one-byte",
                            bytes([0, raw[1]])))
    if not mbap or "transaction" in name:
        width = size
        for key, step, misconception, number in (
                ("decimal-as-hex", f"{where}'s decimal digits written as hex", "decimal-written-as-hex",
                 _decimal_as_hex(value)),
                ("hex-as-decimal", f"{where}'s hex digits read as decimal", "hex-read-as-decimal",
                 hex_as_decimal(value))):
            if number is not None and number < 256 ** width:
                changes.append((key, step, misconception, number.to_bytes(width, "big")))
    if "address" in name and size == 2 and not mbap:
        for key, step, misconception, number in (
                ("from-1", "the address counted from 1", "one-based-address", value + 1),
                ("minus-2", "1 subtracted twice from the address", "address-one-too-low", value - 1),
                ("reference-4", f"the reference number {40001 + value} for the address", "reference-number",
                 40001 + value),
                ("reference-3", f"the reference number {30001 + value} for the address", "reference-number",
                 30001 + value)):
            if 0 <= number <= 0xFFFF:
                changes.append((key, step, misconception, number.to_bytes(2, "big")))
    if name == "quantity" and size == 2 and function in (3, 4) and 2 <= value <= 0x7FFF:  # 2 x 1 is 1 + 1
        changes.append(("bytes", f"{where} counted in bytes, two a register", "bytes-for-registers",
                        (2 * value).to_bytes(2, "big")))
    if name == "function code" and value >= 0x80:
        changes.append(("top-bit", "the function code without its top bit", "exception-bit-missing",
                        bytes([value - 0x80])))
    if name == "function code" and value in (3, 4):
        changes.append(("table", f"function {7 - value} for function {value}", "holding-for-input",
                        bytes([7 - value])))
    return [(f"{offset}-{key}", step, misconception, offset, size, new)
            for key, step, misconception, new in changes]


def _fields(change: tuple, expected: bytes) -> dict:
    """The numbers the catalogue's sentence of a field change names (500 is 01 F4, and F4 01 reads as ...)."""
    _key, _step, misconception, offset, size, new = change
    if misconception is None:
        return {}
    found = detect(misconception, int.from_bytes(new, "big"),
                   int.from_bytes(expected[offset:offset + size], "big"))
    return found if isinstance(found, dict) else {}


def _rtu(body: bytes) -> bytes:
    return body + crc16(body).to_bytes(2, "little")


def _with_register(body: bytes, register: Any) -> bytes | None:
    """``body`` and a CRC register's value, low byte first (None: no 16-bit register)."""
    if not isinstance(register, int) or not 0 <= register <= 0xFFFF:
        return None
    return body + register.to_bytes(2, "little")


def _ascii(body: bytes) -> bytes:
    return b":" + (body + bytes([lrc(body)])).hex().upper().encode("ascii") + b"\r\n"


Envelope = tuple[str, str, "str | None", Callable[[bytes, bytes], Any]]


def _envelopes(mode: str, expected: bytes) -> list[Envelope]:
    """The envelope's slips: (key, step, misconception, make(body, right body) -> frame or Choices).

    ``body`` is what the envelope wraps, perhaps with a field changed: for RTU the unit and the PDU, for
    Modbus/TCP the MBAP header, unit and PDU, for a PDU the PDU."""
    if mode == "rtu":
        return [
            ("crc-high-first", "the CRC's bytes swapped", "crc-swapped",
             lambda body, right: body + crc16(body).to_bytes(2, "big")),
            ("crc-left-out", "the CRC left out", "crc-forgotten", lambda body, right: body),
            *[(f"crc-{key}", f"a CRC with {step}", misconception,
               lambda body, right, compute=compute: _with_register(body, compute(body)))
              for key, step, misconception, compute in CRC_STEPS if key in REGISTER_SLIPS],
            ("crc-over-pdu", "a CRC over the PDU alone", "checksum-without-address",
             lambda body, right: body + crc16(body[1:]).to_bytes(2, "little")),
            ("crc-one-byte", "one byte of the CRC", "crc-one-byte",
             lambda body, right: Choices([_rtu(body)[:-1], body + _rtu(body)[-1:]])),
            ("unit-left-out", "the slave address left out", "unit-missing",
             lambda body, right: Choices([_rtu(body[1:]), body[1:] + _rtu(body)[-2:]])),
            ("pdu-only", "the PDU alone, without the slave address and the CRC around it", "unit-missing",
             lambda body, right: body[1:]),
            ("tcp-frame", "a Modbus/TCP frame (MBAP header, no CRC) where an RTU frame is asked",
             "tcp-frame-for-rtu", lambda body, right: ("tcp", body)),
            ("ascii-frame", "an ASCII frame where an RTU frame is asked", "ascii-frame-for-rtu",
             lambda body, right: _ascii(body)),
            ("crlf", "CR LF after the CRC", "crlf-for-frame-end", lambda body, right: _rtu(body) + b"\r\n"),
        ]
    if mode == "ascii":
        def lrc_as(value: Callable[[bytes], int]) -> Callable[[bytes, bytes], bytes]:
            return lambda body, right: b":" + (body + bytes([value(body) & 0xFF])).hex().upper().encode() + \
                b"\r\n"
        return [
            ("lrc-plain-sum", "the plain sum for the LRC", "lrc-plain-sum", lrc_as(sum)),
            ("lrc-ones", "the one's complement of the sum for the LRC", "lrc-ones-complement",
             lrc_as(lambda body: ~sum(body))),
            ("lrc-characters", "the LRC over the hex characters", "lrc-of-characters",
             lrc_as(lambda body: lrc(body.hex().upper().encode("ascii")))),
            ("lrc-over-pdu", "an LRC over the PDU alone", "checksum-without-address",
             lrc_as(lambda body: lrc(body[1:]))),
            ("crc-for-lrc", "a 2-byte CRC where the LRC goes", "crc-in-ascii",
             lambda body, right: b":" + (body + crc16(body).to_bytes(2, "little")).hex().upper().encode()
             + b"\r\n"),
            ("lrc-left-out", "the LRC left out", None,
             lambda body, right: b":" + body.hex().upper().encode() + b"\r\n"),
            ("crlf-left-out", "CR LF left out", "ascii-without-crlf", lambda body, right: _ascii(body)[:-2]),
            ("lf-only", "LF alone at the end, without the CR before it", None,
             lambda body, right: _ascii(body)[:-2] + b"\n"),
            ("colon-left-out", "the ':' left out", "ascii-colon-forgotten",
             lambda body, right: _ascii(body)[1:]),
            ("spaces", "spaces between the bytes' characters", None,
             lambda body, right: b":" + (body + bytes([lrc(body)])).hex(" ").upper().encode() + b"\r\n"),
            ("unit-left-out", "the slave address left out", "unit-missing",
             lambda body, right: _ascii(body[1:])),
            ("rtu-frame", "the RTU frame's bytes (with a CRC), where an ASCII frame's characters are asked",
             "another-question", lambda body, right: _rtu(body)),
        ]
    if mode == "tcp":
        return [
            ("crc-added", "a CRC after the PDU", "crc-on-tcp",
             lambda body, right: Choices([body + crc16(body[6:]).to_bytes(2, "little"),
                                          _retold(body, 2) + crc16(body[6:]).to_bytes(2, "little")])),
            ("mbap-left-out", "the unit and the PDU without the MBAP header in front", "part-of-answer",
             lambda body, right: body[6:]),
            ("rtu-frame", "an RTU frame (unit, PDU, CRC) where a Modbus/TCP frame is asked",
             "another-question", lambda body, right: _rtu(body[6:])),
            ("pdu-only", "the PDU alone, without the MBAP header", "part-of-answer",
             lambda body, right: body[7:]),
            ("unit-left-out", "the unit identifier left out", "unit-missing",
             lambda body, right: Choices([body[:6] + body[7:], _retold(body[:6] + body[7:], 0)])),
            ("length-left-out", "the length field left out", "mbap-length-missing",
             lambda body, right: body[:4] + body[6:]),
            ("length-one-byte", "the length in one byte", "mbap-length-missing",
             lambda body, right: body[:4] + body[5:]),
            ("length-pdu", "a length that counts the PDU alone", "mbap-length",
             lambda body, right: _retold(body, -1)),
            ("length-frame", "a length that counts the whole frame", "mbap-length",
             lambda body, right: _retold(body, 6)),
            ("length-itself", "a length that counts itself too", "mbap-length",
             lambda body, right: _retold(body, 2)),
        ]
    return [
        ("unit-in-front", "the unit in front of the PDU", "unit-in-pdu",
         lambda body, right: ("unit-in-front", body)),
        ("crc-after", "a checksum after the PDU", "frame-for-pdu",
         lambda body, right: ("crc-after", body)),
        ("function-left-out", "the PDU without its function code", "function-code-missing",
         lambda body, right: body[1:]),
    ]


def _retold(frame: bytes, more: int) -> bytes:
    """A Modbus/TCP frame whose length field says ``more`` more than what follows it."""
    return frame[:4] + (len(frame) - 6 + more).to_bytes(2, "big") + frame[6:]


def _with_field(expected: bytes, mode: str, change: tuple) -> Choices:
    """The right frame's body with one field written wrong; its length field (Modbus/TCP) following the
    change or not."""
    _key, _step, _misconception, offset, size, new = change
    body = _body(expected, mode)
    changed = body[:offset] + new + body[offset + size:]
    if mode == "tcp" and len(new) != size and offset >= 6:
        return Choices([changed, _retold(changed, 0)])
    return Choices([changed])


def _body(expected: bytes, mode: str) -> bytes:
    """What the envelope wraps: an RTU frame without its CRC, an ASCII frame's bytes without the LRC."""
    if mode == "ascii":
        return bytes.fromhex(expected[1:-2].decode("ascii"))[:-1]
    return expected[:-2] if mode == "rtu" else expected


def _wrap(mode: str, body: bytes, right_body: bytes) -> Choices:
    """The right envelope around ``body`` (a field changed): the checksum of the learner's bytes, or the
    right frame's (copied)."""
    if mode == "rtu":
        return Choices([_rtu(body), body + _rtu(right_body)[-2:]])
    if mode == "ascii":
        return Choices([_ascii(body), _ascii(body)[:-4] + _ascii(right_body)[-4:]])
    return Choices([body])


def frame_procedure(expected: Any, mode: str) -> Procedure | None:
    """The procedure that builds the frame ``expected`` (bytes: an RTU frame, a Modbus/TCP frame, a PDU or
    an ASCII frame's characters, as ``mode`` says) and its perturbations; None when the frame's fields
    cannot be read."""
    if mode not in MODES or not isinstance(expected, (bytes, bytearray)) or not expected:
        return None
    expected = bytes(expected)
    try:
        rows = _rows(_rtu(_body(expected, mode)), "rtu") if mode == "ascii" else _rows(expected, mode)
    except (ValueError, UnicodeDecodeError):  # not an ASCII frame of hex characters
        return None
    if rows is None:
        return None
    right_body = _body(expected, mode)
    function = next((raw[0] for _offset, _size, name, raw in rows if name == "function code"), None)
    fields = [change for offset, size, name, raw in rows if name != "crc" and offset + size <= len(right_body)
              for change in _field_changes(offset, size, name, raw, mode, function)]
    steps: list[Perturbation] = []
    for change in fields:
        key, step, misconception, *_ = change
        steps.append(Perturbation(
            key, step, misconception,
            lambda change=change: Choices(frame for body in _with_field(expected, mode, change)
                                          for frame in _wrap(mode, body, right_body)),
            fields=_fields(change, right_body)))
    for key, step, misconception, make in _envelopes(mode, expected):
        steps.append(Perturbation(key, step, misconception,
                                  lambda make=make: make(right_body, right_body),
                                  also="crc-forgotten" if (mode, key) == ("rtu", "pdu-only") else None))
        for change in fields:
            field_key, field_step, field_misconception, *_ = change
            steps.append(Perturbation(
                f"{key}+{field_key}", f"{step}, and {field_step}", misconception,
                lambda make=make, change=change: Choices(
                    one for body in _with_field(expected, mode, change)
                    for one in _flat(make(body, right_body))),
                also=field_misconception if field_misconception != misconception else None))
    unit = expected[0] if mode == "rtu" else None
    return Procedure(f"a frame ({mode})", lambda: expected, tuple(steps),
                     same=lambda mine, got: _same_frame(mine, got, unit))


def _flat(made: Any) -> list:
    return list(made) if isinstance(made, Choices) else [made]


def _same_frame(mine: Any, got: Any, unit: int | None) -> bool:
    if not isinstance(got, (bytes, bytearray)):
        return False
    got = bytes(got)
    if isinstance(mine, tuple) and len(mine) == 2 and isinstance(mine[0], str):
        kind, body = mine
        if kind == "tcp":  # any transaction id, the right protocol id and length
            return len(got) == len(body) + 6 and got[2:4] == bytes(2) and \
                int.from_bytes(got[4:6], "big") == len(body) and got[6:] == body
        if kind == "unit-in-front":  # whatever unit leads
            return len(got) == len(body) + 1 and got[1:] == body
        if kind == "crc-after":  # a CRC of the PDU, with or without a unit in front
            return len(got) == len(body) + 2 and got[:len(body)] == body and (
                got[-2:] == crc16(body).to_bytes(2, "little") or any(
                    got[-2:] == crc16(bytes([u]) + body).to_bytes(2, "little") for u in range(248)))
        return False
    return isinstance(mine, (bytes, bytearray)) and bytes(mine) == got


def frame_verdict(got: Any, expected: Any, mode: str) -> str | None:
    """The verdict's words for a frame the learner built: the one change of :func:`frame_procedure` that
    gives it (or the candidates), else None."""
    procedure = frame_procedure(expected, mode)
    if procedure is None or not isinstance(got, (bytes, bytearray)) or bytes(got) == bytes(expected):
        return None
    return procedure.explain([((), bytes(got))])
