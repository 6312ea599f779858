"""Exercises of notebook 04: ASCII frames and the LRC."""

from __future__ import annotations

from typing import Any

from ..crc import lrc as _library_lrc
from .build import build_exercise
from .core import as_bytes, compare_bytes, exercise, int_answer


@exercise("04.1", "an LRC by hand",
          hint="add the bytes, keep the low 8 bits, then take the two's complement: (256 - sum) % 256; "
               "mb.lrc(data) does it all.",
          wrong=0x82)
def _check_04_1(answer: Any) -> str | None:
    from ..crc import lrc
    from ..framing import parse_hex

    data = parse_hex("11 03 00 6B 00 03")
    expected = lrc(data)
    got = int_answer(answer, "an LRC")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == sum(data) & 0xFF:
        return f"0x{got:02X} is the 8-bit sum; the LRC is its two's complement (256 minus the sum)."
    if got == lrc(data.hex().upper().encode("ascii")):
        return "you added the hex characters; the LRC adds the bytes they stand for."
    return f"0x{got:02X} is not the LRC of 11 03 00 6B 00 03."


@exercise("04.2", "build an ASCII frame",
          hint="44097 is holding register number 4097, address 4096 = 0x1000; mb.AsciiFrame(unit=..., "
               "pdu=mb.ReadHoldingRegistersRequest(address=..., count=...)).encode().",
          wrong=":050310010002E5\r\n")
def _check_04_2(answer: Any) -> str | None:
    from ..datamodel import parse_reference
    from ..framing import AsciiFrame
    from ..pdu import ReadHoldingRegistersRequest

    address = parse_reference("44097").address
    expected = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address, count=2)).encode()
    got = as_bytes(answer)
    if got == expected[:-2]:
        return "an ASCII frame ends with CR LF (b'\\r\\n')."
    off_by_one = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address + 1, count=2)).encode()
    if got.upper() == off_by_one:
        return "the address is the register number minus one: 44097 is number 4097, address 4096."
    if got.upper() == expected:
        return None  # lowercase hex digits are allowed too
    return compare_bytes(got, expected, "your frame")


@exercise("04.3", "the length of an ASCII response",
          hint="an ASCII frame writes each byte (address, PDU, LRC) as two characters, between ':' and "
               "CR LF; the response to a read of 3 registers has the address, function code, byte count, "
               "6 data bytes and the LRC. len(mb.AsciiFrame(unit=5, pdu=...).encode()) counts them.",
          wrong=11)
def _check_04_3(answer: Any) -> str | None:
    from ..framing import AsciiFrame, RtuFrame
    from ..pdu import ReadHoldingRegistersResponse

    pdu = ReadHoldingRegistersResponse(registers=(0, 0, 0))
    expected = len(AsciiFrame(unit=5, pdu=pdu).encode())
    rtu = len(RtuFrame(unit=5, pdu=pdu).encode())
    got = int_answer(answer, "a number of characters")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == rtu:
        return f"{rtu} is the length of the RTU frame, in bytes; ASCII writes every byte as two characters."
    if got == rtu - 1:
        return "that is the number of bytes (address, PDU, LRC); ASCII writes each as two characters."
    if got == expected - 2:
        return "CR LF, the two characters that end the frame, count too."
    if got == expected - 1:
        return "the ':' that starts the frame counts too."
    if got == 2 * rtu + 3:
        return "an ASCII frame carries a 1-byte LRC, not RTU's 2-byte CRC."
    return f"{got} is not the number of characters from ':' to CR LF."


@exercise("04.4", "the PDU inside an ASCII frame",
          hint="decode the frame (mb.AsciiFrame.decode(frame, role='response')) and encode its .pdu; "
               "the PDU starts with the function code, after the address.",
          wrong="05 03 04 FF 06 00 64")
def _check_04_4(answer: Any) -> str | None:
    from ..framing import AsciiFrame, parse_hex

    frame = AsciiFrame.decode(parse_hex(":050304FF0600648B"), role="response")
    expected = frame.pdu.encode()
    got = as_bytes(answer)
    if got == bytes([frame.unit]) + expected:
        return "the first byte, 05, is the slave address: it belongs to the envelope, not to the PDU."
    if got == expected + b"\x8B":
        return "the last byte, 8B, is the LRC: it belongs to the envelope, not to the PDU."
    if got[:1] == b":":
        return "give the bytes of the PDU, not the ASCII characters of the frame."
    return compare_bytes(got, expected, "your PDU")


def _lrc_inputs(rng) -> tuple:
    return (rng.randbytes(rng.randrange(1, 40)),)


def _diagnose_lrc(args, expected, got) -> str | None:
    total = sum(args[0]) & 0xFF
    if got == total:
        return "that is the 8-bit sum itself; the LRC is its two's complement, (-sum) & 0xFF."
    if got == (~total) & 0xFF:
        return "that is the one's complement (every bit inverted); the two's complement adds 1 to it."
    if isinstance(got, int) and got > 255:
        return "keep only the low 8 bits: & 0xFF."
    return None


build_exercise(
    "04.5", "write lrc yourself",
    reference=_library_lrc, inputs=_lrc_inputs,
    edge_cases=[(b"",), (bytes.fromhex("050610010200"),), (bytes.fromhex("0503100000 02"),), (b"\xff" * 3,)],
    hint="add up the bytes, keep the low 8 bits, and take the two's complement: (-sum(data)) & 0xFF.",
    wrong=lambda data: sum(data) & 0xFF, diagnose=_diagnose_lrc)
