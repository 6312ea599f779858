"""Exercises of notebook 00: Welcome."""

from __future__ import annotations

from typing import Any

from ...framing import RtuFrame, TcpFrame, parse_hex
from ...pdu import ReadHoldingRegistersRequest
from ..core import as_bytes, compare_pdu, compare_rtu_frame, exercise, int_answer
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.procedures import rtu_frame_procedure


@exercise("00.1", "the slave address of a frame",
          hint="the first byte of an RTU frame is the slave address; the bytes are written in hexadecimal.",
          accepts=[17, 0x11], refuses=[(11, "hex-read-as-decimal"), (3, "another-field"), (1, None)])
def _check_00_1(answer: Any) -> str | None:
    text = "11 03 00 6B 00 03 76 87"
    expected = RtuFrame.decode(parse_hex(text)).unit
    got = int_answer(answer, "a slave address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    first = text.split()[0]
    named = diagnose("hex-read-as-decimal", got, first) or diagnose("another-field", got, _fields(text))
    if named:
        return named
    return f"the first byte is 0x{first}; {got} is 0x{got:02X}."


def _fields(text: str) -> dict[str, int]:
    """The fields of an RTU read request after its slave address, by name."""
    frame = parse_hex(text)
    return {"function code": frame[1], "starting address": int.from_bytes(frame[2:4], "big"),
            "count": int.from_bytes(frame[4:6], "big"), "CRC's first byte": frame[6],
            "CRC's second byte": frame[7]}


@exercise("00.2", "the PDU inside a Modbus/TCP frame",
          hint="a Modbus/TCP frame is a 7-byte MBAP header (transaction, protocol, length, unit) followed by "
               "the PDU; the PDU starts with the function code.",
          accepts=["03 00 6B 00 03", "03006b0003", bytes.fromhex("03 00 6B 00 03"), [3, 0, 0x6B, 0, 3]],
          refuses=[("11 03 00 6B 00 03", "unit-in-pdu"), ("00 07 00 00 00 06 11 03 00 6B 00 03",
                                                          "frame-for-pdu"),
                   ("03 00 00 00 01", None)])
def _check_00_2(answer: Any) -> str | None:
    frame = parse_hex("00 07 00 00 00 06 11 03 00 6B 00 03")
    expected = TcpFrame.decode(frame).pdu.encode()
    return compare_pdu(answer, expected, "the PDU", unit=frame[6])


@exercise("00.3", "build your first RTU frame",
          hint=("an RTU frame is the slave address, then the PDU (function code, starting address, "
                "quantity), then the CRC, low byte first; the library builds one from a unit and a request "
                "object.",
                "reading holding registers is function 3: mb.ReadHoldingRegistersRequest(address=..., "
                "count=...) is the PDU; mb.RtuFrame takes the unit and that PDU (pdu=), and its .encode() "
                "adds the CRC.",
                "slave 9, one holding register at address 5: the unit 09, the function 03, the address 00 05 "
                "and the count 00 01, each 2-byte field high byte first, then the CRC of those six bytes, "
                "0x4395, low byte first: 09 03 00 05 00 01 95 43."),
          accepts=["02 03 00 00 00 02 C4 38", "02 03 00 00 00 02 c4 38", bytes.fromhex("020300000002C438")],
          refuses=[("02 03 00 00 00 02 38 C4", "crc-swapped"), ("02 03 00 01 00 02 95 F8",
                                                                "one-based-address"),
                   ("02 03 00 00 00 02", "crc-forgotten"), ("03 00 00 00 02 E1 C1", "unit-missing"),
                   ("00 01 00 00 00 06 02 03 00 00 00 02", "tcp-frame-for-rtu"),
                   (b":020300000002F9\r\n", "ascii-frame-for-rtu")])
def _check_00_3(answer: Any) -> str | None:
    pdu = ReadHoldingRegistersRequest(address=0, count=2)
    expected = RtuFrame(unit=2, pdu=pdu).encode()
    got = as_bytes(answer)
    if got == expected:
        return None
    return rtu_frame_procedure(2, pdu).explain([((), got)]) or compare_rtu_frame(got, expected, "your frame")

