"""The wrong functions a newcomer writes for the build exercises: :mod:`.slips` for functions.

Each is a :class:`~.slips.Slip` whose answer is a function as a learner writes it (plain Python, the
library's reference left alone): the slip in it is one a newcomer makes, and the misconception its
verdict must name (or None, with the reason no catalogued misconception applies).  Where a learner's
function refuses an input it raises the library's error, as the exercises' hints ask.
"""

from __future__ import annotations

import struct

from slips import Slip

from modbus_edu.crc import crc16, crc_bytes, lrc
from modbus_edu.errors import ModbusError
from modbus_edu.exercises.diagnosis.misconceptions import crc16_reflected
from modbus_edu.values import decode_value

_TABLES = {"0": "coils", "1": "discrete_inputs", "3": "input_registers", "4": "holding_registers"}


def _check_reference(text: str) -> int:
    number = int(text[1:])
    if not 1 <= number <= 9999 or text[0] not in _TABLES:
        raise ModbusError(f"{text} is no reference number")
    return number


def _reference_whole(text: str) -> tuple:
    """The whole reference number as the address."""
    _check_reference(text)
    return _TABLES[text[0]], int(text) - 1 if text[0] == "0" else int(text)


def _reference_tables_swapped(text: str) -> tuple:
    """3 and 4 mixed up: 4xxxx read as input registers."""
    number = _check_reference(text)
    swapped = {"3": "holding_registers", "4": "input_registers"}
    return swapped.get(text[0], _TABLES[text[0]]), number - 1


def _reference_modulo(text: str) -> tuple:
    """The number taken modulo 10000, never minus 1."""
    _check_reference(text)
    return _TABLES[text[0]], int(text) % 10000


def _reference_no_zero_check(text: str) -> tuple:
    """0000 not refused: 40000 gives address -1."""
    return _TABLES.get(text[0], "holding_registers"), int(text[1:]) - 1


def _reference_two_digit_prefix(text: str) -> tuple:
    """The prefix read as two digits (40108 as table 40, number 108)."""
    _check_reference(text)
    return _TABLES[text[0]], int(text[2:]) - 1


def _fc3_checked(address: int, count: int) -> None:
    if not 1 <= count <= 125 or address + count > 65536:
        raise ModbusError("a read of 1 to 125 registers within 0..65535")


def _fc3_little(address: int, count: int) -> bytes:
    _fc3_checked(address, count)
    return bytes([3]) + address.to_bytes(2, "little") + count.to_bytes(2, "little")


def _fc3_reference(address: int, count: int) -> bytes:
    _fc3_checked(address, count)
    return bytes([3]) + ((address + 40001) & 0xFFFF).to_bytes(2, "big") + count.to_bytes(2, "big")


def _fc3_unit(address: int, count: int) -> bytes:
    _fc3_checked(address, count)
    return bytes([1, 3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")


def _fc3_unchecked(address: int, count: int) -> bytes:
    return bytes([3]) + (address & 0xFFFF).to_bytes(2, "big") + (count & 0xFFFF).to_bytes(2, "big")


def _fc3_count_one_byte(address: int, count: int) -> bytes:
    _fc3_checked(address, count)
    return bytes([3]) + address.to_bytes(2, "big") + bytes([count])


def _handler(registers: list, pdu: bytes, *, bit: int = 0x80, missing: int = 2, per_register: int = 2,
             store: bool = True, one_based: bool = False) -> bytes:
    """A slave's handler for FC 3 and FC 6 with one slip (the keywords say which)."""
    function, address = pdu[0], int.from_bytes(pdu[1:3], "big") - one_based
    if function == 6:
        if not 0 <= address < len(registers):
            return bytes([function | bit, missing])
        if store:
            registers[address] = int.from_bytes(pdu[3:5], "big")
        return bytes(pdu)
    count = int.from_bytes(pdu[3:5], "big")
    if not 1 <= count <= 125:
        return bytes([function | bit, 3])
    if not 0 <= address or address + count > len(registers):
        return bytes([function | bit, missing])
    data = b"".join(value.to_bytes(2, "big") for value in registers[address:address + count])
    return bytes([3, count * per_register]) + data


def _crc_swapped_bytes(data: bytes) -> int:
    """The wire bytes read back as an int, high byte first."""
    return int.from_bytes(crc_bytes(data), "big")


def _crc_big_endian_bytes(data: bytes) -> bytes:
    return crc16(data).to_bytes(2, "big")


def _crc_zero_start(data: bytes) -> int:
    return crc16_reflected(data, initial=0)


def _crc_poly_unreflected_right(data: bytes) -> int:
    """Shifting right, as Modbus does, but with the polynomial as written, 0x8005."""
    register = 0xFFFF
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0x8005 if register & 1 else register >> 1
    return register


def _crc_low_byte(data: bytes) -> int:
    return crc16(data) & 0xFF


def _lrc_characters(data: bytes) -> int:
    return lrc(data.hex().upper().encode("ascii"))


def _mbap(tid: int, unit: int, length: bytes) -> bytes:
    return tid.to_bytes(2, "big") + b"\x00\x00" + length + bytes([unit])


def _transaction(baudrate, parity, stopbits, request, response, silences=2, bits=None, stop=None) -> float:
    bits = bits or 1 + 8 + (parity != "N") + (stop or stopbits)
    char = bits / baudrate
    silence = 0.00175 if baudrate > 19200 else 3.5 * char
    return (request + response) * char + silences * silence


def _answered_unclamped(loop_time: float, timeout: float, reply: float) -> float:
    return (timeout - reply) / loop_time


def _answered_top_only(loop_time: float, timeout: float, reply: float) -> float:
    return min(1.0, (timeout - reply) / loop_time)


def _answered_no_reply(loop_time: float, timeout: float, reply: float) -> float:
    return max(0.0, min(1.0, timeout / loop_time))


def _answered_percent(loop_time: float, timeout: float, reply: float) -> float:
    return 100 * max(0.0, min(1.0, (timeout - reply) / loop_time))


def _answered_missed(loop_time: float, timeout: float, reply: float) -> float:
    return 1 - max(0.0, min(1.0, (timeout - reply) / loop_time))


def _float_order(registers: list, order: str, swaps: dict) -> float:
    order = swaps.get(order, order)
    return decode_value(list(registers), "float32", order)


def _float_little_struct(registers: list, order: str) -> float:
    """Every order read with struct's little-endian '<f'."""
    data = b"".join(int(r).to_bytes(2, "big") for r in registers)
    return struct.unpack("<f", data)[0]


def _split(frame: bytes, pdu_from: int = 7, unit_at: int = 6, length=None) -> tuple:
    if int.from_bytes(frame[4:6], "big") != len(frame) - 6:
        raise ModbusError("the length field does not match the frame")
    length = int.from_bytes(frame[4:6], "big") if length is None else length(frame)
    return int.from_bytes(frame[0:2], "big"), 0, length, frame[unit_at], frame[pdu_from:]


def _split_length_check_wrong(frame: bytes) -> tuple:
    """The length compared with the bytes after the unit: every valid frame refused."""
    if int.from_bytes(frame[4:6], "big") != len(frame) - 7:
        raise ModbusError("the length field does not match the frame")
    return int.from_bytes(frame[0:2], "big"), 0, len(frame) - 7, frame[6], frame[7:]


def _request(tid: int, unit: int, address: int, count: int, length: bytes = b"\x00\x06",
             little: bool = False) -> bytes:
    order = "little" if little else "big"
    return (tid.to_bytes(2, "big") + b"\x00\x00" + length + bytes([unit, 3]) + address.to_bytes(2, order)
            + count.to_bytes(2, order))


def _gateway(frame: bytes, tid: int, *, compare: str = "little", check: bool = True,
             length=None) -> bytes:
    if check and crc16(frame[:-2]) != int.from_bytes(frame[-2:], compare):
        raise ModbusError("bad CRC: the frame is damaged")
    body = frame[:-2]
    length = len(body) if length is None else length(body)
    return tid.to_bytes(2, "big") + b"\x00\x00" + length.to_bytes(2, "big") + body


def _gateway_no_length(frame: bytes, tid: int) -> bytes:
    if crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ModbusError("bad CRC: the frame is damaged")
    return tid.to_bytes(2, "big") + b"\x00\x00" + frame[:-2]


def _gateway_no_unit(frame: bytes, tid: int) -> bytes:
    if crc16(frame[:-2]) != int.from_bytes(frame[-2:], "little"):
        raise ModbusError("bad CRC: the frame is damaged")
    pdu = frame[1:-2]
    return tid.to_bytes(2, "big") + b"\x00\x00" + (len(pdu) + 1).to_bytes(2, "big") + pdu


def _echo_length_only(sent: bytes, received: bytes) -> bytes:
    if len(received) < len(sent):
        raise ModbusError("the echo is cut short")
    return received[len(sent):]


def _echo_first_byte(sent: bytes, received: bytes) -> bytes:
    if received[:1] != sent[:1]:
        raise ModbusError("no echo")
    return received[len(sent):]


def _echo_replace(sent: bytes, received: bytes) -> bytes:
    return received.replace(sent, b"")


def _echo_off_by_one(sent: bytes, received: bytes) -> bytes:
    if received[:len(sent)] != sent:
        raise ModbusError("no echo")
    return received[len(sent) + 1:]


def _echo_prefix_unchecked(sent: bytes, received: bytes) -> bytes:
    if not received:
        raise ModbusError("nothing came back")
    return received[len(sent):]


def _role(pdu: bytes, role: str, *, last_address: bool = True, code: int = 1,
          fc15: bool = True) -> bytes | None:
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    last = address
    if last_address and function in ((15, 16) if fc15 else (16,)):
        last = address + int.from_bytes(pdu[3:5], "big") - 1
    allowed = {"engineer": True, "viewer": function <= 4,
               "operator": function <= 4 or last <= 99}.get(role, False)
    return None if allowed else bytes([function | 0x80, code])


def _role_too_strict(pdu: bytes, role: str) -> bytes | None:
    """The last address counted one too far: address + quantity <= 99."""
    function = pdu[0]
    address = int.from_bytes(pdu[1:3], "big")
    reach = address + (int.from_bytes(pdu[3:5], "big") if function in (15, 16) else 0)
    allowed = {"engineer": True, "viewer": function <= 4,
               "operator": function <= 4 or reach <= 99}.get(role, False)
    return None if allowed else bytes([function | 0x80, 1])


SLIPS: dict[str, tuple[Slip, ...]] = {
    "01.5": (
        Slip(_reference_whole, "reference-number", "the whole reference number as the address"),
        Slip(_reference_tables_swapped, "holding-for-input", "3x and 4x mixed up"),
        Slip(_reference_modulo, "one-based-address", "the number modulo 10000, never minus 1"),
        Slip(_reference_no_zero_check, "invalid-input-accepted", "0000 not refused: a missing check"),
        Slip(_reference_two_digit_prefix, None, "the prefix read as two digits"),
    ),
    "02.5": (
        Slip(_fc3_little, "field-low-byte-first", "address and count low byte first"),
        Slip(_fc3_reference, "reference-number", "40001 added to the address"),
        Slip(_fc3_unit, "unit-in-pdu", "a unit in front of the PDU"),
        Slip(_fc3_unchecked, "invalid-input-accepted", "counts outside 1..125 not refused"),
        Slip(_fc3_count_one_byte, "field-in-one-byte", "the count in one byte"),
    ),
    "03.5": (
        Slip(_crc_swapped_bytes, "crc-swapped", "the wire bytes read back high byte first"),
        Slip(_crc_big_endian_bytes, "crc-as-bytes", "the CRC returned as two bytes"),
        Slip(_crc_zero_start, "crc-initial-zero", "the register started at 0"),
        Slip(_crc_poly_unreflected_right, "crc-msb-first",
             "shifted right with 0x8005, the polynomial not reflected"),
        Slip(_crc_low_byte, "crc-one-byte", "only the low byte kept"),
    ),
    "04.5": (
        Slip(lambda data: sum(data) % 256, "lrc-plain-sum", "the sum modulo 256"),
        Slip(lambda data: 255 - sum(data) % 256, "lrc-ones-complement", "255 minus the sum"),
        Slip(_lrc_characters, "lrc-of-characters", "the LRC of the hex characters"),
        Slip(lambda data: 256 - sum(data) % 256, "lrc-not-8-bits", "256 for a sum of 0: & 0xFF forgotten"),
        Slip(lambda data: (-sum(data)) & 0xFFFF, "lrc-not-8-bits", "kept to 16 bits"),
    ),
    "05.5": (
        Slip(lambda tid, unit, pdu: tid.to_bytes(2, "big") + b"\x00\x00" + bytes([unit]),
             "mbap-length-missing",
             "the length field left out"),
        Slip(lambda tid, unit, pdu: _mbap(tid, unit, bytes([len(pdu) + 1])), "mbap-length-missing",
             "the length in one byte"),
        Slip(lambda tid, unit, pdu: _mbap(tid, unit, (len(pdu) + 7).to_bytes(2, "big")), "mbap-length",
             "the header counted in the length"),
        Slip(lambda tid, unit, pdu: _mbap(tid, unit, (len(pdu) + 1).to_bytes(2, "little")),
             "mbap-little-endian", "the length low byte first"),
        Slip(lambda tid, unit, pdu: _mbap(tid, unit, (len(pdu) + 1).to_bytes(2, "big")) + pdu,
             "frame-for-header",
             "the whole frame, not the header asked"),
    ),
    "06.5": (
        Slip(lambda registers, pdu: _handler(registers, pdu, bit=0), "exception-bit-missing",
             "the exception's function code without its top bit"),
        Slip(lambda registers, pdu: _handler(registers, pdu, missing=1), "illegal-function-for-address",
             "exception 01 for an address the bank does not have"),
        Slip(lambda registers, pdu: _handler(registers, pdu, per_register=1), "byte-count-for-quantity",
             "the byte count as the number of registers"),
        Slip(lambda registers, pdu: _handler(registers, pdu, one_based=True), "slave-subtracts-one",
             "the address counted from 1 on the slave's side"),
        Slip(lambda registers, pdu: _handler(registers, pdu, missing=3), "exception-code-confused",
             "exception 03 (illegal data value) for a missing address"),
    ),
    "07.4": (
        Slip(lambda function, code: bytes([function & 0x7F, code]), "exception-bit-missing",
             "the top bit cleared, not set"),
        Slip(lambda function, code: bytes([1, function | 0x80, code]), "unit-in-pdu", "a unit in front"),
        Slip(lambda function, code: bytes([function | 0x80, code])
             + crc_bytes(bytes([function | 0x80, code])),
             "frame-for-pdu", "a CRC after the PDU"),
        Slip(lambda function, code: bytes([0x80, code]), "exception-function-forgotten",
             "0x80 alone, the function forgotten"),
        Slip(lambda function, code: bytes([function | 0x80, code | 0x80]), "top-bit-on-code",
             "the top bit on both"),
    ),
    "08.4": (
        Slip(lambda *args: _transaction(*args, silences=1), "silences-forgotten", "one silence only"),
        Slip(lambda baudrate, parity, stopbits, request, response:
             _transaction(baudrate, parity, 1, request, response), "parity-bit-forgotten",
             "the stop bits always 1"),
        Slip(lambda baudrate, parity, stopbits, request, response:
             _transaction(baudrate, parity, stopbits, request, response, bits=8), "start-stop-forgotten",
             "8 bits per character: start and stop forgotten"),
        Slip(lambda baudrate, parity, stopbits, request, response:
             (request + response + 7) * (1 + 8 + (parity != "N") + stopbits) / baudrate * 1000,
             "milliseconds-for-seconds", "milliseconds, and 3.5 characters at every rate"),
        Slip(lambda baudrate, parity, stopbits, request, response:
             (request + response + 6) * (1 + 8 + (parity != "N") + stopbits) / baudrate,
             "three-characters-for-t35",
             "3 characters for t3.5"),
    ),
    "09.4": (
        Slip(_answered_percent, "percentage-for-fraction", "a percentage"),
        Slip(_answered_unclamped, "fraction-unclamped", "no clamp to 0..1"),
        Slip(_answered_top_only, "fraction-unclamped", "clamped at 1 only"),
        Slip(_answered_no_reply, "reply-time-forgotten", "the reply time forgotten"),
        Slip(_answered_missed, "missed-for-answered", "the share missed, not answered"),
    ),
    "10.4": (
        Slip(lambda registers, order: _float_order(registers, order, {"ABCD": "BADC"}), "word-order",
             "bytes swapped in each register for ABCD"),
        Slip(_float_little_struct, "word-order", "struct's '<f' for every order"),
        Slip(lambda registers, order: _float_order(registers, order, {"CDAB": "BADC", "BADC": "CDAB"}),
             "word-order", "CDAB and BADC mixed up"),
        Slip(lambda registers, order: decode_value(list(registers), "uint32", order), "integer-for-float",
             "an unsigned int, not a float"),
        Slip(lambda registers, order: round(decode_value(list(registers), "float32", order), 2),
             "result-rounded",
             "rounded to 2 decimals"),
    ),
    "11.4": (
        Slip(lambda frame: _split(frame, length=len), "mbap-length", "the length as the frame's length"),
        Slip(lambda frame: _split(frame, pdu_from=6), "unit-in-pdu", "the unit kept in the PDU"),
        Slip(_split_length_check_wrong, "mbap-length", "the length compared with the PDU alone"),
        Slip(lambda frame: _split(frame, unit_at=7), "another-field", "the function code as the unit"),
        Slip(lambda frame: _split(frame)[:4] + (frame[8:],), "function-code-missing",
             "the PDU without its function code"),
    ),
    "12.4": (
        Slip(lambda tid, unit, address, count: _request(tid, unit, address, count, b""),
             "mbap-length-missing",
             "the length field left out"),
        Slip(lambda tid, unit, address, count: _request(tid, unit, address, count, b"\x00\x05"),
             "mbap-length",
             "the length counts the PDU alone"),
        Slip(lambda tid, unit, address, count: _request(tid, unit, address, count, b"\x00\x0C"),
             "mbap-length",
             "the length counts the whole frame"),
        Slip(lambda tid, unit, address, count: _request(tid, unit, address, count, little=True),
             "field-low-byte-first", "address and count low byte first"),
        Slip(lambda tid, unit, address, count: _request(tid, unit, address + 1, count), "one-based-address",
             "the address counted from 1"),
    ),
    "13.7": (
        Slip(lambda registers, expected: next(
            (o for o in ("ABCD", "CDAB", "BADC", "DCBA")
             if abs(decode_value(registers, "float32", o) - expected) < 1e-9), None),
             "float-compared-exactly",
             "a tolerance of 1e-9, as good as =="),
        Slip(lambda registers, expected: next(
            (o for o in ("ABCD", "CDAB", "BADC", "DCBA")
             if round(decode_value(registers, "float32", o), 6) == expected), None), "float-compared-exactly",
             "rounded to 6 decimals, then =="),
        Slip(lambda registers, expected: "CDAB" if registers[0] < registers[1] else "ABCD", "word-order",
             "the order guessed from which register is larger"),
        Slip(lambda registers, expected: next(
            (o for o in ("ABCD", "CDAB", "BADC", "DCBA")
             if abs(decode_value(registers, "float32", o) - expected) < 1), "ABCD"),
             "an-order-when-none-fits", "ABCD when no order fits, not None"),
        Slip(lambda registers, expected: [o for o in ("ABCD", "CDAB", "BADC", "DCBA")
                                          if abs(decode_value(registers, "float32", o) - expected) < 1e-3],
             None, "a list of orders, not one"),
    ),
    "14.2": (
        Slip(lambda current, and_mask, or_mask: current | or_mask, "mask-write-or", "OR over the register"),
        Slip(lambda current, and_mask, or_mask: (current & ~and_mask) | (or_mask & and_mask),
             "mask-roles-swapped", "the masks' roles swapped"),
        Slip(lambda current, and_mask, or_mask: (current & and_mask) | (or_mask & and_mask), "mask-write-or",
             "the OR mask kept where the AND mask has 1"),
        Slip(lambda current, and_mask, or_mask: (current | or_mask) & and_mask, "mask-write-or",
             "OR before AND"),
        Slip(lambda current, and_mask, or_mask: current & and_mask, "or-mask-forgotten",
             "the OR mask forgotten"),
    ),
    "15.2": (
        Slip(lambda frame, tid: _gateway(frame, tid, compare="big", length=lambda body: len(body)),
             "crc-swapped", "the CRC compared high byte first"),
        Slip(_gateway_no_length, "mbap-length-missing", "the length field left out"),
        Slip(lambda frame, tid: _gateway(frame, tid, length=lambda body: len(body) + 6), "mbap-length",
             "the header counted in the length"),
        Slip(lambda frame, tid: _gateway(frame, tid, check=False), "invalid-input-accepted",
             "a damaged frame forwarded"),
        Slip(_gateway_no_unit, "unit-missing", "the unit dropped"),
    ),
    "16.4": (
        Slip(_echo_length_only, "echo-unchecked", "only the echo's length checked"),
        Slip(_echo_first_byte, "echo-unchecked", "only the echo's first byte checked"),
        Slip(_echo_prefix_unchecked, "echo-unchecked", "only an empty read refused"),
        Slip(_echo_replace, "invalid-input-accepted", "the request's bytes deleted wherever they are: "
             "a missing echo goes unnoticed"),
        Slip(_echo_off_by_one, None, "one byte too many cut"),
    ),
    "17.3": (
        Slip(lambda pdu, role: _role(pdu, role, last_address=pdu[0] != 16),
             "first-address-only", "FC 16 judged by its first address"),
        Slip(lambda pdu, role: _role(pdu, role, last_address=False, code=1), "first-address-only",
             "only the first address checked"),
        Slip(_role_too_strict, "range-one-extra", "the last address counted one too far"),
        Slip(lambda pdu, role: _role(pdu, role, code=2), "exception-code-confused",
             "exception 02 for a refused role"),
        Slip(lambda pdu, role: None if role in ("engineer", "operator") else bytes([pdu[0] | 0x80, 1]), None,
             "an operator allowed everything"),
    ),
}
"""Likely wrong functions for each build exercise, by key."""
