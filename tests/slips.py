"""The slips a newcomer makes, exercise by exercise: likely wrong answers beside the exercises.

The ``refuses`` table of each exercise holds the wrong answers its checker was written against; this
catalogue holds the wider set a newcomer gives when taking the course for real: hex read as decimal and
the reverse, bytes swapped, the unit id in front of a PDU, a CRC swapped or missing, an LRC that is a plain
sum, an MBAP length forgotten or counting the wrong bytes, addresses off by one, 5- and 6-digit reference
numbers, a quantity for a byte count, a function code for an exception code, a scale forgotten, a word
order swapped, floats compared exactly.

Each :class:`Slip` is a wrong answer, the key of the catalogue of misconceptions
(:data:`~.misconceptions.CATALOGUE`) whose label the checker's verdict must contain, and what the newcomer
did.  ``misconception`` is None when no catalogued misconception applies; ``why`` then says why.  The
wrong functions of build exercises are in :mod:`.build_slips`.  The test suite runs them all: each must be
refused, named by its misconception, and no verdict may read like a Python error.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from modbus_edu import errors as mb_errors
from modbus_edu.crc import crc_bytes, lrc
from modbus_edu.datamodel import DataBank
from modbus_edu.exercises.inventory import POST, PRE, key_letters


@dataclass(frozen=True)
class Slip:
    """One wrong answer a newcomer gives, the misconception it shows (or None) and what they did."""

    answer: Any
    misconception: str | None
    why: str


def rtu(text: str) -> str:
    """An RTU frame in hex with its CRC appended: a newcomer's frame, wrong bytes under a right CRC."""
    data = bytes.fromhex(text)
    return (data + crc_bytes(data)).hex(" ").upper()


def crc_over_pdu(text: str) -> str:
    """An RTU frame whose CRC covers the PDU alone, without the slave address."""
    data = bytes.fromhex(text)
    return (data + crc_bytes(data[1:])).hex(" ").upper()


def ascii_frame(text: str, check: int | None = None) -> str:
    """An ASCII frame of the bytes ``text`` with the LRC ``check`` (by default the right one)."""
    data = bytes.fromhex(text)
    return f":{data.hex().upper()}{(lrc(data) if check is None else check):02X}\r\n"


def _bank(*runs: tuple[int, int]) -> DataBank:
    bank = DataBank(sparse=True)
    for first, count in runs:
        bank.holding_registers.declare(first, count)
    return bank


def _wrong_letter(quiz: str, *numbers: int) -> str:
    """The right letters of ``quiz`` with the questions ``numbers`` (from 1) answered by another choice."""
    letters = list(key_letters(quiz))
    for number in numbers:
        letters[number - 1] = "ABCD"[("ABCD".index(letters[number - 1]) + 1) % 4]
    return "".join(letters)


_SITUATIONS = ("request for a unit nobody has", "one bit flipped in the request", "one bit flipped in the "
               "response", "read of an address the slave does not have", "response carries another unit id")


def _outcomes(*outcomes: str) -> dict[str, str]:
    return dict(zip(_SITUATIONS, outcomes))


_MAP_HEAD = "name,table,address,type,order,scale,unit\n"
_MAP_ROWS = (("voltage", 30001, "V"), ("current", 30007, "A"), ("active_power", 30013, "W"),
             ("frequency", 30071, "Hz"), ("import_energy", 30073, "kWh"))


def _map(table: str = "input", shift: int = 0, dtype: str = "float32", order: str = "CDAB",
         scale: str = "1") -> str:
    """The bench meter's map file with one column changed."""
    return _MAP_HEAD + "".join(f"{name},{table},{number + shift},{dtype},{order},{scale},{unit}\n"
                               for name, number, unit in _MAP_ROWS)


def _frames(*texts: str) -> list[str]:
    return [rtu(text) for text in texts]


_BENCH = ("01 04 00 00 00 02", "01 04 00 06 00 02", "01 04 00 0C 00 02", "01 04 00 46 00 04")

SLIPS: dict[str, tuple[Slip, ...]] = {
    PRE: (
        Slip("A" * 12, None, "the pre-test never says which answers are wrong: it must not teach them"),
        Slip("?" * 12, None, "the pre-test never says which answers are wrong: it must not teach them"),
        Slip(_wrong_letter(PRE, 5), None, "the pre-test never says which answers are wrong"),
        Slip(_wrong_letter(PRE, 2, 9), None, "the pre-test never says which answers are wrong"),
        Slip("ABCDABCDABC", None, "eleven letters for twelve questions: a count, no misconception"),
    ),
    POST: (
        Slip(_wrong_letter(POST, 1), "mbap-length", "question 1 asks the MBAP length"),
        Slip(_wrong_letter(POST, 2), "answer-to-damaged-request", "question 2 asks about a damaged request"),
        Slip(_wrong_letter(POST, 6), "mbap-little-endian", "question 6 asks the transaction id's bytes"),
        Slip(_wrong_letter(POST, 9), "reference-number", "question 9 asks the address of 40001"),
        Slip(_wrong_letter(POST, 12), "answer-to-damaged-request",
             "question 12 (a pause inside a frame): the slave answers it with exception 03"),
        Slip(_wrong_letter(POST, 10), "word-order", "question 10 asks who fixes the word order"),
    ),
    "00.1": (
        Slip(11.0, "hex-read-as-decimal", "the byte 11 read as decimal, typed as a float"),
        Slip(0x03, "another-field", "the function code, the second byte"),
        Slip(0x6B, "another-field", "the starting address"),
        Slip(0x76, "another-field", "the first CRC byte"),
        Slip(0x87, "another-field", "the last byte, the CRC's high byte, read as the address"),
        Slip("11", "hex-read-as-decimal", "the byte's digits typed as text, read as decimal"),
        Slip(2, None, "the slave address of another frame: no misconception"),
    ),
    "00.2": (
        Slip("06 11 03 00 6B 00 03", "frame-for-pdu", "the length's low byte and the unit kept"),
        Slip("00 06 11 03 00 6B 00 03", "frame-for-pdu", "everything after the protocol id"),
        Slip("03 00 6C 00 03", "one-based-address", "the address counted from 1"),
        Slip("03 6B 00 03 00", "field-low-byte-first", "address and count written low byte first"),
        Slip("03 00 6B 00 03 76 87", "frame-for-pdu", "an RTU frame's CRC added to the PDU"),
        Slip("04 00 6B 00 03", "holding-for-input", "function 4 for function 3"),
        Slip("03 00 6B 00", "part-of-answer", "cut short: a byte missing"),
    ),
    "00.3": (
        Slip(crc_over_pdu("02 03 00 00 00 02"), "checksum-without-address", "the CRC over the PDU alone"),
        Slip(rtu("02 03 00 00 02 00"), "field-low-byte-first", "the count written low byte first"),
        Slip(rtu("02 04 00 00 00 02"), "holding-for-input", "function 4 for holding registers"),
        Slip(rtu("02 03 9C 41 00 02"), "reference-number", "the address 40001 put in the frame"),
        Slip("02 03 00 00 00 02 38C4", "crc-swapped", "the CRC register's hex as it reads"),
        Slip(rtu("03 00 00 00 02"), "unit-missing", "the slave address left out"),
    ),
    "01.1": (
        Slip(0x249, "decimal-written-as-hex", "the address 249 written with hex digits"),
        Slip(400249, "reference-number", "the 6-digit reference number with the table digit"),
        Slip(30249, "reference-number", "a reference number of the wrong table"),
        Slip(40249.0, "reference-number", "the reference number minus 1, as a float"),
        Slip(250.0, "one-based-address", "the number after the prefix, as a float"),
        Slip(248, "address-one-too-low", "1 subtracted twice"),
    ),
    "01.2": (
        Slip("300009", "zero-based-number", "the 6-digit form counted from 0"),
        Slip("400010", "holding-for-input", "the 6-digit form of the holding register"),
        Slip(40010, "holding-for-input", "the holding register's number as an int"),
        Slip(30009, "zero-based-number", "the number counted from 0, as an int"),
        Slip("40009", "holding-for-input", "the holding table, counted from 0"),
        Slip("3010", None, "four digits: not a reference number"),
    ),
    "01.3": (
        Slip(("holding_registers", False), "holding-for-input", "function 4 read as the holding registers"),
        Slip(["Holding Registers", True], "holding-for-input", "holding registers, writable"),
        Slip(("holding registers", True), "holding-for-input", "the 4 of FC 4 read as the 4x table"),
        Slip(("discrete_inputs", False), "bit-table-for-register-table",
             "the bit table for the register table"),
        Slip(("input_registers", "no"), None, "a word for False: the answer asks True or False"),
    ),
    "01.4": (
        Slip(59, "range-one-end", "one range counted without one end"),
        Slip(58.0, "range-one-end", "both ranges without one end, as a float"),
        Slip(50, "one-range-only", "the first range only"),
        Slip(10, "one-range-only", "the second range only"),
        Slip(62, "range-one-extra", "each range counted with one extra"),
    ),
    "02.1": (
        Slip("10 00 04 00 04 04 01 F4 03 E8", "byte-count-for-quantity", "the byte count as the quantity"),
        Slip("10 00 04 00 02 02 01 F4 03 E8", "byte-count-for-quantity", "the quantity as the byte count"),
        Slip("11 10 00 04 00 02 04 01 F4 03 E8", "unit-in-pdu", "a slave address in front"),
        Slip("10 00 04 00 02 04 01 F4 03 E8 2E 7B", "frame-for-pdu", "a checksum after the PDU"),
        Slip("10 9C 45 00 02 04 01 F4 03 E8", "reference-number", "the reference number 40005 as address"),
        Slip("10 00 04 00 02 04 F4 01 03 E8", "field-low-byte-first", "the first value low byte first"),
        Slip("10 00 04 00 02 01 F4 03 E8", "byte-count-missing", "no byte count"),
    ),
    "02.2": (
        Slip(300 // 125, "count-rounded-down", "rounded down: 2 requests read only 250 registers"),
        Slip(2.4, "count-rounded-down", "300 / 125 without rounding up"),
        Slip(2.0, "count-rounded-down", "rounded down, as a float"),
        Slip(300, "request-per-register", "one request per register"),
        Slip(5, "another-devices-limit", "a limit of 64 registers assumed (another device's)"),
    ),
    "02.3": (
        Slip("01 84 02", "unit-in-pdu", "the unit in front of the PDU"),
        Slip("84", "exception-function-for-code", "the exception code left out"),
        Slip("84 02 C2 C1", "frame-for-pdu", "a CRC after the PDU"),
        Slip([0x04, 0x02], "exception-bit-missing", "the top bit forgotten, as a list"),
        Slip("84 01", "illegal-function-for-address", "illegal function for a missing address"),
        Slip("04 82", "exception-bit-missing", "the top bit on the exception code, not on the function"),
    ),
    "02.4": (
        Slip({5, 7}, "bits-from-the-left", "the bits read from the left, as a set"),
        Slip({1, 3}, "one-based-address", "coils counted from 1, as a set"),
        Slip([0, 1, 2], None, "the 1 of the byte count read as a coil"),
        Slip([5], "byte-value-as-coils", "the byte's value read as a coil number"),
        Slip([2], None, "only one bit seen"),
    ),
    "03.1": (
        Slip("98B2", "crc-swapped", "the CRC register's hex written as it reads"),
        Slip([0x98, 0xB2], "crc-swapped", "the register's bytes, high first"),
        Slip(bytes([0x98, 0xB2]), "crc-swapped", "the register's bytes, high first, as bytes"),
        Slip("98 b2", "crc-swapped", "high byte first, lower case"),
        Slip("B2", "crc-one-byte", "one byte only"),
    ),
    "03.2": (
        Slip(rtu("01 06 00 02 04 D2"), "hex-read-as-decimal", "0x1234 read as 1234, then written as 04 D2"),
        Slip(rtu("01 06 00 03 12 34"), "one-based-address", "the address counted from 1 (right CRC)"),
        Slip(crc_over_pdu("01 06 00 02 12 34"), "checksum-without-address", "the CRC over the PDU alone"),
        Slip(rtu("01 06 9C 43 12 34"), "reference-number", "the reference number 40003 as address"),
        Slip("01 06 00 02 12 34 7d 25", "crc-swapped", "the CRC high byte first, lower case"),
        Slip(rtu("06 00 02 12 34"), "unit-missing", "the slave address left out"),
    ),
    "03.3": (
        Slip(True, "answer-to-damaged-request", "a damaged request answered"),
        Slip("False", None, "a string, not the bool asked"),
        Slip(0, None, "0 for False: the answer asks True or False"),
        Slip("yes", None, "a word for True"),
        Slip(1, None, "1 for True"),
    ),
    "03.4": (
        Slip(43.0, "crc-forgotten", "the CRC left out, as a float"),
        Slip(25.0, "register-one-byte", "one byte per register, as a float"),
        Slip(25, "register-one-byte", "one byte per register"),
        Slip(40, "data-bytes-only", "the data bytes alone"),
        Slip(46, None, "one byte too many"),
    ),
    "04.1": (
        Slip(0x82, "lrc-plain-sum", "the plain sum of the bytes"),
        Slip(130.0, "lrc-plain-sum", "the plain sum, as a float"),
        Slip(0x7D, "lrc-ones-complement", "the bits inverted, 1 not added"),
        Slip(125.0, "lrc-ones-complement", "the bits inverted, as a float"),
        Slip(0xA0, "lrc-of-characters", "the LRC of the hex characters"),
        Slip(0x182, None, "the sum kept to 9 bits"),
    ),
    "04.2": (
        Slip(ascii_frame("05 03 10 00 00 02", 0x1A), "lrc-plain-sum", "the LRC as the plain sum"),
        Slip(ascii_frame("05 03 10 00 00 02", 0xE5), "lrc-ones-complement", "the bits inverted, 1 not added"),
        Slip(ascii_frame("05 03 40 96 00 02"), "decimal-written-as-hex", "address 4096 in decimal digits"),
        Slip(ascii_frame("05 03 00 10 00 02"), "field-low-byte-first", "the address low byte first"),
        Slip(ascii_frame("05 03 10 00 00 02", lrc(bytes.fromhex("03 10 00 00 02"))),
             "checksum-without-address",
             "the LRC over the PDU alone"),
        Slip(ascii_frame("05 03 AC 41 00 02"), "reference-number", "the reference number 44097 as address"),
        Slip(ascii_frame("05 04 10 00 00 02"), "holding-for-input", "function 4 for holding registers"),
        Slip(":050310000002E6", "ascii-without-crlf", "CR LF left out"),
    ),
    "04.3": (
        Slip(21.0, "ascii-without-crlf", "CR LF left out, as a float"),
        Slip(21, "ascii-without-crlf", "CR LF left out"),
        Slip(11, "rtu-length-for-ascii", "the RTU frame's length"),
        Slip(25, "crc-in-ascii", "a 2-byte checksum as in RTU"),
        Slip(22, "ascii-colon-forgotten", "the ':' left out"),
    ),
    "04.4": (
        Slip("05 03 04 FF 06 00 64 8B", "frame-for-pdu", "the whole frame's bytes"),
        Slip("03 04 FF 06 00 64 8B", "frame-for-pdu", "the LRC kept"),
        Slip("05 03 04 FF 06 00 64", "unit-in-pdu", "the slave address kept"),
        Slip("03 04 06 FF 64 00", "field-low-byte-first", "each register read low byte first"),
        Slip([5, 3, 4, 0xFF, 6, 0, 0x64], "unit-in-pdu", "the slave address kept, as a list"),
        Slip("04 FF 06 00 64", "function-code-missing", "the function code left out"),
    ),
    "05.1": (
        Slip(0x2A00, "mbap-little-endian", "the two bytes read low byte first"),
        Slip(10752.0, "mbap-little-endian", "low byte first, as a float"),
        Slip(6, "another-field", "the length field"),
        Slip(0x11, "another-field", "the unit identifier"),
        Slip(0x6B, "another-field", "the starting address"),
        Slip(0, "another-field", "the protocol identifier"),
    ),
    "05.2": (
        Slip("00 07 00 00 01 06 00 00 04 D2", "mbap-length-missing", "the length field left out"),
        Slip("00 07 00 00 06 01 06 00 00 04 D2", "mbap-length-missing", "the length in one byte"),
        Slip("00 07 00 00 00 0C 01 06 00 00 04 D2", "mbap-length", "the length counts the whole frame"),
        Slip("00 07 00 00 00 06 01 06 00 00 12 34", "decimal-written-as-hex", "1234 written as hex digits"),
        Slip("00 07 00 00 00 06 01 06 9C 41 04 D2", "reference-number", "the reference number 40001"),
        Slip("00 07 00 00 00 06 06 00 00 04 D2", "unit-missing",
             "the unit left out: the length field still says 6"),
    ),
    "05.3": (
        Slip(22, "mbap-length", "the PDU alone, without the unit"),
        Slip(22.0, "mbap-length", "the unit left out, as a float"),
        Slip(29, "mbap-length", "the whole frame counted"),
        Slip(28, "mbap-length", "the header and the PDU, not the unit"),
        Slip(20, "data-bytes-only", "the data bytes alone"),
    ),
    "05.4": (
        Slip("protocol identifier", None, "a field that holds what it should"),
        Slip("transaction id", None, "0x0118 looks odd, but it is a transaction id like another"),
        Slip("unit", None, "a field that holds what it should"),
        Slip("function code", None, "not a field of the MBAP header"),
        Slip(4, None, "a byte index, not a field's name"),
    ),
    "06.1": (
        Slip(41.66, "truncated-not-rounded", "41.667 cut to 41.66"),
        Slip(0.0417, "seconds-for-milliseconds", "seconds, rounded"),
        Slip(0.041667, "seconds-for-milliseconds", "seconds"),
        Slip(34.375, "silences-forgotten", "the silences left out"),
        Slip(34.38, "silences-forgotten", "the silences left out, rounded"),
        Slip(41666.7, "microseconds-for-milliseconds", "microseconds"),
    ),
    "06.2": (
        Slip(0x85, "exception-function-for-code", "the exception response's function code"),
        Slip(1.0, "illegal-function-for-address", "illegal function, as a float"),
        Slip(0x01, "illegal-function-for-address", "illegal function"),
        Slip(4, "exception-code-confused", "slave device failure"),
        Slip(0, "refusal-unanswered", "no exception at all"),
    ),
    "06.3": (
        Slip(87.2, "truncated-not-rounded", "87.27 cut to 87.2"),
        Slip(0.011458, "time-for-rate", "the time of one transaction"),
        Slip(0.01146, "time-for-rate", "the time of one transaction, rounded"),
        Slip(128, "silences-forgotten", "the silences left out"),
        Slip(43.64, "another-baud-rate", "the rate at 9600 baud"),
    ),
    "06.4": (
        Slip(mb_errors.CrcError, "answer-to-damaged-request", "a CRC error expected at the master"),
        Slip(mb_errors.ChecksumError, "answer-to-damaged-request", "a checksum error at the master"),
        Slip(mb_errors.ModbusExceptionError, "answer-to-damaged-request",
             "an exception response expected: no catalogued name"),
        Slip(TimeoutError, "builtin-for-library-exception", "Python's own timeout, not the library's"),
        Slip("timeout", None, "a word, not the exception class"),
    ),
    "07.1": (
        Slip((83, 2), "hex-read-as-decimal", "the byte 83 read as decimal"),
        Slip((0x83, 0x02), "exception-code-as-function", "the response's function code"),
        Slip([0x83, 2], "exception-code-as-function", "the response's function code, as a list"),
        Slip((3, 0x82), "top-bit-on-code", "0x80 added to the exception code"),
        Slip((2, 3), "function-and-code-swapped", "the two swapped"),
    ),
    "07.2": (
        Slip("11 81 02", "crc-forgotten", "the CRC left out"),
        Slip(crc_over_pdu("11 81 02"), "checksum-without-address", "the CRC over the PDU alone"),
        Slip(rtu("11 01 02"), "exception-bit-missing", "the top bit forgotten"),
        Slip(rtu("17 81 02"), "decimal-written-as-hex", "unit 17 written as hex digits"),
        Slip(rtu("11 81 01"), "illegal-function-for-address", "illegal function for a missing address"),
        Slip(rtu("81 02"), "unit-missing", "the unit left out"),
    ),
    "07.3": (
        Slip(_outcomes("checksum error", "timeout", "checksum error", "exception", "mismatch"),
             "answer-to-another-unit", "a unit nobody has read as a checksum error"),
        Slip(_outcomes("timeout", "checksum error", "checksum error", "exception", "mismatch"),
             "answer-to-damaged-request", "a damaged request answered with a checksum error"),
        Slip(_outcomes("timeout", "exception", "checksum error", "exception", "mismatch"),
             "answer-to-damaged-request", "a damaged request answered with an exception"),
        Slip(_outcomes("timeout", "timeout", "timeout", "exception", "mismatch"),
             "damaged-response-as-silence",
             "a damaged response read as no response"),
        Slip(_outcomes("timeout", "timeout", "checksum error", "timeout", "mismatch"), "refusal-unanswered",
             "a missing address read as silence"),
    ),
    "08.1": (
        Slip(8.02, "milliseconds-for-seconds", "milliseconds, rounded"),
        Slip(0.0022917, "one-character-for-t35", "one character of 11 bits"),
        Slip(0.00729, "parity-bit-forgotten", "10 bits per character"),
        Slip(0.008020, "truncated-not-rounded", "0.0080208 cut to 6 decimals"),
        Slip(0.0073, "parity-bit-forgotten", "10 bits per character, rounded"),
    ),
    "08.2": (
        Slip(58.2, "silences-forgotten", "the silences left out"),
        Slip(58.1818, "silences-forgotten", "the silences left out, more decimals"),
        Slip(47.9, "truncated-not-rounded", "47.99 cut to 47.9"),
        Slip(0.0208, "time-for-rate", "the time of one transaction"),
        Slip(87.27, "one-register-response", "the rate for one register"),
    ),
    "08.3": (
        Slip([5], "t15-forgotten", "only a pause of 3.5 or more"),
        Slip((5.0,), "t15-forgotten", "only a pause of 3.5 or more, as a tuple"),
        Slip([3.0, 5.0], "pause-threshold", "the 2-character pause not counted"),
        Slip([1.4, 2.0, 3.0, 5.0], "pause-threshold", "a pause of 1.4 counted, which is not more than 1.5"),
        Slip([], "pause-threshold", "no pause breaks a frame"),
    ),
    "09.1": (
        Slip((4, 16), "decimal-written-as-hex", "the number after the prefix, 0010, read as hex"),
        Slip((3, 9), "holding-for-input", "function 3 for an input register"),
        Slip((3, 10), "holding-for-input", "function 3 for an input register, counted from 1"),
        Slip((4, 300009), "reference-number", "the 6-digit reference number minus 1"),
        Slip([4, 10], "one-based-address", "counted from 1, as a list"),
        Slip((4, 0x0A), "one-based-address", "10 written in hex: the number, not the address"),
    ),
    "09.2": (
        Slip(_bank((150, 26), (200, 26)), "one-based-address", "the numbers as addresses"),
        Slip(_bank((149, 25), (199, 25)), "range-one-end", "each range without one end"),
        Slip(_bank((149, 26), (199, 25)), "range-one-end", "the second range without one end"),
        Slip(_bank((149, 26)), "one-range-only", "one range only"),
        Slip(DataBank(sparse=False), "dense-for-sparse", "a dense bank: every address exists"),
    ),
    "09.3": (
        Slip(1650, "milliseconds-for-seconds", "milliseconds"),
        Slip(2000, "milliseconds-for-seconds", "milliseconds, rounded"),
        Slip(1.0, "given-figure", "the master's usual timeout"),
        Slip(1.65, "loop-time-for-timeout", "the loop time alone"),
        Slip(10, "timeout-far-too-long", "far longer than needed"),
    ),
    "10.1": (
        Slip(4105.0, "raw-for-scaled", "the scale forgotten"),
        Slip(4105, "raw-for-scaled", "the scale forgotten, an int"),
        Slip(15204352.0, "word-order", "low word first with bytes swapped, scaled"),
        Slip(232.0, "word-order", "bytes swapped in each register, scaled"),
        Slip(41.05, "scale-wrong", "divided by 100"),
    ),
    "10.2": (
        Slip([0x6884, 0x0004], "word-order", "low word first"),
        Slip([0, 2889], "current-not-in-milliamperes", "tenths of an ampere"),
        Slip([288900], "one-register-for-32-bits", "one register for the 32-bit value"),
        Slip([0x0000, 0x0121], "current-not-in-milliamperes", "whole amperes"),
        Slip((0x6884, 4), "word-order", "low word first, as a tuple"),
        Slip([0x0004, 0x8468], "field-low-byte-first", "the low register's bytes swapped"),
    ),
    "10.3": (
        Slip((3, 36, 6), "hex-read-as-decimal", "the address 0x36 read as decimal"),
        Slip((3, 54, 3), "one-register-for-32-bits", "one register per value"),
        Slip((3, 55, 6), "one-based-address", "counted from 1"),
        Slip((4, 54, 6), "holding-for-input", "function 4 for holding registers"),
        Slip((3, 40055, 6), "reference-number", "the reference number"),
        Slip((3, 54, 12), "bytes-for-registers", "a byte count for the register count"),
    ),
    "11.1": (
        Slip((0x2A00, 6, 16, 500), "mbap-little-endian", "the transaction id low byte first"),
        Slip((42, 6, 10, 500), "hex-read-as-decimal", "the address 0x10 read as decimal"),
        Slip((42, 6, 17, 500), "one-based-address", "the address counted from 1"),
        Slip([10752, 6, 16, 500], "mbap-little-endian", "low byte first, as a list"),
        Slip((42, 6, 40017, 500), "reference-number", "the reference number of the register"),
        Slip((42, 17, 16, 500), "another-field", "the unit for the function"),
    ),
    "11.2": (
        Slip("00 07 00 00 03 03 00 00 00 03", "mbap-length-missing", "the length field left out"),
        Slip("00 07 00 00 00 08 03 03 00 00 00 03 04 29", "crc-on-tcp", "the CRC kept"),
        Slip("00 07 00 00 00 05 03 03 00 00 00 03", "mbap-length", "the unit not counted"),
        Slip("00 07 00 00 00 0C 03 03 00 00 00 03", "mbap-length", "the whole frame counted"),
        Slip("00 07 00 00 00 06 03 03 00 01 00 03", "one-based-address", "the address counted from 1"),
        Slip("00 07 00 00 00 06 03 03 00 00 03 00", "field-low-byte-first", "the count low byte first"),
    ),
    "11.3": (
        Slip("socket://192.168.1.60", "url-without-port", "the port left out"),
        Slip("socket://192.168.1.60:502", "modbus-tcp-port-for-server",
             "the Modbus/TCP port, not the device server's"),
        Slip("192.168.1.60:4001", "url-not-socket", "the scheme left out"),
        Slip("tcp://192.168.1.60:4001", "url-not-socket", "another scheme"),
        Slip("socket://192.168.1.60:99999", "port-out-of-range", "a port past 65535"),
    ),
    "12.1": (
        Slip("0x008C", "one-based-address", "the cell before: counted from 1"),
        Slip("0x0150", "decimal-written-as-hex", "150 written with hex digits"),
        Slip("0x8c", "one-based-address", "the cell before, lower case"),
        Slip("150", "another-form", "the unsigned display: the value is right, the form is not"),
        Slip("0x00A0", None, "the cell after"),
    ),
    "12.2": (
        Slip({"role": "rtu_master", "unit": 7, "function": 3, "address": 10, "length": 4, "interval": 0.5},
             "holding-for-input", "function 3 for input registers"),
        Slip({"role": "rtu_master", "unit": 7, "function": 4, "address": 30011, "length": 4,
              "interval": 0.5}, "reference-number", "the reference number as address"),
        Slip({"role": "rtu_master", "unit": 7, "function": 4, "address": 10, "length": 4, "interval": 500},
             "milliseconds-for-seconds", "the interval in milliseconds"),
        Slip({"role": "tcp_client", "unit": 7, "function": 4, "address": 11, "length": 4,
              "interval": 0.5}, "one-based-address", "counted from 1"),
        Slip({"role": "rtu_slave", "unit": 7, "function": 4, "address": 10, "length": 4, "interval": 0.5},
             "slave-for-master", "a slave, which answers, for the master"),
    ),
    "12.3": (
        Slip((283, "1B 01"), "mbap-little-endian", "the id low byte first"),
        Slip((283, b"\x1b\x01"), "mbap-little-endian", "the id low byte first, as bytes"),
        Slip((0x1B01, "1B 01"), "mbap-little-endian", "the id and its bytes low byte first"),
        Slip((0x283, "02 83"), "decimal-written-as-hex", "283 written with hex digits"),
        Slip((282, "01 1A"), "last-transaction-id", "the third request's id"),
    ),
    "13.1": (
        Slip({"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"},
             "causes-swapped", "two wires mixed up"),
        Slip({"A": "wrong baud rate or parity", "B": "no slave on the line", "C": "wrong unit id"},
             "causes-swapped", "two wires mixed up"),
        Slip({"A": "wrong unit id", "B": "no slave on the line"}, None, "a wire left out"),
        Slip({"A": "unit", "B": "nothing", "C": "baud"}, None, "words other than the three causes"),
        Slip(["wrong unit id", "no slave on the line", "wrong baud rate or parity"], None, "a list"),
    ),
    "13.2": (
        Slip(("ABCD", 292880.386), "word-order", "high word first"),
        Slip(("CDAB", 135541), "milliamperes-for-amperes", "milliamperes"),
        Slip(("BADC", 135.541), "word-order", "bytes swapped in each register"),
        Slip(("CDAB", 135.541e3), "milliamperes-for-amperes", "milliamperes, as a float"),
        Slip(("abcd", 292.88), "word-order", "high word first, lower case"),
        Slip(("CDAB", 13.55), "scale-wrong", "divided by 10 000"),
    ),
    "13.3": (
        Slip(400020, "reference-number", "the 6-digit reference number minus 1"),
        Slip(0x20, "decimal-written-as-hex", "20 written with hex digits"),
        Slip(21.0, "one-based-address", "counted from 1, as a float"),
        Slip(40021.0, "reference-number", "the reference number, as a float"),
        Slip(19, "address-one-too-low", "1 subtracted twice"),
    ),
    "13.4": (
        Slip((3, "00 03"), "mbap-little-endian", "what the client meant, not what the server reads"),
        Slip((768, "03 00"), "mbap-little-endian", "the client's bytes again"),
        Slip((300, "00 03"), "hex-read-as-decimal", "0x0300 read as 300"),
        Slip([3, b"\x03\x00"], "mbap-little-endian", "both the client's view, as a list"),
        Slip((0x300, "00 00 03"), None, "three bytes"),
    ),
    "13.5": (
        Slip(crc_over_pdu("01 03 00 00 00 01"), "checksum-without-address", "the CRC over the PDU alone"),
        Slip(rtu("01 04 00 00 00 01"), "holding-for-input", "function 4 for a holding register"),
        Slip(rtu("01 03 00 00 01 00"), "field-low-byte-first", "the count low byte first"),
        Slip("01 03 00 00 00 01 0A 84", "crc-swapped", "the CRC high byte first"),
        Slip(rtu("01 03 9C 41 00 01"), "reference-number", "the reference number 40001 as address"),
        Slip("84 0A", "part-of-answer", "the right CRC alone, not the corrected frame"),
    ),
    "13.6": (
        Slip(2200, "milliseconds-for-seconds", "milliseconds"),
        Slip(2000.0, "milliseconds-for-seconds", "milliseconds, rounded"),
        Slip(1.0, "given-figure", "the timeout"),
        Slip(0.45, "given-figure", "the fraction answered"),
        Slip(5.0, "given-figure", "the poll interval"),
    ),
    "14.1": (
        Slip(135, "hex-read-as-decimal", "0x0135 read as 135"),
        Slip(0x01B5, "mask-write-or", "the OR mask over the whole register"),
        Slip(437.0, "mask-write-or", "the OR mask over the whole register, as a float"),
        Slip(0x00A0, "mask-roles-swapped", "the AND mask read the other way round"),
        Slip(0x0005, "or-mask-forgotten", "the AND mask alone"),
    ),
    "14.3": (
        Slip(6, None, "the damaged request counted; the number alone cannot tell it from the clear request "
             "counted, so the verdict names both"),
        Slip(6.0, None, "the damaged request counted, as a float: the verdict names both candidates"),
        Slip(4, None, "the 0x0B request itself forgotten; the number alone cannot tell it from unit 2's "
             "response left out, so the verdict names both"),
        Slip(3, "others-not-heard", "only the requests for unit 1"),
        Slip(2, "others-not-heard", "only the reads of unit 1"),
        Slip(7, "own-frames-counted", "every frame on the line"),
    ),
    "15.1": (
        Slip(12.5, "parity-bit-forgotten", "10 bits per character"),
        Slip(9.74, "silences-forgotten", "the silences left out"),
        Slip(0.01375, "seconds-for-milliseconds", "seconds"),
        Slip(13.74, "truncated-not-rounded", "13.7499 cut to 13.74"),
        Slip("12.5 ms", "parity-bit-forgotten", "10 bits per character, with the unit"),
    ),
    "15.3": (
        Slip({"a": 0x0B, "b": 0x0B, "c": 0x01, "d": "timeout"}, "gateway-codes-swapped", "0B for every "
             "unreachable unit"),
        Slip({"a": 0x0A, "b": "timeout", "c": 0x01, "d": "timeout"}, "gateway-silence",
             "the meter's silence passed on"),
        Slip({"a": "0A", "b": "0A", "c": "01", "d": "timeout"}, "gateway-codes-swapped",
             "0A for a silent unit"),
        Slip({"a": "timeout", "b": 0x0B, "c": 0x01, "d": "timeout"}, "gateway-silence",
             "no path read as silence"),
        Slip({"a": 10, "b": 11, "c": 1}, None, "a case left out"),
    ),
    "16.1": (
        Slip(_map(table="holding"), "holding-for-input", "the holding table"),
        Slip(_map(order="ABCD"), "word-order", "high word first, against the datasheet"),
        Slip(_map(order="BADC"), "word-order", "the bytes swapped for 'low word first'"),
        Slip(_map(shift=1), None, "one too high: 30002 for 30001"),
        Slip(_map(dtype="uint32"), "integer-for-float", "an integer type for a float"),
    ),
    "16.2": (
        Slip(_frames(*(text.replace("01 04", "01 03") for text in _BENCH)), "holding-for-input",
             "function 3 for input registers"),
        Slip([crc_over_pdu(text) for text in _BENCH], "checksum-without-address",
             "the CRC over the PDU alone"),
        Slip(_frames("01 04 00 01 00 02", "01 04 00 07 00 02", "01 04 00 0D 00 02", "01 04 00 47 00 04"),
             "one-based-address", "addresses counted from 1"),
        Slip([text[:-6] for text in _frames(*_BENCH)], "crc-forgotten", "the CRC left out"),
        Slip(_frames("01 04 00 00 00 01", "01 04 00 06 00 01", "01 04 00 0C 00 01", "01 04 00 46 00 02"),
             "one-register-for-32-bits", "one register per float"),
        Slip([text.replace(" ", "") for text in _frames(*_BENCH)][::-1], None, "the frames in reverse"),
    ),
    "16.3": (
        Slip("parity", "check-ruled-out", "already ruled out by the scan"),
        Slip("check the wiring", None, "the question is which way round"),
        Slip("termination", "termination-for-silence", "a terminator garbles, it does not silence"),
        Slip("increase the timeout", "check-ruled-out", "the meter never answered at all"),
        Slip("the unit id", "check-ruled-out", "the scan asked every unit"),
    ),
    "17.1": (
        Slip(0xF401, "field-low-byte-first", "the value low byte first"),
        Slip(10, "another-field", "the address"),
        Slip(6, "another-field", "the function code"),
        Slip(7, "another-field", "the transaction id"),
        Slip(62465.0, "field-low-byte-first", "the value low byte first, as a float"),
        Slip(0x01F5, None, "the value plus one"),
    ),
    "17.2": (
        Slip(0, "first-address-only", "allowed: only the first address checked"),
        Slip(0.0, "first-address-only", "allowed, as a float"),
        Slip(0x90, "exception-function-for-code", "the exception response's function code"),
        Slip(2, "exception-code-confused", "illegal data address, the slave's answer"),
        Slip(4, "exception-code-confused", "slave device failure"),
    ),
}
"""Likely wrong answers to each value exercise, by key (build exercises: :data:`.build_slips.SLIPS`)."""
