"""Exercises of notebook 05: Modbus/TCP and the MBAP header."""

from __future__ import annotations

import re
from typing import Any

from ...explain import explain
from ...framing import TcpFrame, parse_hex
from ...pdu import (
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    WriteMultipleRegistersRequest,
    WriteSingleRegisterRequest,
    decode_pdu,
)
from ..build import build_exercise
from ..core import as_bytes, compare_bytes, exercise, int_answer, pdu_address_diagnosis, tcp_frame_diagnosis
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.procedures import MBAP, field_value_procedure, response_length_procedure


@exercise("05.1", "read a transaction id",
          hint="the transaction identifier is bytes 0-1 of the MBAP header, big-endian (high byte first).",
          accepts=[42, 0x2A], refuses=[(10752, "mbap-little-endian"), (43, None)])
def _check_05_1(answer: Any) -> str | None:
    frame = parse_hex("00 2A 00 00 00 06 11 03 00 6B 00 03")
    expected = TcpFrame.decode(frame).transaction_id
    got = int_answer(answer, "a transaction id")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    others = {"protocol identifier": 0, "length field": int.from_bytes(frame[4:6], "big"),
              "unit identifier": frame[6], "function code": frame[7],
              "starting address": int.from_bytes(frame[8:10], "big"),
              "quantity": int.from_bytes(frame[10:12], "big")}
    named = diagnose("mbap-little-endian", got, expected) or field_value_procedure(
        frame[:2], "transaction id", others).explain([((), got)])
    if named:
        return named
    return f"{got} is not the transaction id of that frame."


@exercise("05.2", "build a Modbus/TCP frame",
          hint=("a Modbus/TCP frame is the 7-byte MBAP header (transaction id, protocol id 0, length, unit) "
                "and then the PDU; the length counts the unit identifier and the PDU.",
                "function 6's PDU is 06, the address and the value (2 bytes each, high byte first); "
                "mb.TcpFrame(transaction_id=..., unit=..., pdu=...) computes the length for you.",
                "transaction 9, unit 2, 500 into address 3: 00 09 00 00 00 06 02 06 00 03 01 F4."),
          accepts=["00 07 00 00 00 06 01 06 00 00 04 D2", "0007000000060106000004d2",
                   bytes.fromhex("00 07 00 00 00 06 01 06 00 00 04 D2")],
          refuses=[("07 00 00 00 00 06 01 06 00 00 04 D2", "mbap-little-endian"),
                   ("00 07 00 00 06 00 01 06 00 00 04 D2", "mbap-little-endian"),
                   ("00 07 00 00 00 05 01 06 00 00 04 D2", "mbap-length"),
                   ("00 07 00 00 00 08 01 06 00 00 04 D2 89 B5", "crc-on-tcp"),
                   ("00 07 00 00 00 06 01 06 00 01 04 D2", "one-based-address"),
                   ("00 07 00 00 00 06 01 06 00 00 04 D3", None),
                   ("00 07 00 00 00 06 01 06 00 00 12 34", "decimal-written-as-hex"),
                   ("00 07 00 00 00 06 01 06 00 00 D2 04", "field-low-byte-first"),
                   ("00 07 00 00 01 06 00 00 04 D2", "mbap-length-missing")])
def _check_05_2(answer: Any) -> str | None:
    pdu = WriteSingleRegisterRequest(address=0, value=1234)
    expected = TcpFrame(transaction_id=7, unit=1, pdu=pdu).encode()
    got = as_bytes(answer)
    if got == expected:
        return None
    named = (pdu_address_diagnosis(got[7:], expected[7:]) if got[:7] == expected[:7] else None) or \
        tcp_frame_diagnosis(got, expected)
    if named:
        return named
    if len(got) == len(expected) and got[:4] == expected[:4] and got[6:] == expected[6:]:
        return f"the length field is wrong: it counts the unit identifier and the PDU ({expected[5]})."
    return compare_bytes(got, expected, "your frame")


@exercise("05.3", "the MBAP length of a response",
          hint="the length counts the bytes after the length field: unit identifier (1) + function code (1) "
               "+ byte count (1) + 2 bytes per register.",
          accepts=[23, 0x17], refuses=[(22, "mbap-length"), (29, "mbap-length"), (25, None),
                                       (20, "data-bytes-only"), (6, "another-question"),
                                       (13, "register-one-byte")])
def _check_05_3(answer: Any) -> str | None:
    frame = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersResponse(registers=[0] * 10)).encode()
    expected = int.from_bytes(frame[4:6], "big")
    got = int_answer(answer, "a length")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = response_length_procedure(10, mbap=True).explain([((), got)]) or diagnose("mbap-length", got,
                                                                                      expected)
    if named:
        return named
    return f"{got} is not the length field of that response."


@exercise("05.4", "spot the wrong MBAP field",
          hint=("each MBAP field holds a fixed value or one the rest of the frame fixes: check each field "
                "against the bytes of the frame.",
                "transaction id: any value; protocol identifier: 0; length: the number of bytes after the "
                "length field (the unit and the PDU), high byte first; unit: the server's. "
                "mb.explain(frame, mode='tcp') checks a frame for you.",
                "in 00 01 00 01 00 06 01 03 00 00 00 01 the protocol identifier is 00 01, where it must be "
                "00 00."),
          accepts=["length", "Length field", "the length", "the length field", "LENGTH", "MBAP length",
                   "length field (bytes 4-5)", "Length"],
          refuses=[("transaction identifier", None), ("protocol id", None), ("unit identifier", None),
                   ("lenght of the header", None), ("", None)])
def _check_05_4(answer: Any) -> str | None:
    dissection = explain("01 18 00 00 06 00 01 03 00 00 00 01", mode="tcp")
    fields = [row.field for row in dissection.rows]
    expected = next(row.field for row in dissection.rows if not row.ok)
    if not isinstance(answer, str):
        return "answer with the name of a field, as a string."
    got = _field_name(answer, fields)
    if got == expected:
        return None
    if got is None:
        return (f"{answer.strip()!r} is not the name of a field of that frame; its fields are "
                f"{', '.join(fields)}.")
    if got == "transaction identifier":
        return ("0x0118 is a perfectly good transaction id (big-endian, 280); look at the field that must "
                "count the bytes that follow.")
    return f"the {got} of that frame holds what it should; another field does not."


def _field_name(answer: str, fields: list[str]) -> str | None:
    """The field of ``fields`` that ``answer`` names ("the Length field", "protocol id", "MBAP length"),
    or None."""
    words = [word for word in re.findall(r"[a-z]+", answer.lower())
             if word not in ("the", "field", "mbap", "header", "s", "bytes", "byte")]
    if not words:
        return None
    aliases = {"id": "identifier", "tid": "transaction identifier", "pid": "protocol identifier",
               "len": "length"}
    text = " ".join(aliases.get(word, word) for word in words)
    matches = [field for field in fields if text == field or text in field.split()
               or (len(text) >= 4 and field.startswith(text))]
    return matches[0] if len(matches) == 1 else None


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
    return tcp_frame_diagnosis(got, expected) or diagnose("frame-for-header", got, expected)


build_exercise(
    "05.5", "write the MBAP header yourself",
    reference=_mbap_header, inputs=_mbap_inputs,
    edge_cases=[(280, 1, bytes.fromhex("03 00 00 00 01")), (0, 0, bytes.fromhex("03 00 00 00 01")),
                (65535, 255, bytes.fromhex("03 00 6B 00 03")),
                # the longest request PDU: 123 registers written, 252 bytes (length 253)
                (1, 1, WriteMultipleRegistersRequest(address=0, values=[0xABCD] * 123).encode())],
    hint=("seven bytes: transaction id (2 bytes), protocol id 0 (2 bytes), length = 1 + len(pdu) (2 bytes), "
          "unit (1 byte); every 2-byte field high byte first.",
          "an int's .to_bytes(2, 'big') gives its two bytes high byte first; bytes([unit]) gives one byte; "
          "+ joins bytes.",
          "transaction 300, unit 9, a 5-byte PDU: 01 2C | 00 00 | 00 06 | 09."),
    refuses=[(lambda tid, unit, pdu: tid.to_bytes(2, "little") + bytes(2) + (len(pdu) + 1).to_bytes(2, "big")
              + bytes([unit]), "mbap-little-endian"),
             (lambda tid, unit, pdu: tid.to_bytes(2, "big") + bytes(2) + len(pdu).to_bytes(2, "big")
              + bytes([unit]), "mbap-length"),
             (lambda tid, unit, pdu: _mbap_header(tid, unit, pdu) + bytes(pdu), "frame-for-header")],
    diagnose=_diagnose_mbap, procedure=MBAP)
