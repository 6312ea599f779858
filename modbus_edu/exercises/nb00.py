"""Exercises of notebook 00: Welcome."""

from __future__ import annotations

from typing import Any

from .core import as_bytes, compare_bytes, compare_rtu_frame, exercise, int_answer


@exercise("00.1", "the slave address of a frame",
          hint="the first byte of an RTU frame is the slave address; the bytes are written in hexadecimal.",
          wrong=11)
def _check_00_1(answer: Any) -> str | None:
    from ..framing import RtuFrame, parse_hex

    text = "11 03 00 6B 00 03 76 87"
    expected = RtuFrame.decode(parse_hex(text)).unit
    got = int_answer(answer, "a slave address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    first = text.split()[0]
    if got == int(first):
        return (f"{got} reads the hex digits '{first}' as a decimal number; the byte is 0x{first}, "
                f"which is {expected} in decimal (int('{first}', 16)).")
    return f"the first byte is 0x{first}; {got} is 0x{got:02X}."


@exercise("00.2", "the PDU inside a Modbus/TCP frame",
          hint="a Modbus/TCP frame is a 7-byte MBAP header (transaction, protocol, length, unit) followed by "
               "the PDU; the PDU starts with the function code.",
          wrong="11 03 00 6B 00 03")
def _check_00_2(answer: Any) -> str | None:
    from ..framing import TcpFrame, parse_hex

    frame = parse_hex("00 07 00 00 00 06 11 03 00 6B 00 03")
    expected = TcpFrame.decode(frame).pdu.encode()
    got = as_bytes(answer)
    if got == frame[6:]:
        return "you included the unit identifier (byte 6): it belongs to the MBAP header, not to the PDU."
    return compare_bytes(got, expected, "the PDU")


@exercise("00.3", "build your first RTU frame",
          hint="mb.RtuFrame(unit=..., pdu=mb.ReadHoldingRegistersRequest(address=..., count=...)).encode()",
          wrong="02 03 00 00 00 02 38 C4")
def _check_00_3(answer: Any) -> str | None:
    from ..framing import RtuFrame
    from ..pdu import ReadHoldingRegistersRequest

    expected = RtuFrame(unit=2, pdu=ReadHoldingRegistersRequest(address=0, count=2)).encode()
    return compare_rtu_frame(answer, expected, "your frame", "the CRC bytes are in the wrong order: "
                             "the low byte goes first.")
