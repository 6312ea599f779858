"""The catalogue of misconceptions: the mistakes learners make about Modbus, each named one way.

Every checker that can recognise a mistake asks this catalogue for it, so that the same mistake reads the
same in every notebook: a CRC whose two bytes are the wrong way round is "swapped CRC bytes" whether the
learner built a frame (03.2), corrected one (13.5) or wrote a function that returns the CRC (03.5).

An entry has a key (``"crc-swapped"``), a label (the name a learner reads), the shape of what its
detector reads, a teaching sentence (which may name the learner's case: ``{used}``) and a detector.
:func:`name` gives the verdict's words; :func:`detect` runs one detector; :func:`diagnose` tries several
and names the first that fits.  Detectors never raise: a value of the wrong kind simply does not fit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..crc import crc16, lrc
from ..pdu import mask_write
from ..values import ORDERS, decode_value


@dataclass(frozen=True)
class Misconception:
    """One mistake: its key, the label a learner reads, what its detector reads, one teaching sentence."""

    key: str
    label: str
    shape: str
    sentence: str
    detector: Callable[..., Any]

    def say(self, **fields: Any) -> str:
        """The words of a verdict: the label, then the teaching sentence with ``fields`` filled in."""
        return f"{self.label}: {self.sentence.format(**fields)}"


CATALOGUE: dict[str, Misconception] = {}


def _entry(key: str, label: str, shape: str, sentence: str) -> Callable:
    def register(detector: Callable[..., Any]) -> Callable[..., Any]:
        if key in CATALOGUE:
            raise ValueError(f"misconception {key} is catalogued twice")
        CATALOGUE[key] = Misconception(key, label, shape, sentence, detector)
        return detector

    return register


def name(key: str, **fields: Any) -> str:
    """The verdict for the misconception ``key``: its label and its teaching sentence."""
    return CATALOGUE[key].say(**fields)


def detect(key: str, *args: Any) -> Any:
    """What the detector of ``key`` finds in ``args``: falsy when the mistake is not there, else True or
    a dict of the fields its sentence names."""
    try:
        return CATALOGUE[key].detector(*args)
    except Exception:  # a learner's value of another kind: the mistake is not this one
        return None


def diagnose(keys: str | tuple[str, ...] | list[str], *args: Any) -> str | None:
    """The verdict of the first misconception among ``keys`` whose detector fits ``args``, or None."""
    for key in (keys,) if isinstance(keys, str) else keys:
        found = detect(key, *args)
        if found:
            return name(key, **found) if isinstance(found, dict) else name(key)
    return None


# --- small helpers the detectors share -----------------------------------------------------------------

def _int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _bytes(value: Any) -> bool:
    return isinstance(value, (bytes, bytearray))


def _near(got: float, expected: float, tolerance: float = 0.0) -> bool:
    return abs(got - expected) <= max(tolerance, 2e-3 * abs(expected), 1e-12)


def _same_time(got: Any, other: Any) -> bool:
    """The learner's number is (near) ``other``, the time a slip gives."""
    return _number(got) and _number(other) and _near(got, other)


def _swap16(value: int) -> int:
    return (value & 0xFF) << 8 | (value >> 8) & 0xFF


# --- checksums -----------------------------------------------------------------------------------------

@_entry("crc-swapped", "swapped CRC bytes", "got, expected: an RTU frame or the CRC's two wire bytes "
        "(bytes), or the CRC register (int)",
        "on the wire the CRC's low byte goes first, then its high byte; the CRC value itself (the "
        "register, e.g. 0x4B37) is never swapped, only sent low byte first (37 4B).")
def _crc_swapped(got: Any, expected: Any) -> bool:
    if _int(got) and _int(expected):
        return got != expected and 0 <= expected <= 0xFFFF and got == _swap16(expected)
    got, expected = bytes(got), bytes(expected)
    return (len(got) == len(expected) >= 2 and got != expected
            and got == expected[:-2] + expected[-2:][::-1])


@_entry("crc-on-tcp", "a CRC on Modbus/TCP", "got, expected: a Modbus/TCP frame (bytes)",
        "a Modbus/TCP frame carries no CRC, because TCP checks every byte itself; it is the MBAP header and "
        "the PDU, nothing after.")
def _crc_on_tcp(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(got) == len(expected) + 2 and got[:4] == expected[:4] and got[6:-2] == expected[6:]


@_entry("crc-initial-zero", "a CRC register started at 0", "data (bytes), got: the learner's CRC (int)",
        "that is CRC-16/ARC, the same polynomial with its register started at 0x0000; Modbus starts the "
        "register at 0xFFFF.")
def _crc_initial_zero(data: Any, got: Any) -> bool:
    return _int(got) and got == crc16_reflected(bytes(data), initial=0) != crc16(bytes(data))


def reflected(value: int, width: int) -> int:
    """``value``'s lowest ``width`` bits in reverse order."""
    return int(f"{value:0{width}b}"[::-1], 2)


def crc16_reflected(data: bytes, initial: int = 0xFFFF) -> int:
    """The reflected CRC-16 (polynomial 0xA001) bit by bit, from any starting register: 0xFFFF is
    CRC-16/MODBUS, 0 is CRC-16/ARC (the slip checkers name)."""
    register = initial
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register


def crc16_unreflected(data: bytes) -> int:
    """The CRC a learner gets shifting left with 0x8005 from 0xFFFF (most significant bit first)."""
    register = 0xFFFF
    for byte in data:
        register ^= byte << 8
        for _ in range(8):
            register = ((register << 1) ^ 0x8005) & 0xFFFF if register & 0x8000 else (register << 1) & 0xFFFF
    return register


@_entry("crc-msb-first", "an unreflected CRC", "data (bytes), got: the learner's CRC (int)",
        "shifting left with the polynomial 0x8005 (most significant bit first) is another CRC; Modbus's CRC "
        "is reflected: shift right and XOR with 0xA001, 0x8005's bits reversed.")
def _crc_msb_first(data: Any, got: Any) -> bool:
    register = crc16_unreflected(bytes(data))
    return _int(got) and got in (register, reflected(register, 16)) and got != crc16(bytes(data))


@_entry("crc-as-bytes", "a CRC returned as bytes", "got: what the learner's CRC function returns",
        "return the CRC register as an int (e.g. 0x4B37); the library turns it into the two wire bytes.")
def _crc_as_bytes(got: Any) -> bool:
    return _bytes(got)


@_entry("lrc-ones-complement", "one's complement for the LRC", "data (bytes), got: the learner's LRC (int)",
        "the LRC is the two's complement of the 8-bit sum of the bytes: invert every bit and add 1; "
        "inverting the bits alone is one less.")
def _lrc_ones(data: Any, got: Any) -> bool:
    return _int(got) and got == (~sum(bytes(data))) & 0xFF != lrc(bytes(data))


@_entry("lrc-plain-sum", "the plain sum for the LRC", "data (bytes), got: the learner's LRC (int)",
        "the 8-bit sum is only the first step; the LRC is its two's complement, so that the sum of the bytes "
        "and the LRC is 0 (modulo 256).")
def _lrc_sum(data: Any, got: Any) -> bool:
    return _int(got) and got == sum(bytes(data)) & 0xFF != lrc(bytes(data))


@_entry("lrc-of-characters", "an LRC over the hex characters", "data (bytes), got: the learner's LRC (int)",
        "the LRC adds the bytes the hex characters stand for (0x11, 0x03, ...), not the ASCII characters "
        "'1', '1', '0', '3' that carry them.")
def _lrc_characters(data: Any, got: Any) -> bool:
    return _int(got) and got == lrc(bytes(data).hex().upper().encode("ascii")) != lrc(bytes(data))


# --- addresses and tables ------------------------------------------------------------------------------

REFERENCE_OFFSETS = (1, 10000, 10001, 30000, 30001, 40000, 40001, 100000, 100001, 300000, 300001, 400000,
                     400001)


@_entry("one-based-address", "a 1-based address", "got, expected: addresses on the wire (int)",
        "the address on the wire counts from 0: the first register (number 1 in a datasheet) is address 0, "
        "so subtract 1.")
def _one_based(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected + 1


@_entry("reference-number", "a reference number for an address", "got, expected: addresses on the wire "
        "(int)",
        "the table's digit (4xxxx holding registers, 3xxxx input registers) never travels in the frame, "
        "the function code names the table; the address is the number after that digit, minus 1.")
def _reference(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got - expected in REFERENCE_OFFSETS[1:]


@_entry("zero-based-number", "a reference number counted from 0", "got, expected: reference numbers (int)",
        "a reference number counts from 1: address 0 is 40001 (or 30001), so the number is the address plus "
        "1.")
def _zero_based_number(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 1


@_entry("table-2x", "a 2x table", "text: a reference number whose table digit is 2; got: not an exception",
        "there is no 2x table: the prefixes are 0x coils, 1x discrete inputs, 3x input registers and 4x "
        "holding registers, so a number starting with 2 is refused.")
def _table_2x(text: Any, got: Any = None) -> bool:
    return isinstance(text, str) and text[:1] == "2"


@_entry("holding-for-input", "holding and input registers confused", "got, expected: function codes or "
        "table names",
        "function 3 reads the holding registers (4xxxx, read-write), function 4 the input registers "
        "(3xxxx, read-only).")
def _holding_for_input(got: Any, expected: Any) -> bool:
    pairs = ({3, 4}, {"holding_registers", "input_registers"})
    return got != expected and {got, expected} in pairs


@_entry("range-one-end", "a range counted without one end", "got, expected: counts of registers (int), "
        "ranges first..last",
        "a range from 10 to 19 holds 19 - 10 + 1 = 10 registers: count both ends.")
def _range_one_end(got: Any, expected: Any, ranges: int = 1) -> bool:
    return _int(got) and _int(expected) and got == expected - ranges


# --- time, units and scale -----------------------------------------------------------------------------

@_entry("seconds-for-milliseconds", "seconds for milliseconds", "got, expected: a time, expected in ms",
        "the question asks for milliseconds: 0.5 s is 500 ms, multiply by 1000.")
def _s_for_ms(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and got != expected and _near(got * 1000, expected)


@_entry("milliseconds-for-seconds", "milliseconds for seconds", "got, expected: a time, expected in s",
        "the question asks for seconds: 500 ms is 0.5 s, divide by 1000.")
def _ms_for_s(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and got != expected and _near(got / 1000, expected)


@_entry("fraction-for-percentage", "a fraction for a percentage", "got, expected: a share, expected in %",
        "the question asks for a percentage: a fraction of 0.6 is 60 %.")
def _fraction_for_percentage(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and got != expected and _near(got * 100, expected)


@_entry("percentage-for-fraction", "a percentage for a fraction", "got, expected: a share, expected as a "
        "fraction 0..1",
        "the question asks for a fraction between 0 and 1: 60 % is 0.6.")
def _percentage_for_fraction(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and got != expected and _near(got / 100, expected)


@_entry("time-for-rate", "a time for a rate", "got: a number; expected: a rate (per second)",
        "the question asks how many fit in one second, which is 1 divided by the time one takes.")
def _time_for_rate(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and expected > 0 and _near(got, 1 / expected)


@_entry("raw-for-scaled", "the raw value for the scaled one", "got, raw, scaled: numbers",
        "a register carries a whole number; the register map's scale turns it into the quantity (V x 10: "
        "divide by 10).")
def _raw_for_scaled(got: Any, raw: Any, scaled: Any) -> bool:
    return _number(got) and _near(got, raw) and not _near(raw, scaled)


@_entry("milliamperes-for-amperes", "milliamperes for amperes", "got, expected: a current, expected in A",
        "the registers carry milliamperes; the question asks for amperes: divide by 1000.")
def _ma_for_a(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and _near(got, expected * 1000)


@_entry("current-not-in-milliamperes", "a current not in milliamperes", "got: the number the learner "
        "stored; amperes: the current",
        "this device sends the current in milliamperes, as a whole number: 12.5 A is 12 500 mA.")
def _not_ma(got: Any, amperes: Any) -> bool:
    return _int(got) and any(got == round(amperes * scale) for scale in (1, 10, 100))


# --- serial timing -------------------------------------------------------------------------------------

@_entry("silences-forgotten", "the silences forgotten", "got, without: a time, and the same time without "
        "the two silences",
        "a transaction is request + silence + the slave's processing time + response + silence, where each "
        "silence is 3.5 character times (at 19200 baud or below; 1.75 ms above). The course's slave answers "
        "at once: request + 3.5 + response + 3.5 characters.")
def _silences(got: Any, without: Any) -> bool:
    return _same_time(got, without)


@_entry("parity-bit-forgotten", "10 bits for a character with parity", "got, ten_bits: a time, and the same "
        "time with 10-bit characters",
        "a character is a start bit, 8 data bits, the parity bit when there is one, and the stop bits: 8E1 "
        "makes 11 bits, not 10.")
def _parity(got: Any, ten_bits: Any) -> bool:
    return _same_time(got, ten_bits)


@_entry("fixed-silence-ignored", "3.5 characters above 19200 baud", "got, scaled: a time, and the same "
        "time with 3.5-character silences above 19200 baud",
        "above 19200 baud the specification recommends a fixed silence of 1.75 ms (and 0.75 ms for 1.5 "
        "characters) instead of 3.5 character times, and the course's line uses it.")
def _fixed_silence(got: Any, scaled: Any) -> bool:
    return _same_time(got, scaled)


@_entry("t15-forgotten", "only 3.5 characters break a frame", "got, expected: the pauses (in characters) "
        "that leave a frame unanswered",
        "inside an RTU frame a pause of more than 1.5 character times (at 19200 baud or below; 0.75 ms "
        "above) already breaks it (the slave drops it); 3.5 character times or more (1.75 ms above 19200 "
        "baud) cut it in two.")
def _t15(got: Any, expected: Any) -> bool:
    got, expected = sorted(got), sorted(expected)
    return got != expected and got == [p for p in expected if p >= 3.5]


@_entry("one-character-for-t35", "one character time for t3.5", "got, char_time: seconds",
        "the silence that ends a frame is 3.5 character times at 19200 baud or below (1.75 ms above), not "
        "one.")
def _one_char(got: Any, char_time: Any) -> bool:
    return _same_time(got, char_time)


@_entry("t15-for-t35", "t1.5 for t3.5", "got, char_time: seconds",
        "a pause of more than 1.5 character times inside a frame breaks that frame (the slave drops it); "
        "only a silence of 3.5 character times ends a frame (at 19200 baud or below; 0.75 ms and 1.75 ms "
        "above).")
def _t15_for_t35(got: Any, char_time: Any) -> bool:
    return _number(char_time) and _same_time(got, 1.5 * char_time)


@_entry("crlf-for-frame-end", "CR LF at the end of a frame that has none", "got, expected: an RTU or "
        "Modbus/TCP frame (bytes)",
        "only an ASCII frame ends with CR LF; an RTU frame ends with its CRC and a silence, a Modbus/TCP "
        "frame with the PDU's last byte (the MBAP length says where).")
def _crlf_end(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return not expected.startswith(b":") and got == expected + b"\r\n"


# --- Modbus/TCP ----------------------------------------------------------------------------------------

@_entry("mbap-little-endian", "a little-endian MBAP field", "got, expected: an MBAP header or frame, or one "
        "2-byte field (bytes), or one field's value (int)",
        "every MBAP field (transaction id, protocol id, length) goes high byte first: transaction id 5 is "
        "00 05, and the bytes 05 00 read as 1280.")
def _mbap_little(got: Any, expected: Any) -> bool:
    if _int(got) and _int(expected):
        return got != expected and 0 <= expected <= 0xFFFF and got == _swap16(expected)
    got, expected = bytes(got), bytes(expected)
    if len(got) != len(expected) or len(got) < 2 or got == expected or got[6:] != expected[6:]:
        return False
    return all(got[i:i + 2] in (expected[i:i + 2], expected[i:i + 2][::-1]) for i in range(0, 6, 2))


@_entry("mbap-length", "an MBAP length that counts the wrong bytes", "got, expected: the length field's "
        "value (int)",
        "the length counts the bytes that follow it: the unit identifier (1 byte) and the PDU, nothing "
        "before.")
def _mbap_length(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got in (expected - 1, expected + 6, expected + 5)


@_entry("unit-in-pdu", "the unit identifier in the PDU", "got, expected: a PDU (bytes), unit: int",
        "the unit identifier (or an RTU frame's slave address) belongs to the envelope; the PDU starts with "
        "the function code.")
def _unit_in_pdu(got: Any, expected: Any, unit: Any) -> bool:
    return bytes(got) == bytes([unit]) + bytes(expected)


@_entry("frame-for-pdu", "a whole frame for a PDU", "got, expected: a PDU (bytes)",
        "the PDU is only the function code and its data, without the unit, the MBAP header or the checksum "
        "around it.")
def _frame_for_pdu(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return got != expected and len(got) > len(expected) and expected in got


# --- frames and PDUs -----------------------------------------------------------------------------------

@_entry("ascii-without-crlf", "an ASCII frame without CR LF", "got, expected: an ASCII frame (bytes)",
        "an ASCII frame starts with ':' and ends with the two characters CR LF (b'\\r\\n'); without them the "
        "slave never sees the frame end.")
def _ascii_crlf(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return expected.endswith(b"\r\n") and got.upper() == expected[:-2].upper()


@_entry("echo-unchecked", "an echo cut off unchecked", "sent, received: the request and the bytes read "
        "back; got: what the learner's function kept",
        "an echoing adapter gives the request back first: drop those bytes only once they are exactly the "
        "request; a missing or damaged echo means the adapter or the line is at fault, so raise an error.")
def _echo_unchecked(sent: Any, received: Any, got: Any) -> bool:
    sent, received = bytes(sent), bytes(received)
    return _bytes(got) and bytes(got) == received[len(sent):] and received[:len(sent)] != sent


@_entry("first-address-only", "a multiple write judged by its first address", "pdu: a write-multiple "
        "request PDU (bytes), limit: the last address allowed, got: the learner's verdict (None: allowed)",
        "a write of N registers from address A touches A to A + N - 1: a rule about addresses holds for the "
        "last one too, so read the quantity (bytes 3-4) and check A + N - 1.")
def _first_address_only(pdu: Any, limit: int, got: Any) -> bool:
    pdu = bytes(pdu)
    if got is not None or pdu[0] not in (15, 16):
        return False
    address, quantity = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
    return address <= limit < address + quantity - 1


@_entry("crc-forgotten", "a frame without its CRC", "got, expected: frame lengths (int)",
        "an RTU frame ends with its two CRC bytes.")
def _crc_forgotten(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 2


@_entry("register-one-byte", "a register of one byte", "got, expected: byte counts (int); registers: int",
        "a register is 16 bits: two bytes on the wire, high byte first.")
def _register_one_byte(got: Any, expected: Any, registers: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - registers


@_entry("byte-count-missing", "the byte count left out", "got, expected: a write-multiple PDU (bytes), the "
        "byte count at index 5",
        "a write of several registers or coils carries, after the quantity, one byte counting the data "
        "bytes that follow.")
def _byte_count(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(got) == len(expected) - 1 and got[:5] == expected[:5] and got[5:] == expected[6:]


@_entry("exception-bit-missing", "an exception without its top bit", "got, expected: function-code bytes "
        "(int) of an exception response",
        "an exception response sets the top bit of the function code (function + 0x80: 03 becomes 83); that "
        "bit is what marks it as an exception.")
def _exception_bit(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and expected & 0x80 and got == expected & 0x7F


@_entry("exception-code-as-function", "the response's function code for the request's", "got, expected: "
        "function codes (int)",
        "an exception response's function code is the request's plus 0x80; the request's function is that "
        "byte minus 0x80.")
def _exception_as_function(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected | 0x80 and got != expected


@_entry("illegal-function-for-address", "exception 01 for a missing address", "got, expected: exception "
        "codes (int)",
        "01 (illegal function) means the slave will not carry out this function: it does not implement it, "
        "or not in its present state, or (Modbus/TCP Security) not for your role; a coil or register it "
        "does not have is 02 (illegal data address).")
def _illegal_function(got: Any, expected: Any) -> bool:
    return got == 1 and expected == 2


@_entry("bits-from-the-left", "bits read from the left", "got, expected: lists of the bits that are on "
        "(addresses)",
        "in a read-bits response the first coil is the least significant (rightmost) bit of the first data "
        "byte.")
def _bits_left(got: Any, expected: Any) -> bool:
    return sorted(got) == sorted(7 - a for a in expected) != sorted(expected)


@_entry("hex-read-as-decimal", "hex digits read as decimal", "got: int, text: the hex byte as written",
        "the bytes of a frame are written in hexadecimal: 11 is 0x11 = 17, int('11', 16).")
def _hex_as_decimal(got: Any, text: Any) -> bool:
    return _int(got) and got == int(text) != int(text, 16)


def _hex_form(value: int, width: int) -> str:
    return f"0x{value:0{width}X}"


@_entry("decimal-written-as-hex", "a decimal number written as hex digits", "got, expected: one field of "
        "one or two bytes (int)",
        "{decimal} is a decimal number: in hex it is {right} (hex({decimal})), while {written} is "
        "{written_value}.")
def _decimal_as_hex(got: Any, expected: Any) -> dict | None:
    if not (_int(got) and _int(expected) and 0 <= expected and got == int(str(expected), 16) != expected):
        return None
    width = 2 if max(got, expected) <= 0xFF else 4
    return {"decimal": expected, "right": _hex_form(expected, width), "written": _hex_form(got, width),
            "written_value": got}


@_entry("field-low-byte-first", "a 16-bit field low byte first", "got, expected: one 2-byte field (int)",
        "an address, a quantity or a register value goes high byte first: {right} is {right_bytes}, and "
        "{written_bytes} reads as {written}; only an RTU frame's CRC goes low byte first.")
def _field_low_first(got: Any, expected: Any) -> dict | None:
    if not (_int(got) and _int(expected) and 0 <= expected <= 0xFFFF):
        return None
    if got != _swap16(expected) or got == expected:
        return None
    return {"right": f"{expected} (0x{expected:04X})", "written": f"{got} (0x{got:04X})",
            "right_bytes": f"{expected >> 8:02X} {expected & 0xFF:02X}",
            "written_bytes": f"{got >> 8:02X} {got & 0xFF:02X}"}


FRAME_SLIPS = ("decimal-written-as-hex", "field-low-byte-first")
"""The slips :func:`frame_slip` looks for in a frame the learner built byte by byte."""


def _windows(start: int, end: int, limit: int) -> list[list[tuple[int, int]]]:
    """Ways to read the differing bytes ``start..end-1`` as fields of one or two bytes (within ``limit``)."""
    length = end - start
    if length == 1:
        spans = [[(start, start + 1)], [(start - 1, start + 1)], [(start, start + 2)]]
    else:
        spans = [[(i, min(i + 2, end)) for i in range(start, end, 2)]]
    return [span for span in spans if all(0 <= a < b <= limit for a, b in span)]


def frame_slip(got: Any, expected: Any, tail: int = 0, keys: tuple[str, ...] = FRAME_SLIPS) -> str | None:
    """Name the slip that explains every byte where a frame the learner built differs from the right one.

    ``got`` and ``expected`` are frames of the same length; the last ``tail`` bytes (an RTU frame's CRC,
    which follows whatever came before) are left out.  Each run of differing bytes is read as a field of
    one or two bytes, high byte first; a slip of ``keys`` that explains every run is named, with the
    first field's numbers: a value written in decimal digits as hex (500 as ``05 00``), a field low byte
    first (500 as ``F4 01``).  None when no one slip explains them all.
    """
    if not (_bytes(got) and _bytes(expected)) or len(got) != len(expected) or got == expected:
        return None
    limit = len(expected) - tail
    differ = [i for i in range(limit) if got[i] != expected[i]]
    if not differ:
        return None
    runs: list[list[int]] = []
    for i in differ:
        if runs and i == runs[-1][1]:
            runs[-1][1] = i + 1
        else:
            runs.append([i, i + 1])
    for key in keys:
        fields = []
        for start, end in runs:
            for span in _windows(start, end, limit):
                found = [detect(key, int.from_bytes(got[a:b], "big"), int.from_bytes(expected[a:b], "big"))
                         for a, b in span]
                if all(found):
                    fields.append(found[0])
                    break
            else:
                break
        else:
            return name(key, **fields[0])
    return None


@_entry("answer-to-damaged-request", "an answer to a damaged request", "got, expected: what the master "
        "sees (str), or whether the slave answers (bool)",
        "a slave that receives a request with a wrong CRC (or a broken frame) cannot trust any of its bytes, "
        "not even its own address in them, and says nothing: the master sees a timeout, not a frame it "
        "could check.")
def _damaged_request(got: Any, expected: Any) -> bool:
    return (got, expected) in (("checksum error", "timeout"), ("exception", "timeout"), (True, False))


@_entry("answer-to-another-unit", "an answer to a request for another unit", "got, expected: what the "
        "master sees (str) of a request for a unit no slave has",
        "a slave answers only requests for its own address: a sound frame for another unit is simply not "
        "its business, so it stays silent; with no slave of that address the master "
        "sees a timeout.")
def _another_unit(got: Any, expected: Any) -> bool:
    return expected == "timeout" and got in ("exception", "checksum error", "valid", "mismatch")


@_entry("refusal-unanswered", "a refusal without an exception response", "got, expected: what the "
        "master sees (str) of a valid request the slave cannot carry out",
        "a slave that receives a sound request for itself and cannot carry it out answers with an "
        "exception response saying why (02 for an address it does not have); it neither stays silent nor "
        "makes data up.")
def _refusal_unanswered(got: Any, expected: Any) -> bool:
    return expected == "exception" and got in ("timeout", "valid")


@_entry("write-not-stored", "a write echoed but not stored", "a build exercise's read-back: the register "
        "read after a write",
        "a slave must store what FC 6 writes; the echo only confirms it, and the next read gives the new "
        "value.")
def _write_not_stored(read_back: Any, old: Any, new: Any) -> bool:
    return read_back == old != new


@_entry("one-register-for-32-bits", "one register for a 32-bit value", "got, expected: register counts "
        "(int); values: how many 32-bit values",
        "a 32-bit value (uint32, float32) takes two 16-bit registers: count registers, not values.")
def _one_register(got: Any, expected: Any, values: Any = 1) -> bool:
    return _int(got) and got == values and expected == 2 * values


# --- values across registers ---------------------------------------------------------------------------

ORDER_WORDS = {"ABCD": "high word first", "CDAB": "low word first", "BADC": "high word first, bytes swapped "
               "in each register", "DCBA": "low word first, bytes swapped in each register"}


@_entry("word-order", "the wrong word order", "registers, dtype, value: registers that carry value in "
        "the order(s) right",
        "read in {used} order ({used_words}) these registers give a value the device did not send; its "
        "value comes out in {right}. Try the orders of mb.ORDERS: keep the one that gives a value the device "
        "could measure.")
def _word_order(registers: Any, dtype: str, value: Any, right: Any) -> dict | None:
    rights = {right} if isinstance(right, str) else set(right)
    for order in ORDERS:
        if order in rights:
            continue
        got = decode_value(list(registers), dtype, order)
        if _number(got) and _number(value) and (got == value or math.isclose(got, value, rel_tol=1e-6)):
            return {"used": order, "used_words": ORDER_WORDS[order], "right": " or ".join(sorted(rights))}
    return None


@_entry("mask-write-or", "the OR mask over the whole register", "current, and_mask, or_mask, got: ints",
        "FC 22 keeps the bits where the AND mask has 1 and takes the OR mask's bits only where the AND "
        "mask has 0: an OR mask bit never reaches a place where the AND mask has 1.")
def _mask_or(current: Any, and_mask: Any, or_mask: Any, got: Any) -> bool:
    return _int(got) and got in ((current & and_mask) | or_mask, current | or_mask) and \
        got != mask_write(current, and_mask, or_mask)
