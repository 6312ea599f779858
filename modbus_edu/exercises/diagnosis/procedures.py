"""One procedure per concept, each with the perturbations a learner's slips make of it (:mod:`.procedure`).

The concepts: the CRC (:data:`CRC`, the register value; :data:`CRC_WIRE`, its two bytes as sent), the LRC
(:data:`LRC`), the MBAP header (:data:`MBAP`), an RTU frame built from a unit and a PDU
(:func:`rtu_frame_procedure`), a transaction's time on a serial line (:data:`TRANSACTION_TIME`), an address
from a reference number (:data:`ADDRESS`), a float32 across two registers (:data:`FLOAT32`), the share of
requests a slow loop answers (:data:`ANSWERED`) and a bus message count (:func:`message_count_procedure`).
Every exercise that uses a concept asks the same procedure, so 03.1, 03.5 and 15.2 say the same thing about
the same CRC slip.
"""

from __future__ import annotations

import struct
from typing import Any

from ...crc import crc16, lrc
from ...devices.arduino import expected_answered_fraction
from ...framing import RtuFrame
from ...links.wire import SerialTiming
from ...values import ORDERS, decode_value
from .crcsteps import CRC_STEPS, hex_as_decimal
from .frames import frame_procedure
from .procedure import Choices, Perturbation, Procedure

# --- the CRC -------------------------------------------------------------------------------------------

CRC = Procedure(
    "the CRC (the register value)",
    crc16,
    tuple(Perturbation(key, step, misconception, compute) for key, step, misconception, compute in CRC_STEPS),
)
"""CRC-16/MODBUS of some bytes, as the register value (an int)."""


def _wire(register: Any) -> bytes | None:
    return register.to_bytes(2, "little") if isinstance(register, int) and 0 <= register <= 0xFFFF else None


CRC_WIRE = Procedure(
    "the CRC's two bytes in wire order",
    lambda data: crc16(data).to_bytes(2, "little"),
    tuple(
        [
            Perturbation(key, step, misconception, lambda data, compute=compute: _wire(compute(data)))
            for key, step, misconception, compute in CRC_STEPS
            if key not in ("as-bytes", "as-bytes-high-first", "low-byte-only", "high-byte-only")
        ]
        + [
            Perturbation(
                "one-byte",
                "one byte of the two",
                "crc-one-byte",
                lambda data: crc16(data).to_bytes(2, "little")[:1],
            ),
            Perturbation(
                "frame-given",
                "the whole frame given instead of its CRC",
                "another-question",
                lambda data: data + crc16(data).to_bytes(2, "little"),
            ),
        ]
    ),
)
"""The CRC of some bytes as its two bytes in the order they are sent (low byte first)."""


# --- the LRC -------------------------------------------------------------------------------------------

LRC = Procedure(
    "the LRC",
    lrc,
    (
        Perturbation(
            "plain-sum",
            "the plain 8-bit sum, not its two's complement",
            "lrc-plain-sum",
            lambda data: sum(data) & 0xFF,
        ),
        Perturbation(
            "ones-complement",
            "the one's complement of the sum (the bits inverted, no + 1)",
            "lrc-ones-complement",
            lambda data: ~sum(data) & 0xFF,
        ),
        Perturbation(
            "characters",
            "the LRC over the hex characters",
            "lrc-of-characters",
            lambda data: lrc(data.hex().upper().encode("ascii")),
        ),
        Perturbation(
            "not-8-bits", "the sum's negative, not kept to 8 bits", "lrc-not-8-bits", lambda data: -sum(data)
        ),
        Perturbation(
            "16-bits",
            "the sum's two's complement kept to 16 bits",
            "lrc-not-8-bits",
            lambda data: -sum(data) & 0xFFFF,
        ),
        Perturbation(
            "256-minus",
            "256 minus the sum without the final modulo (256 for a sum of 0)",
            "lrc-not-8-bits",
            lambda data: 256 - sum(data) % 256,
        ),
        Perturbation(
            "address-left-out",
            "the first byte (the address) left out",
            "checksum-without-address",
            lambda data: lrc(data[1:]) if data else None,
        ),
    ),
)
"""The LRC of some bytes (an int 0..255)."""


# --- the MBAP header -----------------------------------------------------------------------------------


def _mbap(
    tid: int,
    unit: int,
    pdu: bytes,
    *,
    tid_order: str = "big",
    length: int | None = None,
    length_order: str = "big",
) -> bytes:
    length = len(pdu) + 1 if length is None else length
    return tid.to_bytes(2, tid_order) + bytes(2) + length.to_bytes(2, length_order) + bytes([unit])


MBAP = Procedure(
    "the MBAP header",
    lambda tid, unit, pdu: _mbap(tid, unit, pdu),
    (
        Perturbation(
            "tid-little-endian",
            "the transaction id low byte first",
            "mbap-little-endian",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, tid_order="little"),
        ),
        Perturbation(
            "length-little-endian",
            "the length low byte first",
            "mbap-little-endian",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, length_order="little"),
        ),
        Perturbation(
            "all-little-endian",
            "every 2-byte field low byte first",
            "mbap-little-endian",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, tid_order="little", length_order="little"),
        ),
        Perturbation(
            "length-pdu-only",
            "a length that counts the PDU alone",
            "mbap-length",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, length=len(pdu)),
        ),
        Perturbation(
            "length-with-header",
            "a length that counts the whole frame",
            "mbap-length",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, length=len(pdu) + 7),
        ),
        Perturbation(
            "length-with-itself",
            "a length that counts itself too",
            "mbap-length",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu, length=len(pdu) + 3),
        ),
        Perturbation(
            "length-missing",
            "the length field left out",
            "mbap-length-missing",
            lambda tid, unit, pdu: tid.to_bytes(2, "big") + bytes(2) + bytes([unit]),
        ),
        Perturbation(
            "length-one-byte",
            "the length in one byte",
            "mbap-length-missing",
            lambda tid, unit, pdu: tid.to_bytes(2, "big") + bytes(2) + bytes([len(pdu) + 1, unit]),
        ),
        Perturbation(
            "protocol-one-byte",
            "the protocol identifier in one byte",
            "field-in-one-byte",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu)[:3] + _mbap(tid, unit, pdu)[4:],
        ),
        Perturbation(
            "tid-low-byte-kept",
            "the transaction id kept to its low byte",
            "field-in-one-byte",
            lambda tid, unit, pdu: _mbap(tid & 0xFF, unit, pdu) if tid > 0xFF else None,
        ),
        Perturbation(
            "unit-missing",
            "the unit identifier left out",
            "unit-missing",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu)[:6],
        ),
        Perturbation(
            "whole-frame",
            "the whole frame, header and PDU",
            "frame-for-header",
            lambda tid, unit, pdu: _mbap(tid, unit, pdu) + bytes(pdu),
        ),
    ),
)
"""The 7-byte MBAP header of a Modbus/TCP frame from its transaction id, unit and PDU."""


# --- an RTU frame from a unit and a request ------------------------------------------------------------


def rtu_frame_procedure(unit: int, pdu: Any) -> Procedure:
    """The RTU frame of ``unit`` and the request ``pdu``, and the frames its slips give: the shared frame
    procedure (:func:`.frames.frame_procedure`): another mode's frame, the CRC swapped, left out, over the
    PDU alone or one byte of it, the unit left out, a field written wrong (the address counted from 1 or
    given as a reference number, a field low byte first or in one byte ...), and a field and the
    envelope both."""
    procedure = frame_procedure(RtuFrame(unit=unit, pdu=pdu).encode(), "rtu")
    if procedure is None:  # every request the library encodes has fields explain reads
        raise ValueError(f"no fields read in the RTU frame of unit {unit} and {pdu!r}")
    return procedure


# --- a transaction's time on a serial line -------------------------------------------------------------


def _time(
    baudrate: int,
    parity: str,
    stopbits: int,
    request: int,
    response: int,
    *,
    bits: int | None = None,
    t35: float | None = None,
    silences: float = 2,
) -> float:
    char = (1 + 8 + (parity != "N") + stopbits if bits is None else bits) / baudrate
    silence = (0.00175 if baudrate > 19200 else 3.5 * char) if t35 is None else t35
    return (request + response) * char + silences * silence


def _t35_chars(chars: float):
    return lambda b, p, s, q, r: _time(b, p, s, q, r, t35=chars * (1 + 8 + (p != "N") + s) / b)


TRANSACTION_TIME = Procedure(
    "a transaction's time on a serial line",
    lambda *args: SerialTiming(baudrate=args[0], parity=args[1], stopbits=args[2]).transaction_time(
        args[3], args[4]
    ),
    (
        Perturbation(
            "parity-forgotten",
            "10 bits a character whatever the parity and stop bits",
            "parity-bit-forgotten",
            lambda b, p, s, q, r: _time(b, p, s, q, r, bits=10),
        ),
        Perturbation(
            "parity-forgotten-no-fixed-silence",
            "10 bits a character, and 3.5 characters for t3.5 at every rate",
            "parity-bit-forgotten",
            lambda b, p, s, q, r: _time(b, p, s, q, r, bits=10, t35=35 / b),
            also="fixed-silence-ignored",
        ),
        Perturbation(
            "stop-bits-one",
            "the stop bits always 1",
            "parity-bit-forgotten",
            lambda b, p, s, q, r: _time(b, p, 1, q, r),
        ),
        Perturbation(
            "parity-left-out",
            "the parity bit left out",
            "parity-bit-forgotten",
            lambda b, p, s, q, r: _time(b, "N", s, q, r),
        ),
        Perturbation(
            "no-silences",
            "the silences left out",
            "silences-forgotten",
            lambda b, p, s, q, r: _time(b, p, s, q, r, silences=0),
        ),
        Perturbation(
            "one-silence",
            "one silence instead of two",
            "silences-forgotten",
            lambda b, p, s, q, r: _time(b, p, s, q, r, silences=1),
        ),
        Perturbation(
            "no-fixed-silence",
            "3.5 characters for t3.5 above 19200 baud",
            "fixed-silence-ignored",
            _t35_chars(3.5),
        ),
        Perturbation(
            "fixed-silence-from-19200",
            "the fixed 1.75 ms already at 19200 baud",
            "fixed-silence-at-19200",
            lambda b, p, s, q, r: _time(b, p, s, q, r, t35=0.00175) if b == 19200 else _time(b, p, s, q, r),
        ),
        Perturbation(
            "three-characters",
            "silences of 3 characters, not 3.5",
            "three-characters-for-t35",
            lambda b, p, s, q, r: _t35_chars(3)(b, p, s, q, r) if b <= 19200 else None,
        ),
        Perturbation(
            "parity-added",
            "11 bits a character (a parity bit where the line has none)",
            None,
            lambda b, p, s, q, r: _time(b, p, s, q, r, bits=11) if p == "N" and s == 1 else None,
        ),
        Perturbation(
            "eight-bits",
            "8 bits a character (no start and stop bits)",
            "start-stop-forgotten",
            lambda b, p, s, q, r: _time(b, p, s, q, r, bits=8),
        ),
    ),
    forms=(Perturbation("milliseconds", "the time in milliseconds", "milliseconds-for-seconds",
                        lambda seconds: 1000 * seconds),),
    same=lambda mine, got: (
        isinstance(got, (int, float))
        and not isinstance(got, bool)
        and abs(mine - got) <= 1e-9 + 1e-9 * abs(mine)
    ),
)
"""A transaction's time in seconds: (baudrate, parity, stopbits, request bytes, response bytes)."""


# --- addresses -----------------------------------------------------------------------------------------

ADDRESS = Procedure(
    "an address on the wire from a register number (from 1)",
    lambda number: number - 1,
    (
        Perturbation(
            "from-1", "the register number itself (counted from 1)", "one-based-address", lambda n: n
        ),
        Perturbation("minus-two", "1 subtracted twice", "address-one-too-low", lambda n: n - 2),
    )
    + tuple(
        Perturbation(f"reference-{table}{'-6' if digits == 6 else ''}{'-less-1' if less else ''}",
                     f"the {digits}-digit reference number {table}{'x' * (digits - 1)}"
                     + (" less 1" if less else ""),
                     "reference-number",
                     lambda n, base=table * 10 ** (digits - 1), less=less: base + n - less)
        for table in (4, 3) for digits in (5, 6) for less in (0, 1)
    ),
)
"""The address on the wire of the n-th register (n counted from 1, as a register number is)."""


# --- a float32 across two registers --------------------------------------------------------------------


def _float32(registers: list, order: str) -> float:
    return decode_value(list(registers), "float32", order)


FLOAT32 = Procedure(
    "a float32 in two registers",
    _float32,
    tuple(
        [
            Perturbation(
                f"always-{order}",
                f"the {order} order whatever the order asked",
                "word-order",
                lambda registers, order_asked, order=order: _float32(registers, order),
            )
            for order in ORDERS
        ]
        + [
            Perturbation(
                "another-order",
                "a word order taken for another (each order read as some order)",
                "word-order",
                lambda registers, order: Choices(
                    [_float32(registers, other) for other in ORDERS]
                    + [struct.unpack("<f", b"".join(int(r).to_bytes(2, "big") for r in registers))[0]]
                ),
            )
        ]
        + [
            Perturbation(
                "registers-swapped",
                "the registers taken in the other order",
                "word-order",
                lambda registers, order: _float32(list(registers)[::-1], order),
            ),
            Perturbation(
                "as-uint32",
                "the registers read as a 32-bit integer",
                "integer-for-float",
                lambda registers, order: decode_value(list(registers), "uint32", order),
            ),
        ]
        + [
            Perturbation(
                f"rounded-{places}",
                f"the result rounded to {places} decimals",
                "result-rounded",
                lambda registers, order, places=places: round(_float32(registers, order), places),
            )
            for places in (0, 1, 2, 3)
        ]
    ),
)
"""A float32's value from its two registers in a word order (ABCD, CDAB, BADC, DCBA)."""


# --- the share of requests a slow loop answers ---------------------------------------------------------


def _share(value: float) -> float:
    return min(1.0, max(0.0, value))


ANSWERED = Procedure(
    "the share of requests a slow loop answers",
    expected_answered_fraction,
    (
        Perturbation(
            "unclamped",
            "(timeout - reply) / loop time, not kept within 0..1",
            "fraction-unclamped",
            lambda loop, timeout, reply: (timeout - reply) / loop,
        ),
        Perturbation(
            "unclamped-reply-forgotten",
            "timeout / loop time, neither the reply's time taken away nor kept within 0..1",
            "fraction-unclamped",
            lambda loop, timeout, reply: timeout / loop,
            also="reply-time-forgotten",
        ),
        Perturbation(
            "clamped-at-1-only",
            "(timeout - reply) / loop time kept below 1 but not above 0",
            "fraction-unclamped",
            lambda loop, timeout, reply: min(1.0, (timeout - reply) / loop),
        ),
        Perturbation(
            "reply-forgotten",
            "timeout / loop time (the reply's time left out)",
            "reply-time-forgotten",
            lambda loop, timeout, reply: _share(timeout / loop),
        ),
        Perturbation(
            "reply-added",
            "(timeout + reply) / loop time (the reply's time added, not taken away)",
            None,
            lambda loop, timeout, reply: _share((timeout + reply) / loop),
        ),
        Perturbation(
            "missed",
            "the share missed",
            "missed-for-answered",
            lambda loop, timeout, reply: 1 - _share((timeout - reply) / loop),
        ),
    ),
    forms=(Perturbation("percentage", "a percentage", "percentage-for-fraction", lambda share: 100 * share),),
)
"""The share of requests answered in time: (loop time, timeout, reply time), all in seconds."""


# --- a bus message count -------------------------------------------------------------------------------


def message_count_procedure(expected: int, *, own_responses: int, own_requests: int) -> Procedure:
    """A slave's bus message count after a clear (``expected``), and the counts its slips give: a damaged
    frame counted, the clear request counted, the count request left out, another node's response left
    out, its own responses counted, only the requests addressed to it counted (``own_requests``)."""
    return Procedure(
        "a bus message count",
        lambda: expected,
        (
            Perturbation(
                "damaged-counted", "a damaged frame counted", "damaged-message-counted", lambda: expected + 1
            ),
            Perturbation("clear-counted", "the clear request counted", None, lambda: expected + 1),
            Perturbation(
                "count-request-left-out",
                "the count request itself left out",
                "count-request-forgotten",
                lambda: expected - 1,
            ),
            Perturbation(
                "other-response-left-out", "another unit's response left out", None, lambda: expected - 1
            ),
            Perturbation(
                "own-counted",
                "its own responses counted",
                "own-frames-counted",
                lambda: expected + own_responses,
            ),
            Perturbation(
                "own-only",
                "only the requests addressed to it counted",
                "others-not-heard",
                lambda: own_requests,
            ),
            Perturbation(
                "own-only-with-count",
                "only the requests addressed to it, and the count request",
                "others-not-heard",
                lambda: own_requests + 1,
            ),
        ),
    )


PROCEDURES = {
    "crc": CRC,
    "crc-wire": CRC_WIRE,
    "lrc": LRC,
    "mbap": MBAP,
    "transaction-time": TRANSACTION_TIME,
    "address": ADDRESS,
    "float32": FLOAT32,
    "answered": ANSWERED,
}
"""The procedures of fixed arguments, by concept (the frame's and the count's are made per exercise)."""


# --- one field's value read from a frame ---------------------------------------------------------------


def field_value_procedure(raw: bytes, name: str, others: dict[str, int], *,
                          register: bool = False) -> Procedure:
    """Reading the 2-byte field ``raw`` (called ``name``) out of a frame, and the values its slips give: the
    field low byte first, its high or low byte alone, its hex digits read as decimal, or another field of
    the frame (``others``: each field's name and value).  Where two of them give the same number (a high
    byte of 01 and a unit of 1), the verdict names both candidates.  A ``register`` value read as one of its
    bytes is "a register of one byte"; another 2-byte field, "a 2-byte field in one byte"."""
    one_byte = "register-one-byte" if register else "field-in-one-byte"
    value = int.from_bytes(raw, "big")
    steps = [
        Perturbation("low-first", f"the {name} low byte first", "field-low-byte-first",
                     lambda: int.from_bytes(raw[::-1], "big") if raw[0] != raw[1] else None),
        Perturbation("high-byte", f"the {name}'s high byte alone", one_byte,
                     lambda: raw[0] if value > 0xFF else None),
        Perturbation("low-byte", f"the {name}'s low byte alone", one_byte,
                     lambda: raw[1] if value > 0xFF else None),
        Perturbation("hex-as-decimal", f"the {name}'s hex digits read as decimal", "hex-read-as-decimal",
                     lambda: hex_as_decimal(value)),
    ]
    steps += [Perturbation(f"field-{other}", f"the {other} ({number})", "another-field",
                           lambda number=number: number, fields={"got": number, "field": other})
              for other, number in others.items() if number != value]
    return Procedure(f"the {name} read from a frame", lambda: value, tuple(steps))


# --- the length of a read's response: an RTU frame's bytes, or the MBAP length field -------------------


def response_length_procedure(count: int, *, mbap: bool) -> Procedure:
    """The length of the response to a read of ``count`` registers (FC 3 or 4): the RTU frame's bytes, or
    with ``mbap`` the MBAP length field (the bytes after it: unit, function, byte count, data), and what
    its slips give: a register of one byte (or four), the byte count, the unit or the CRC left out, a CRC
    counted on Modbus/TCP, the data alone, and the request's length given for the response's (the MBAP
    length: also the length counting the PDU alone, the whole frame or itself)."""
    def length(*, per_register: int = 2, byte_count: int = 1, unit: int = 1, crc: int = 0) -> int:
        return unit + 1 + byte_count + per_register * count + crc

    tail = 0 if mbap else 2
    request = 6 if mbap else 8  # the request's length field (unit + 5), or its RTU frame's bytes
    return Procedure(
        "the MBAP length of a read's response" if mbap else "the length of a read's RTU response",
        lambda: length(crc=tail),
        (
            Perturbation("one-byte", "one byte a register", "register-one-byte",
                         lambda: length(per_register=1, crc=tail)),
            Perturbation("four-bytes", "four bytes a register", None,
                         lambda: length(per_register=4, crc=tail)),
            *(() if mbap else (Perturbation("byte-count-left-out", "no byte for the byte count",
                                            "byte-count-missing", lambda: length(byte_count=0, crc=tail)),
                               Perturbation("unit-left-out", "the unit left out", "unit-missing",
                                            lambda: length(unit=0, crc=tail)))),
            Perturbation("crc", "a CRC counted on Modbus/TCP" if mbap else "the CRC left out",
                         "crc-on-tcp" if mbap else "crc-forgotten", lambda: length(crc=2 - tail)),
            Perturbation("data-only", "the data bytes alone", "data-bytes-only", lambda: 2 * count),
            Perturbation("request", "the request's length, where the response's is asked", "another-question",
                         lambda: request),
            *((Perturbation("length-pdu", "a length that counts the PDU alone", "mbap-length",
                            lambda: length(unit=0)),
               Perturbation("length-frame", "a length that counts the whole frame", "mbap-length",
                            lambda: length() + 6),
               Perturbation("length-itself", "a length that counts itself too", "mbap-length",
                            lambda: length() + 2)) if mbap else ()),
        ),
    )
