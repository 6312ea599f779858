"""Exercises of notebook 07: Exceptions and errors."""

from __future__ import annotations

from typing import Any

from ...datamodel import DataBank
from ...errors import ChecksumError, ModbusExceptionError, ModbusTimeoutError, TransactionMismatchError
from ...framing import RtuFrame, parse_hex
from ...links.loopback import loopback_serial
from ...master import Master
from ...pdu import ExceptionCode, ExceptionResponse
from ...slave import Slave
from ..build import build_exercise
from ..core import as_bytes, compare_rtu_frame, exercise, field_diagnosis, named_then, pdu_envelope_diagnosis
from ..diagnosis.frameslip import frame_slip
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.procedures import field_value_procedure


@exercise("07.1", "read an exception response",
          hint="in a response, a function code of 0x80 or more is an exception: subtract 0x80 to get the "
               "request's function; the next byte is the exception code. mb.RtuFrame.decode(..., "
               "role='response').pdu reads it for you.",
          accepts=[(3, 2), [3, 2], (0x03, 0x02)],
          refuses=[((0x83, 2), "exception-code-as-function"), ((3, 3), "exception-code-confused"),
                   ((2, 3), "function-and-code-swapped"), ((3, 0x82), "top-bit-on-code")])
def _check_07_1(answer: Any) -> str | None:
    pdu = RtuFrame.decode(parse_hex("11 83 02 C1 34"), role="response").pdu
    expected = (pdu.function, pdu.code)
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair of ints: (function, code)."
    function, code = answer
    if isinstance(function, bool) or not isinstance(function, int) or not isinstance(code, int):
        return "both numbers should be ints, e.g. (1, 3)."
    if function == pdu.function_code:
        return diagnose("exception-code-as-function", function, expected[0])
    named = diagnose("function-and-code-swapped", (function, code), expected)
    if named:
        return named
    named = field_diagnosis(function, pdu.function_code) or field_diagnosis(function, expected[0])
    if function != expected[0] and named:
        return named + " An exception response's function byte is the request's function + 0x80."
    others = {"slave address": 0x11, "CRC's first byte": 0xC1, "CRC's second byte": 0x34}
    if function != expected[0]:
        named = field_value_procedure(bytes([pdu.function_code]), "function byte", {
            **others, "exception code": expected[1]}).explain([((), function)])
        return named_then(named, f"the request's function is not {function}.")
    if code != expected[1]:
        named = field_diagnosis(code, expected[1]) or diagnose(("top-bit-on-code", "exception-code-confused"),
                                                               code, expected[1])
        if named:
            return named
        named = field_value_procedure(bytes([expected[1]]), "exception code", others).explain([((), code)])
        return named_then(named, f"the exception code is the byte after the function code, not {code}.")
    return None


@exercise("07.2", "the frame slave 17 answers with",
          hint=("a refusal is an exception response: the function code with its top bit set, then the "
                "exception code that says why; in an RTU frame the slave address comes first and the CRC "
                "last.",
                "a coil the slave does not have is exception 02 (illegal data address); read coils is "
                "function 01. mb.ExceptionResponse(function=..., code=...) is that PDU; mb.RtuFrame adds "
                "the address and the CRC.",
                "slave 4 refusing a read of holding registers (FC3) at an address it lacks: 04 83 02 D0 F0."),
          accepts=["11 81 02 C0 54", "118102c054", bytes.fromhex("11 81 02 C0 54")],
          refuses=[("11 01 02 C1 34", "exception-bit-missing"), ("17 81 02 20 55", "decimal-written-as-hex"),
                   ("11 81 02 54 C0", "crc-swapped"), ("11 81 01 80 55", "illegal-function-for-address"),
                   ("11 81 03 01 94", "exception-code-confused"), ("11 81 02", "crc-forgotten")])
def _check_07_2(answer: Any) -> str | None:
    code = int(ExceptionCode.ILLEGAL_DATA_ADDRESS)
    expected = RtuFrame(unit=17, pdu=ExceptionResponse(function=1, code=code)).encode()
    got = as_bytes(answer)
    named = diagnose("crc-swapped", got, expected) or frame_slip(got, expected, tail=2)
    if named:
        return named
    if len(got) > 1 and got[1] == 0x01:
        return name("exception-bit-missing")
    if len(got) > 2 and got[1] == 0x81 and got[2] != expected[2]:
        return (diagnose(("illegal-function-for-address", "exception-code-confused"), got[2], expected[2])
                or f"exception code {got[2]:02X} is not the one for an address the slave does not have.")
    return compare_rtu_frame(got, expected, "your exception response")


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
          accepts=[dict(zip(_SITUATIONS, ("timeout", "timeout", "checksum error", "exception", "mismatch"))),
                   dict(zip(_SITUATIONS, ("Timeout", " timeout", "Checksum error", "EXCEPTION",
                                          "mismatch")))],
          refuses=[(dict.fromkeys(_SITUATIONS, "checksum error"), "answer-to-another-unit"),
                   (dict(zip(_SITUATIONS, ("timeout", "exception", "checksum error", "exception",
                                           "mismatch"))), "answer-to-damaged-request"),
                   (dict(zip(_SITUATIONS, ("timeout", "timeout", "checksum error", "exception",
                                           "timeout"))), None),
                   (dict(zip(_SITUATIONS, ("timeout", "timeout", "timeout", "exception", "mismatch"))),
                    "damaged-response-as-silence"),
                   (dict(zip(_SITUATIONS, ("timeout", "timeout", "checksum error", "timeout", "mismatch"))),
                    "refusal-unanswered"),
                   (dict.fromkeys(_SITUATIONS, "valid"), "answer-to-another-unit")])
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
            named = diagnose("answer-to-another-unit" if situation == _SITUATIONS[0]
                             else ("answer-to-damaged-request", "refusal-unanswered",
                                   "damaged-response-as-silence"),
                             got, expected)
            if named:
                return f"{situation}: {named}"
            return f"{situation}: the master does not see {got!r}."
    return None


def _exception_pdu(function: int, code: int) -> bytes:
    return ExceptionResponse(function=function, code=code).encode()


def _diagnose_exception(got, expected) -> str | None:
    if not isinstance(got, (bytes, bytearray)) or not got:
        return None
    return (pdu_envelope_diagnosis(got, expected) or diagnose("exception-bit-missing", got[0], expected[0])
            or diagnose("exception-function-forgotten", got, expected)
            or (diagnose(("top-bit-on-code", "exception-code-confused"), got[1], expected[1])
                if len(got) == 2 == len(expected) and got[0] == expected[0] else None))


def _exception_inputs(rng) -> tuple:
    return rng.randrange(1, 128), rng.randrange(1, 12)


build_exercise(
    "07.4", "write an exception response",
    reference=_exception_pdu, inputs=_exception_inputs,
    edge_cases=[(3, 2), (16, 1), (1, 4), (127, 11),
                # both ends: the lowest function and code, the gateway codes, a function whose top bit shows
                (1, 1), (6, 3), (4, 10), (43, 11), (64, 2)],
    hint="two bytes: the function code with its top bit set (function | 0x80, or function + 128) and the "
         "exception code.",
    refuses=[(lambda function, code: bytes([function, code]), "exception-bit-missing"),
             (lambda function, code: bytes([function | 0x80, 2]), "exception-code-confused"),
             (lambda function, code: bytes([0x80, code]), "exception-function-forgotten")],
    diagnose=lambda args, expected, got: _diagnose_exception(got, expected))
