"""Exercises of notebook 02: Function codes and the PDU."""

from __future__ import annotations

from typing import Any

from .build import build_exercise
from .core import as_bytes, compare_bytes, exercise, int_answer


@exercise("02.1", "build a Write Multiple Registers PDU",
          hint="function 16 (0x10): address (2 bytes), quantity (2 bytes), byte count (1 byte), then the "
               "values, each high byte first; mb.WriteMultipleRegistersRequest(address=..., values=[...]).",
          wrong="10 00 04 00 02 01 F4 03 E8")
def _check_02_1(answer: Any) -> str | None:
    from ..pdu import WriteMultipleRegistersRequest

    expected = WriteMultipleRegistersRequest(address=4, values=(500, 1000)).encode()
    got = as_bytes(answer)
    if len(got) == len(expected) - 1 and got[:5] == expected[:5] and got[5:] == expected[6:]:
        return ("the byte count (one byte, the number of data bytes that follow) is missing after "
                "the quantity.")
    if got == expected[1:]:
        return "the PDU starts with the function code."
    return compare_bytes(got, expected, "your PDU")


@exercise("02.2", "how many requests to read 300 registers",
          hint="one Read Holding Registers request reads at most mb.MAX_READ_REGISTERS registers.",
          wrong=2)
def _check_02_2(answer: Any) -> str | None:
    from ..pdu import MAX_READ_REGISTERS

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
          wrong="04 02")
def _check_02_3(answer: Any) -> str | None:
    from ..pdu import ExceptionCode, ExceptionResponse

    expected = ExceptionResponse(function=4, code=ExceptionCode.ILLEGAL_DATA_ADDRESS).encode()
    got = as_bytes(answer)
    if len(got) == 2 and got[0] == expected[0] & 0x7F:
        return ("the first byte must have its top bit set (function code + 0x80): that is what marks "
                "an exception.")
    if len(got) == 2 and got[0] == 0x83:
        return "0x83 answers a read of holding registers (function 3); this read was of input registers."
    if len(got) == 2 and got[0] == expected[0] and got[1] != expected[1]:
        return f"the function byte is right; exception code {got[1]:02X} is not 'illegal data address'."
    return compare_bytes(got, expected, "your exception response")


@exercise("02.4", "which coils are ON",
          hint="in a read-bits response the first coil is the least significant bit (the rightmost) of "
               "the first data byte; 0x05 = 0000 0101 in binary.",
          wrong=[5, 7])
def _check_02_4(answer: Any) -> str | None:
    from ..pdu import ReadCoilsResponse

    bits = ReadCoilsResponse.decode(bytes([0x01, 0x01, 0x05])).bits
    expected = [address for address, bit in enumerate(bits) if bit]
    try:
        got = sorted(int(a) for a in answer)
    except TypeError:
        return "answer with a list of coil addresses, e.g. [1, 4]."
    if got == expected:
        return None
    if got == sorted(7 - a for a in expected):
        return "you read the bits from the left; the first coil is the rightmost (least significant) bit."
    return f"{got} are not the coils that are ON."


def _fc3_pdu(address: int, count: int) -> bytes:
    from ..pdu import ReadHoldingRegistersRequest

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
    hint="the PDU is the function code 3, then the address and the count, each as two bytes high byte first: "
         "bytes([3]) + address.to_bytes(2, 'big') + count.to_bytes(2, 'big'). Refuse (raise) a count outside "
         "1..125 or a range past address 65535.",
    wrong=lambda address, count: bytes([3]) + address.to_bytes(2, "big") + count.to_bytes(2, "big"))
