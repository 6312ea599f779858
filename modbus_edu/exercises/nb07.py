"""Exercises of notebook 07: Exceptions and errors."""

from __future__ import annotations

from typing import Any

from .build import build_exercise
from .core import as_bytes, compare_bytes, exercise


@exercise("07.1", "read an exception response",
          hint="in a response, a function code of 0x80 or more is an exception: subtract 0x80 to get the "
               "request's function; the next byte is the exception code. mb.RtuFrame.decode(..., "
               "role='response').pdu reads it for you.",
          wrong=(0x83, 2))
def _check_07_1(answer: Any) -> str | None:
    from ..framing import RtuFrame, parse_hex

    pdu = RtuFrame.decode(parse_hex("11 83 02 C1 34"), role="response").pdu
    expected = (pdu.function, pdu.code)
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair of ints: (function, code)."
    function, code = answer
    if isinstance(function, bool) or not isinstance(function, int) or not isinstance(code, int):
        return "both numbers should be ints, e.g. (1, 3)."
    if function == pdu.function_code:
        return (f"0x{function:02X} is the function code *of the response*, with the exception bit set; "
                "the request's function is that minus 0x80.")
    if function != expected[0]:
        return f"the request's function is not {function}."
    if code != expected[1]:
        return f"the exception code is the byte after the function code, not {code}."
    return None


@exercise("07.2", "build an exception response",
          hint="unit 17, function code 1 + 0x80, exception code 02 (illegal data address): "
               "mb.RtuFrame(unit=17, pdu=mb.ExceptionResponse(function=..., code=...)).encode()",
          wrong="11 01 02 C1 34")
def _check_07_2(answer: Any) -> str | None:
    from ..framing import RtuFrame
    from ..pdu import ExceptionCode, ExceptionResponse

    code = int(ExceptionCode.ILLEGAL_DATA_ADDRESS)
    expected = RtuFrame(unit=17, pdu=ExceptionResponse(function=1, code=code)).encode()
    got = as_bytes(answer)
    if got[:1] == b"\x17":
        return "17 is decimal: the slave address byte is 17 = 0x11, not 0x17."
    if len(got) > 1 and got[1] == 0x01:
        return "an exception response sets the top bit of the function code: 0x01 becomes 0x81."
    if len(got) > 2 and got[1] == 0x81 and got[2] != expected[2]:
        return f"exception code {got[2]:02X} is not the one for an address the slave does not have."
    return compare_bytes(got, expected, "your exception response")


_OUTCOMES = ("valid", "exception", "timeout", "checksum error", "mismatch")
_SITUATIONS = (
    "request for a unit nobody has",
    "one bit flipped in the request",
    "one bit flipped in the response",
    "read of an address the slave does not have",
    "response carries another unit id",
)


def _outcome_of(situation: str) -> str:
    """Run one situation of exercise 07.3 on a loopback wire and name what the master saw."""
    from ..datamodel import DataBank
    from ..errors import ChecksumError, ModbusExceptionError, ModbusTimeoutError, TransactionMismatchError
    from ..links.loopback import loopback_serial
    from ..master import Master
    from ..slave import Slave

    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 10)
    link = loopback_serial(Slave(unit=1, bank=bank), seed=0)
    master = Master(link, timeout=0.1)
    unit, address = 1, 0
    if situation == _SITUATIONS[0]:
        unit = 5
    elif situation == _SITUATIONS[1]:
        link.faults.flip_bits(1, target="request")
    elif situation == _SITUATIONS[2]:
        link.faults.flip_bits(1, target="response")
    elif situation == _SITUATIONS[3]:
        address = 100
    else:
        link.faults.answer_as(1, 2)
    try:
        master.read_holding_registers(unit=unit, address=address, count=1)
    except ModbusExceptionError:
        return "exception"
    except ChecksumError:
        return "checksum error"
    except TransactionMismatchError:
        return "mismatch"
    except ModbusTimeoutError:
        return "timeout"
    return "valid"


@exercise("07.3", "what the master sees",
          hint="silence (no answer) is a timeout; a damaged answer is a checksum error; a refusal is an "
               "exception; an answer from the wrong unit is a mismatch. Try each on mb.loopback_serial "
               "with link.faults.",
          wrong=dict.fromkeys(_SITUATIONS, "checksum error"))
def _check_07_3(answer: Any) -> str | None:
    if not isinstance(answer, dict):
        return "answer with a dict {situation: outcome}, using the five situations of the exercise."
    missing = [s for s in _SITUATIONS if s not in answer]
    if missing:
        return f"the dict has no entry for {missing[0]!r}."
    for situation in _SITUATIONS:
        got = str(answer[situation]).strip().lower()
        if got not in _OUTCOMES:
            return f"{answer[situation]!r} is not one of {', '.join(_OUTCOMES)}."
        expected = _outcome_of(situation)
        if got != expected:
            if expected == "timeout" and got == "checksum error":
                return (f"{situation}: the slave cannot trust a damaged request or ignores one for another "
                        "unit; it stays silent, so the master sees no frame to check.")
            return f"{situation}: the master does not see {got!r}."
    return None


def _exception_pdu(function: int, code: int) -> bytes:
    from ..pdu import ExceptionResponse

    return ExceptionResponse(function=function, code=code).encode()


def _exception_inputs(rng) -> tuple:
    return rng.randrange(1, 128), rng.randrange(1, 12)


build_exercise(
    "07.4", "write an exception response",
    reference=_exception_pdu, inputs=_exception_inputs,
    edge_cases=[(3, 2), (16, 1), (1, 4), (127, 11)],
    hint="two bytes: the function code with its top bit set (function | 0x80, or function + 128) and the "
         "exception code.",
    wrong=lambda function, code: bytes([function, code]))
