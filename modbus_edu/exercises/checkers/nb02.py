"""Exercises of notebook 02: Function codes and the PDU."""

from __future__ import annotations

from typing import Any

from ...pdu import (
    MAX_READ_REGISTERS,
    ExceptionCode,
    ExceptionResponse,
    ReadCoilsResponse,
    ReadHoldingRegistersRequest,
    WriteMultipleRegistersRequest,
)
from ..build import build_exercise
from ..core import (
    address_diagnosis,
    as_bytes,
    compare_bytes,
    compare_pdu,
    exercise,
    int_answer,
    line_after_tries,
    pdu_address_diagnosis,
    pdu_envelope_diagnosis,
    request_field_diagnosis,
)
from ..diagnosis.frameslip import frame_slip
from ..diagnosis.misconceptions import diagnose, name


@exercise("02.1", "build a Write Multiple Registers PDU",
          hint=("function 16's request is the function code, the starting address, the quantity, a byte "
                "count, then the values; every 2-byte field goes high byte first.",
                "the quantity is how many values, the byte count 2 bytes per value; 500 is 0x01F4, so it "
                "goes as 01 F4. mb.WriteMultipleRegistersRequest(address=..., values=[...]).encode() checks "
                "your bytes.",
                "writing 7 and 300 at address 10: 10 | 00 0A | 00 02 | 04 | 00 07 | 01 2C."),
          accepts=["10 00 04 00 02 04 01 F4 03 E8", "10000400020401f403e8",
                   bytes.fromhex("10 00 04 00 02 04 01 F4 03 E8")],
          refuses=[("10 00 04 00 02 01 F4 03 E8", "byte-count-missing"),
                   ("10 00 05 00 02 04 01 F4 03 E8", "one-based-address"),
                   ("10 00 01 00 02 04 00 0A 01 02", None),
                   ("10 00 04 00 02 04 05 00 10 00", "decimal-written-as-hex"),
                   ("10 00 04 00 02 04 F4 01 E8 03", "field-low-byte-first"),
                   ("10 04 00 02 00 04 01 F4 03 E8", "field-low-byte-first"),
                   ("10 00 04 00 04 04 01 F4 03 E8", "byte-count-for-quantity"),
                   ("01 10 00 04 00 02 04 01 F4 03 E8", "unit-in-pdu")])
def _check_02_1(answer: Any) -> str | None:
    expected = WriteMultipleRegistersRequest(address=4, values=(500, 1000)).encode()
    got = as_bytes(answer)
    named = diagnose("byte-count-missing", got, expected) or pdu_address_diagnosis(got, expected)
    if named:
        return named
    return diagnose("byte-count-for-quantity", got, expected) or compare_pdu(got, expected, "your PDU")


@exercise("02.2", "how many requests to read 300 registers",
          hint="one Read Holding Registers request reads at most mb.MAX_READ_REGISTERS registers.",
          accepts=[3, 3.0], refuses=[(2, "count-rounded-down"), (4, None), (300, "request-per-register"),
                   (5, "another-devices-limit")])
def _check_02_2(answer: Any) -> str | None:
    expected = -(-300 // MAX_READ_REGISTERS)
    exact = 300 / MAX_READ_REGISTERS
    if isinstance(answer, float) and not answer.is_integer() and abs(answer - exact) < 0.05:
        return diagnose("count-rounded-down", answer, exact)
    got = int_answer(answer, "a number of requests")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got < expected:
        named = diagnose("count-rounded-down", got, exact)
        return (f"{named} " if named else "") + \
            f"{got} requests can read at most {got * MAX_READ_REGISTERS} registers."
    named = diagnose("request-per-register", got, 300) or diagnose("another-devices-limit", got, 300,
                                                                    MAX_READ_REGISTERS)
    return named or f"{got} requests work, but fewer are enough."


@exercise("02.3", "the exception response for a missing address",
          hint="an exception response is two bytes: the function code with its top bit set (+ 0x80), "
               "then the exception code; mb.ExceptionCode lists the codes.",
          accepts=["84 02", "8402", bytes([0x84, 0x02]), [132, 2]],
          refuses=[("04 02", "exception-bit-missing"), ("84 01", "illegal-function-for-address"),
                   ("83 02", "holding-for-input"), ("84 03", "exception-code-confused"),
                   ("01 84 02", "unit-in-pdu")])
def _check_02_3(answer: Any) -> str | None:
    expected = ExceptionResponse(function=4, code=ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
    got = as_bytes(answer)
    named = pdu_envelope_diagnosis(got, expected)
    if named:
        return named
    if len(got) == 1 and got[0] == expected[0]:
        return diagnose("exception-function-for-code", got[0], 4, expected[1]) + " Here the code is missing."
    if len(got) == 2 and got[0] == expected[0] & 0x7F:
        return name("exception-bit-missing")
    if len(got) == 2 and got[0] & 0x80 and got[1] == expected[1]:
        named = diagnose("holding-for-input", got[0] & 0x7F, expected[0] & 0x7F)
        if named:
            return f"0x{got[0]:02X} answers function {got[0] & 0x7F}; {named}"
    if len(got) == 2 and got[0] == expected[0] and diagnose("illegal-function-for-address", got[1],
                                                            expected[1]):
        return name("illegal-function-for-address")
    if len(got) == 2 and got[0] == expected[0] and got[1] != expected[1]:
        return (diagnose("exception-code-confused", got[1], expected[1])
                or f"the function byte is right; exception code {got[1]:02X} is not 'illegal data address'.")
    return compare_bytes(got, expected, "your exception response")


@exercise("02.4", "which coils are ON",
          hint="in a read-bits response the first coil is the least significant bit (the rightmost) of "
               "the first data byte; 0x05 = 0000 0101 in binary.",
          accepts=[[0, 2], (2, 0), {0, 2}],
          refuses=[([5, 7], "bits-from-the-left"), ([1, 3], "one-based-address"), ([0], None),
                   ([5], "byte-value-as-coils")])
def _check_02_4(answer: Any) -> str | None:
    pdu = bytes([0x01, 0x01, 0x05])  # function, byte count, the data byte
    bits = ReadCoilsResponse.decode(pdu).bits
    expected = [address for address, bit in enumerate(bits) if bit]
    if not isinstance(answer, (list, tuple, set, frozenset)) or len(answer) > 64:
        return "answer with a list of coil addresses, e.g. [1, 4]."
    items = [int_answer(a, "a coil address") for a in answer]
    if any(isinstance(item, str) for item in items):
        return next(item for item in items if isinstance(item, str))
    got = sorted(items)
    if got == expected:
        return None
    named = diagnose("bits-from-the-left", got, expected) or diagnose("byte-value-as-coils", got, pdu[2:])
    if named:
        return named
    if len(got) == len(expected) and all(a == b + 1 for a, b in zip(got, expected)):
        return address_diagnosis(got[0], expected[0])
    return f"{got} are not the coils that are ON."


def _diagnose_fc3(got, expected) -> str | None:
    if not isinstance(got, (bytes, bytearray)) or not isinstance(expected, bytes):
        return None
    return (pdu_envelope_diagnosis(got, expected) or request_field_diagnosis(got, expected, 0)
            or frame_slip(got, expected) or diagnose("field-in-one-byte", got, expected))


def _fc3_pdu(address: int, count: int) -> bytes:
    return ReadHoldingRegistersRequest(address=address, count=count).encode()


def _fc3_inputs(rng) -> tuple:
    if rng.random() < 0.15:  # a request the specification forbids: the learner's function must refuse it
        return rng.choice([(rng.randrange(65536), 0), (rng.randrange(65536), rng.randrange(126, 300)),
                           (rng.randrange(65500, 65536), 125)])
    count = rng.randrange(1, 126)
    return rng.randrange(0, 65536 - count + 1), count


build_exercise(
    "02.5", "write the PDU of a read request",
    reference=_fc3_pdu, inputs=_fc3_inputs,
    edge_cases=[(0, 1), (107, 3), (65535, 1), (0, 125), (0, 0), (0, 126), (65535, 2)],
    hint="the PDU is the function code 3, then the address, then the count, each in two bytes, high byte "
         "first (an int can give its bytes in either order). Refuse (raise) a count outside 1..125 or a "
         "range past address 65535.",
    refuses=[(lambda address, count: bytes([3]) + (address + 1).to_bytes(2, "big") + count.to_bytes(2, "big"),
              "one-based-address"),
             (lambda address, count: bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big"),
              "invalid-input-accepted"),
             (lambda address, count: _fc3_pdu(address, count)[:3] + bytes([count]), "field-in-one-byte")],
    diagnose=lambda args, expected, got: _diagnose_fc3(got, expected))
line_after_tries("02.5", "bytes([3]) is the function code's byte; an int's .to_bytes(2, 'big') gives its "
                 "two bytes, high byte first; + joins bytes. Check the count and the range first, and raise "
                 "when they break a limit.",
                 "function 4 for address 300 and count 2: 300 = 0x012C, so that PDU is 04 01 2C 00 02, and "
                 "(300).to_bytes(2, 'big') == b'\\x01\\x2c'.")
