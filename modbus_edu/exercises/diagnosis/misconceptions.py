"""The catalogue of misconceptions: the mistakes learners make about Modbus, each named one way.

Every checker that can recognise a mistake asks this catalogue for it, so that the same mistake reads the
same in every notebook: a CRC whose two bytes are the wrong way round is "swapped CRC bytes" whether the
learner built a frame (03.2), corrected one (13.5) or wrote a function that returns the CRC (03.5).

An entry has a key (``"crc-swapped"``), a label (the name a learner reads), the shape of what its
detector reads, a teaching sentence (which may name the learner's case: ``{used}``) and a detector.
:func:`name` gives the verdict's words; :func:`detect` runs one detector; :func:`diagnose` tries several
and names the first that fits.  Detectors never raise: a value of the wrong kind simply does not fit.

The machinery lives in :mod:`.catalogue`; this module holds the entries about checksums, addresses,
units, serial timing, Modbus/TCP, frames and values, and imports :mod:`.misconceptions_counting` (counts,
rates, ports, responses, masks, tables) at its end so that every entry is registered once it is imported.
"""

from __future__ import annotations

import math
from typing import Any

from ...crc import crc16, crc_bytes, lrc
from ...pdu import mask_write
from ...values import ORDERS, decode_value

# The catalogue's machinery, re-exported: checkers import CATALOGUE, diagnose and name from here.
from .catalogue import (  # noqa: F401
    CATALOGUE,
    Misconception,
    _bytes,
    _entry,
    _int,
    _near,
    _number,
    _same_time,
    _swap16,
    detect,
    diagnose,
    name,
)

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


def crc16_reflected(data: bytes, initial: int = 0xFFFF, poly: int = 0xA001) -> int:
    """The reflected CRC-16 (polynomial 0xA001) bit by bit, from any starting register: 0xFFFF is
    CRC-16/MODBUS, 0 is CRC-16/ARC (the slip checkers name); ``poly=0x8005`` shifts right with the
    polynomial as written, not reflected (another slip)."""
    register = initial
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ poly if register & 1 else register >> 1
    return register


def crc16_unreflected(data: bytes) -> int:
    """The CRC a learner gets shifting left with 0x8005 from 0xFFFF (most significant bit first)."""
    register = 0xFFFF
    for byte in data:
        register ^= byte << 8
        for _ in range(8):
            register = ((register << 1) ^ 0x8005) & 0xFFFF if register & 0x8000 else (register << 1) & 0xFFFF
    return register


def crc_bit_loop(data: bytes, shifts: int = 8, test_after: bool = False, limit: int | None = None) -> int:
    """CRC-16/MODBUS with its bit loop changed as a learner's slip changes it: ``shifts`` shifts a byte, the
    bit tested after the shift (``test_after``), only the first ``limit`` bytes."""
    register = 0xFFFF
    for byte in bytes(data)[:limit]:
        register ^= byte
        for _ in range(shifts):
            if test_after:
                register >>= 1
                register = register ^ 0xA001 if register & 1 else register
            else:
                register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register


# --- the CRC's own loop (steps of the CRC procedure, :mod:`.crcsteps`) ------------------------------------

@_entry("crc-bit-loop", "the CRC's bit loop changed", "data (bytes), got: the learner's CRC (int)",
        "after each byte is XORed into the register's low byte come exactly 8 steps: test the lowest bit, "
        "shift right by one, and XOR with 0xA001 when the bit tested was 1.")
def _crc_bit_loop(data: Any, got: Any) -> bool:
    return _int(got) and got != crc_bit_loop(data) and got in (
        crc_bit_loop(data, shifts=7), crc_bit_loop(data, shifts=9), crc_bit_loop(data, test_after=True))


@_entry("crc-not-every-byte", "not every byte in the CRC", "data (bytes), got: the learner's CRC (int)",
        "the CRC runs over every byte of the data, whatever its length: the loop neither stops one byte "
        "early nor stops at a frame's 256 bytes: data of more than 256 bytes has its CRC too.")
def _crc_not_every_byte(data: Any, got: Any) -> bool:
    data = bytes(data)
    return _int(got) and any(got == crc16(data[:end]) != crc16(data) for end in (len(data) - 1, 255, 256)
                             if 0 <= end < len(data))


@_entry("crc-msb-first", "an unreflected CRC", "data (bytes), got: the learner's CRC (int)",
        "the polynomial 0x8005 as written (shifting left, most significant bit first) gives another CRC; "
        "Modbus's CRC is reflected: shift right and XOR with 0xA001, 0x8005's bits reversed.")
def _crc_msb_first(data: Any, got: Any) -> bool:
    register = crc16_unreflected(bytes(data))
    wrong = (register, reflected(register, 16), crc16_reflected(bytes(data), poly=0x8005))
    return _int(got) and got in wrong and got != crc16(bytes(data))


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


@_entry("address-one-too-low", "1 subtracted twice", "got, expected: addresses on the wire (int)",
        "the address is the number after the table digit minus 1, subtracted once: 40021 is address 20; "
        "one less is the register before it.")
def _address_one_too_low(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 1 >= -1


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


@_entry("truncated-not-rounded", "decimals cut off instead of rounded", "got, expected: numbers; "
        "decimals: how many the question asks for",
        "to give {places}, round to the nearest: {exact} becomes {right} (round(x, {decimals})); cutting the "
        "other digits off gives {got}.")
def _truncated(got: Any, expected: Any, decimals: int) -> dict | None:
    if not (_number(got) and _number(expected)):
        return None
    scale = 10 ** decimals
    cut, right = math.trunc(expected * scale) / scale, round(expected, decimals)
    if cut == right or abs(got - cut) > 1e-9 or abs(got - right) < 1e-9:
        return None
    places = f"{decimals} decimal" + "s" * (decimals != 1)
    return {"places": places, "decimals": decimals, "exact": f"{expected:.{decimals + 2}f}",
            "right": f"{right:.{decimals}f}", "got": f"{cut:.{decimals}f}"}


@_entry("float-compared-exactly", "floats compared with ==", "got: the learner's result, None; near: the "
        "values that are close but not equal",
        "a float32 keeps about 7 significant digits, so the registers give {near}, a hair away from the "
        "value asked: compare floats with a tolerance, math.isclose(a, b, rel_tol=1e-6), never with ==.")
def _float_exactly(got: Any, near: Any) -> dict | None:
    if got is not None or not _number(near):
        return None
    return {"near": repr(near)}


@_entry("time-for-rate", "a time for a rate", "got: a number; expected: a rate (per second)",
        "the question asks how many fit in one second, which is 1 divided by the time one takes.")
def _time_for_rate(got: Any, expected: Any) -> bool:
    return _number(got) and _number(expected) and expected > 0 and _near(got, 1 / expected)


@_entry("raw-for-scaled", "the raw value for the scaled one", "got, raw, scaled: numbers",
        "a register carries a whole number; the register map's scale turns it into the quantity (V x 10: "
        "divide by 10).")
def _raw_for_scaled(got: Any, raw: Any, scaled: Any) -> bool:
    return _number(got) and _near(got, raw) and not _near(raw, scaled)


@_entry("scale-wrong", "the wrong scale", "got, raw, scaled: numbers",
        "divide the register's whole number by the scale the register map gives (tenths: by 10; mA to A: by "
        "1000), not by another power of ten.")
def _scale_wrong(got: Any, raw: Any, scaled: Any) -> bool:
    return (_number(got) and _number(raw) and not _near(got, scaled) and not _near(got, raw)
            and any(_near(got * 10 ** k, raw) for k in range(1, 6)))


@_entry("fraction-unclamped", "a fraction outside 0..1", "got: a share the learner computed",
        "a share of requests answered stays between 0 and 1: clamp it with max(0.0, min(1.0, x)).")
def _fraction_unclamped(got: Any) -> bool:
    return _number(got) and not 0 <= got <= 1


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


@_entry("mbap-length-missing", "an MBAP header without its length", "got, expected: a Modbus/TCP frame "
        "or MBAP header (bytes)",
        "the MBAP header is 7 bytes: transaction id (2), protocol id (2), the length (2 bytes, high byte "
        "first), then the unit; the length field is never left out, even when the receiver could count.")
def _mbap_length_missing(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(expected) >= 7 and got in (expected[:4] + expected[6:], expected[:4] + expected[5:])


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
    return _bytes(got) and received[:len(sent)] != sent


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


@_entry("function-code-missing", "a PDU without its function code", "got, expected: a PDU (bytes)",
        "a PDU starts with the function code (03, 10, 83 ...); its data follows it.")
def _function_code_missing(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    return len(expected) >= 2 and got == expected[1:]


@_entry("top-bit-on-code", "the top bit set on the exception code", "got, expected: exception codes (int)",
        "only the function code gets the top bit (function + 0x80); the exception code after it stays as it "
        "is: 02, not 82.")
def _top_bit_on_code(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and expected < 0x80 and got == expected | 0x80


@_entry("crc-forgotten", "a frame without its CRC", "got, expected: frame lengths (int)",
        "an RTU frame ends with its two CRC bytes.")
def _crc_forgotten(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected - 2


@_entry("checksum-without-address", "a checksum without the address", "got, expected: an RTU frame or the "
        "bytes an ASCII frame's characters stand for (bytes)",
        "the CRC (or the LRC) covers every byte before it, the slave address included, not the PDU alone.")
def _checksum_without_address(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    if len(got) != len(expected) or got == expected or len(expected) < 4:
        return False
    return got in (expected[:-2] + crc_bytes(expected[1:-2]), expected[:-1] + bytes([lrc(expected[1:-1])]))


@_entry("byte-count-for-quantity", "the byte count for the quantity", "got, expected: a write-multiple "
        "request PDU (bytes)",
        "the quantity (bytes 3-4) counts registers or coils, the byte count after it counts data bytes: two "
        "registers are a quantity of 2 and a byte count of 4.")
def _byte_count_for_quantity(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    if len(got) != len(expected) or len(expected) < 6 or expected[0] not in (15, 16) or got == expected:
        return False
    quantity, count = int.from_bytes(expected[3:5], "big"), expected[5]
    pairs = ((count, count), (quantity, quantity), (count, quantity))
    fields = (int.from_bytes(got[3:5], "big"), got[5])
    return got[:3] == expected[:3] and got[6:] == expected[6:] and fields in pairs


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


@_entry("exception-code-confused", "another exception code", "got, expected: exception codes (int)",
        "the code says why: 01 illegal function, 02 illegal data address (no such address), 03 illegal "
        "data value (the request's structure is not allowed, such as its quantity; not a value the "
        "application rejects), 04 slave device failure.")
def _exception_code_confused(got: Any, expected: Any) -> bool:
    return (_int(got) and _int(expected) and got != expected and 1 <= got <= 11 and 1 <= expected <= 11
            and (got, expected) != (1, 2))


@_entry("unit-missing", "a frame without its slave address", "got, expected: an RTU frame or a Modbus/TCP "
        "frame (bytes)",
        "the slave address (the unit identifier) comes before the PDU in every frame; without it the "
        "function code is read as the address.")
def _unit_missing(got: Any, expected: Any) -> bool:
    got, expected = bytes(got), bytes(expected)
    if len(got) != len(expected) - 1 or len(expected) < 4:
        return False
    return got[:-2] == expected[1:-2] or (len(expected) > 8 and got == expected[:6] + expected[7:])


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


@_entry("hex-read-as-decimal", "hex digits read as decimal", "got: int, text: the hex digits as written "
        "(str), or the field's value (int: its hex digits are what the learner read)",
        "the bytes of a frame are written in hexadecimal: 11 is 0x11 = 17, int('11', 16).")
def _hex_as_decimal(got: Any, text: Any) -> bool | dict:
    if _int(text):
        if not (_int(got) and 0 <= text and got == int(f"{text:X}") != text):
            return False
        return {"value": text}
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


@_entry("another-field", "another field of the frame", "got: the learner's number; fields: the frame's "
        "other fields by name (int values)",
        "{got} is the {field}; each field has its place in the frame: count the bytes from its start, as the "
        "layout lists them.")
def _another_field(got: Any, fields: Any) -> dict | None:
    if not _int(got):
        return None
    return next(({"got": got, "field": field} for field, value in dict(fields).items() if value == got), None)


@_entry("count-rounded-down", "a count rounded down", "got: int; exact: the quotient (float)",
        "a part of a block still needs a whole request (or register): round the quotient up, "
        "-(-total // size) or math.ceil, never down.")
def _count_rounded_down(got: Any, exact: Any) -> bool:
    return _number(got) and _number(exact) and not float(exact).is_integer() and got in (
        math.floor(exact), exact)


@_entry("invalid-input-accepted", "an invalid input accepted", "got: what the function returned where the "
        "library raises",
        "a frame, a reference or a request the specification forbids must be refused: check it, and raise "
        "an error instead of returning a result built from it.")
def _invalid_accepted(got: Any) -> bool:
    return True


@_entry("exception-function-for-code", "the exception's function byte for its code", "got: int; function, "
        "code: the exception response's two bytes",
        "an exception response is two bytes: the function code + 0x80, then the exception code; the code is "
        "the second byte.")
def _exception_function_for_code(got: Any, function: Any, code: Any) -> bool:
    return _int(got) and _int(function) and got == function | 0x80 != code


@_entry("gateway-codes-swapped", "gateway exceptions 0A and 0B confused", "got, expected: exception codes",
        "0A (gateway path unavailable): the gateway has no way to that unit and asks nobody; 0B (gateway "
        "target device failed to respond): it asked the unit, and no answer came in its timeout.")
def _gateway_codes(got: Any, expected: Any) -> bool:
    return {got, expected} == {0x0A, 0x0B}


@_entry("gateway-silence", "a gateway that stays silent", "got, expected: what the client sees",
        "a gateway answers its client even when it cannot reach the slave: 0A with no path to it, 0B once "
        "its own timeout has passed; the client sees a timeout only if it gives up first.")
def _gateway_silence(got: Any, expected: Any) -> bool:
    return got == "timeout" and expected in (0x0A, 0x0B)


@_entry("damaged-message-counted", "a damaged message counted", "got, expected: message counts (int)",
        "a frame with a bad CRC is no message to a slave: it goes to the checksum-error counter (0x0C), "
        "never to the bus message count (0x0B).")
def _damaged_counted(got: Any, expected: Any) -> bool:
    return _int(got) and _int(expected) and got == expected + 1


@_entry("others-not-heard", "only its own messages counted", "got: a message count; own: the messages "
        "addressed to the node",
        "every node on an RS-485 line hears every frame, and the course's slave counts the requests for "
        "other units and their responses too (the specification leaves open what a device counts; notebook "
        "14's rule is the course slave's).")
def _others_not_heard(got: Any, own: Any) -> bool:
    return _int(got) and _int(own) and got == own


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
    return _int(got) and got in ((current & and_mask) | or_mask, current | or_mask,
                                 (current | or_mask) & and_mask) and \
        got != mask_write(current, and_mask, or_mask)


@_entry("mask-roles-swapped", "the AND and OR masks' roles swapped", "current, and_mask, or_mask, got: ints",
        "a 1 in the AND mask keeps the register's bit; where the AND mask has 0 the bit comes from the OR "
        "mask: (current & and_mask) | (or_mask & ~and_mask).")
def _mask_roles(current: Any, and_mask: Any, or_mask: Any, got: Any) -> bool:
    return _int(got) and got == ((current & ~and_mask) | (or_mask & and_mask)) & 0xFFFF != mask_write(
        current, and_mask, or_mask)


from . import misconceptions_counting  # noqa: E402,F401  (its entries register in CATALOGUE)
