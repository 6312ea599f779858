"""Exercises of notebook 05: Modbus/TCP and the MBAP header."""

from __future__ import annotations

from typing import Any

from ..explain import explain
from ..framing import TcpFrame, parse_hex
from ..pdu import (
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    WriteMultipleRegistersRequest,
    WriteSingleRegisterRequest,
    decode_pdu,
)
from .build import build_exercise
from .core import as_bytes, compare_bytes, exercise, int_answer


@exercise("05.1", "read a transaction id",
          hint="the transaction identifier is bytes 0-1 of the MBAP header, big-endian (high byte first).",
          wrong=10752)
def _check_05_1(answer: Any) -> str | None:
    frame = parse_hex("00 2A 00 00 00 06 11 03 00 6B 00 03")
    expected = TcpFrame.decode(frame).transaction_id
    got = int_answer(answer, "a transaction id")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == int.from_bytes(frame[:2], "little"):
        return "you read the two bytes low byte first; every MBAP field is big-endian."
    return f"{got} is not the transaction id of that frame."


@exercise("05.2", "build a Modbus/TCP frame",
          hint="mb.TcpFrame(transaction_id=..., unit=..., pdu=mb.WriteSingleRegisterRequest(address=..., "
               "value=...)).encode(); the length field counts the unit identifier and the PDU.",
          wrong="07 00 00 00 00 06 01 06 00 00 04 D2")
def _check_05_2(answer: Any) -> str | None:
    pdu = WriteSingleRegisterRequest(address=0, value=1234)
    expected = TcpFrame(transaction_id=7, unit=1, pdu=pdu).encode()
    got = as_bytes(answer)
    if got == expected:
        return None
    if len(got) == len(expected) and got[2:] == expected[2:] and got[:2] == expected[1::-1]:
        return "the transaction id is written low byte first; every MBAP field is big-endian."
    if len(got) == len(expected) and got[:4] == expected[:4] and got[6:] == expected[6:]:
        return (f"the length field is wrong: it counts the bytes after it, the unit identifier and the PDU "
                f"({expected[5]} bytes), big-endian.")
    return compare_bytes(got, expected, "your frame")


@exercise("05.3", "the MBAP length of a response",
          hint="the length counts the bytes after the length field: unit identifier (1) + function code (1) "
               "+ byte count (1) + 2 bytes per register.",
          wrong=22)
def _check_05_3(answer: Any) -> str | None:
    frame = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersResponse(registers=[0] * 10)).encode()
    expected = int.from_bytes(frame[4:6], "big")
    got = int_answer(answer, "a length")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == expected - 1:
        return "the length also counts the unit identifier."
    if got == len(frame):
        return "that is the whole frame; the length counts only the bytes after the length field."
    return f"{got} is not the length field of that response."


@exercise("05.4", "spot the wrong MBAP field",
          hint="decode the frame with mb.explain(frame, mode='tcp'): the row marked as a problem is the one. "
               "Answer with the field's name, e.g. 'protocol identifier'.",
          wrong="transaction identifier")
def _check_05_4(answer: Any) -> str | None:
    dissection = explain("01 18 00 00 06 00 01 03 00 00 00 01", mode="tcp")
    expected = next(row.field for row in dissection.rows if not row.ok)
    if not isinstance(answer, str):
        return "answer with the name of a field, as a string."
    got = answer.strip().lower()
    if got and (got == expected or (got in expected and len(got) >= 4)):
        return None
    if "transaction" in got:
        return ("0x0118 is a perfectly good transaction id (big-endian, 280); look at the field that must "
                "count the bytes that follow.")
    return f"{answer!r} is right in that frame; another field is not."


def _mbap_header(tid: int, unit: int, pdu: bytes) -> bytes:
    return TcpFrame(transaction_id=tid, unit=unit, pdu=decode_pdu(pdu, "request")).encode()[:7]


def _mbap_inputs(rng) -> tuple:
    if rng.random() < 0.5:
        pdu = ReadHoldingRegistersRequest(address=rng.randrange(65000), count=rng.randrange(1, 126))
    else:
        values = [rng.randrange(65536) for _ in range(rng.randrange(1, 20))]
        pdu = WriteMultipleRegistersRequest(address=rng.randrange(65000), values=values)
    return rng.randrange(65536), rng.randrange(256), pdu.encode()


def _diagnose_mbap(args, expected, got) -> str | None:
    if not isinstance(got, (bytes, bytearray)) or len(got) != 7:
        return None
    if got[:2] == expected[1::-1] and got[2:] == expected[2:]:
        return "your transaction id is low byte first; every MBAP field goes high byte first."
    if got[:4] == expected[:4] and got[6] == expected[6] and int.from_bytes(got[4:6], "big") == len(args[2]):
        return "the length counts the bytes after it: the unit identifier (1) and the PDU."
    return None


build_exercise(
    "05.5", "write the MBAP header yourself",
    reference=_mbap_header, inputs=_mbap_inputs,
    edge_cases=[(280, 1, bytes.fromhex("03 00 00 00 01")), (0, 0, bytes.fromhex("03 00 00 00 01")),
                (65535, 255, bytes.fromhex("03 00 6B 00 03"))],
    hint="seven bytes: transaction id (2 bytes), protocol id 0 (2 bytes), length = 1 + len(pdu) (2 bytes), "
         "unit (1 byte); every 2-byte field high byte first: tid.to_bytes(2, 'big').",
    wrong=lambda tid, unit, pdu: tid.to_bytes(2, "little") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big")
    + bytes([unit]),
    diagnose=_diagnose_mbap)
