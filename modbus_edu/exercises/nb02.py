"""Exercises of notebook 02: Function codes and the PDU."""

from __future__ import annotations

from typing import Any

from ..pdu import (
    MAX_READ_REGISTERS,
    ExceptionCode,
    ExceptionResponse,
    ReadCoilsResponse,
    ReadHoldingRegistersRequest,
    WriteMultipleRegistersRequest,
)
from .build import build_exercise
from .core import (
    address_diagnosis,
    as_bytes,
    compare_bytes,
    exercise,
    int_answer,
    line_after_tries,
    pdu_address_diagnosis,
)
from .misconceptions import diagnose, frame_slip, name


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
                   ("10 04 00 02 00 04 01 F4 03 E8", "field-low-byte-first")])
def _check_02_1(answer: Any) -> str | None:
    expected = WriteMultipleRegistersRequest(address=4, values=(500, 1000)).encode()
    got = as_bytes(answer)
    named = diagnose("byte-count-missing", got, expected) or pdu_address_diagnosis(got, expected)
    if named:
        return named
    if got == expected[1:]:
        return "the PDU starts with the function code."
    return frame_slip(got, expected) or compare_bytes(got, expected, "your PDU")


@exercise("02.2", "how many requests to read 300 registers",
          hint="one Read Holding Registers request reads at most mb.MAX_READ_REGISTERS registers.",
          accepts=[3], refuses=[(2, None), (4, None)])
def _check_02_2(answer: Any) -> str | None:
    expected = -(-300 // MAX_READ_REGISTERS)
    got = int_answer(answer, "a number of requests")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got < expected:
        return f"{got} requests can read at most {got * MAX_READ_REGISTERS} registers."
    return f"{got} requests work, but fewer are enough."


@exercise("02.3", "the exception response for a missing address",
          hint="an exception response is two bytes: the function code with its top bit set (+ 0x80), "
               "then the exception code; mb.ExceptionCode lists the codes.",
          accepts=["84 02", "8402", bytes([0x84, 0x02]), [132, 2]],
          refuses=[("04 02", "exception-bit-missing"), ("84 01", "illegal-function-for-address"),
                   ("83 02", "holding-for-input"), ("84 03", None)])
def _check_02_3(answer: Any) -> str | None:
    expected = ExceptionResponse(function=4, code=ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
    got = as_bytes(answer)
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
        return f"the function byte is right; exception code {got[1]:02X} is not 'illegal data address'."
    return compare_bytes(got, expected, "your exception response")


@exercise("02.4", "which coils are ON",
          hint="in a read-bits response the first coil is the least significant bit (the rightmost) of "
               "the first data byte; 0x05 = 0000 0101 in binary.",
          accepts=[[0, 2], (2, 0), {0, 2}],
          refuses=[([5, 7], "bits-from-the-left"), ([1, 3], "one-based-address"), ([0], None)])
def _check_02_4(answer: Any) -> str | None:
    bits = ReadCoilsResponse.decode(bytes([0x01, 0x01, 0x05])).bits
    expected = [address for address, bit in enumerate(bits) if bit]
    try:
        got = sorted(int(a) for a in answer)
    except TypeError:
        return "answer with a list of coil addresses, e.g. [1, 4]."
    if got == expected:
        return None
    named = diagnose("bits-from-the-left", got, expected)
    if named:
        return named
    if len(got) == len(expected) and all(a == b + 1 for a, b in zip(got, expected)):
        return address_diagnosis(got[0], expected[0])
    return f"{got} are not the coils that are ON."


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
              None)],
    diagnose=lambda args, expected, got: pdu_address_diagnosis(got, expected)
    if isinstance(got, bytes) and isinstance(expected, bytes) else None)
line_after_tries("02.5", "bytes([3]) is the function code's byte; an int's .to_bytes(2, 'big') gives its "
                 "two bytes, high byte first; + joins bytes. Check the count and the range first, and raise "
                 "when they break a limit.",
                 "function 4 for address 300 and count 2: 300 = 0x012C, so that PDU is 04 01 2C 00 02, and "
                 "(300).to_bytes(2, 'big') == b'\\x01\\x2c'.")
