"""Exercises of notebook 04: ASCII frames and the LRC."""

from __future__ import annotations

from typing import Any

from ...crc import lrc
from ...crc import lrc as _library_lrc
from ...datamodel import parse_reference
from ...errors import ModbusError
from ...explain import explain
from ...framing import AsciiFrame, RtuFrame, parse_hex
from ...pdu import ReadHoldingRegistersRequest, ReadHoldingRegistersResponse
from ..build import build_exercise
from ..core import (
    AnswerError,
    address_diagnosis,
    as_bytes,
    compare_pdu,
    exercise,
    int_answer,
    line_after_tries,
    request_field_diagnosis,
    right_value_in_another_form,
)
from ..diagnosis.frames import frame_verdict
from ..diagnosis.frameslip import frame_slip
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.procedures import LRC


@exercise("04.1", "an LRC by hand",
          hint=("add the bytes, keep the low 8 bits, then take the two's complement: (256 - sum) % 256.",
                "mb.lrc_trace shows the running sum byte by byte, and mb.lrc checks your result.",
                "for 01 03 00 00 00 0A the sum is 0x0E = 14; 256 - 14 = 242 = 0xF2."),
          accepts=[0x7E, 126],
          refuses=[(0x82, "lrc-plain-sum"), (0x7D, "lrc-ones-complement"), (0xA0, "lrc-of-characters"),
                   (0x7F, None)])
def _check_04_1(answer: Any) -> str | None:
    data = parse_hex("11 03 00 6B 00 03")
    expected = lrc(data)
    got = int_answer(answer, "an LRC")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = LRC.explain([((data,), got)])
    if named:
        return named
    if not 0 <= got <= 0xFF:
        return f"{got} is no byte: an LRC is one byte, 0x00 to 0xFF."
    return f"0x{got:02X} is not the LRC of 11 03 00 6B 00 03."


@exercise("04.2", "build an ASCII frame",
          hint=("44097 is holding register number 4097, address 4096 = 0x1000; an ASCII frame is ':', then "
                "the address, the PDU and the LRC as hex characters, then CR LF.",
                "mb.parse_reference gives the address; mb.AsciiFrame(unit=..., pdu=...) builds the frame, "
                "and its .encode() adds the LRC and CR LF.",
                "slave 2, one register at address 4: b':020300040001F6\\r\\n'."),
          accepts=[":050310000002E6\r\n", b":050310000002E6\r\n",
                   r":050310000002E6\r\n", list(b":050310000002E6\r\n")],
          refuses=[(":050310000002E6", "ascii-without-crlf"), (b":050310000002E6", "ascii-without-crlf"),
                   (":050310010002E5\r\n", "one-based-address"),
                   (":050310000002E5\r\n", "lrc-ones-complement"),
                   (":0503100000021A\r\n", "lrc-plain-sum"),
                   (":050310000002E7\r\n", None), (":050310000002e6\r\n", "another-form")])
def _check_04_2(answer: Any) -> str | None:
    address = parse_reference("44097").address
    expected = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address, count=2)).encode()
    got = ascii_frame_answer(answer)
    named = diagnose("ascii-without-crlf", got, expected)
    if named:
        return named
    off_by_one = AsciiFrame(unit=5, pdu=ReadHoldingRegistersRequest(address=address + 1, count=2)).encode()
    if got.upper() == off_by_one:
        return address_diagnosis(address + 1, address)
    if got == expected:
        return None
    if got.upper() == expected:
        return right_value_in_another_form("upper-case hex digits: the specification writes an ASCII frame's "
                                           "hex characters as '0'-'9' and 'A'-'F' only")
    return (frame_verdict(got.upper(), expected, "ascii") or ascii_frame_diagnosis(got.upper(), expected)
            or compare_characters(got, expected, "your frame"))


def _ascii_bytes(frame: bytes) -> bytes | None:
    """The bytes an ASCII frame's hex characters stand for (address, PDU, LRC), or None."""
    body = frame[1:-2] if frame.endswith(b"\r\n") else frame[1:]
    if not frame.startswith(b":") or len(body) % 2:
        return None
    try:
        return bytes.fromhex(body.decode("ascii"))
    except (UnicodeDecodeError, ValueError):
        return None


def ascii_frame_diagnosis(got: bytes, expected: bytes) -> str | None:
    """Name the catalogued slips in an ASCII frame (upper case): an LRC that is the plain sum, its one's
    complement or computed over the characters, shown as the characters the learner wrote; an LRC without
    the address; a field written wrong (in decimal digits, low byte first, hex read as decimal)."""
    mine, right = _ascii_bytes(got), _ascii_bytes(expected)
    if mine is None or right is None or len(mine) != len(right):
        return None
    if mine[:-1] == right[:-1]:
        named = diagnose(("lrc-plain-sum", "lrc-ones-complement", "lrc-of-characters"), right[:-1], mine[-1])
        if named:
            return f"{named} Your frame carries the characters '{mine[-1]:02X}' where the LRC goes."
    return (diagnose("checksum-without-address", mine, right) or request_field_diagnosis(mine, right, 1, 1)
            or frame_slip(mine, right, tail=1))


def compare_characters(got: bytes, expected: bytes, what: str) -> str | None:
    """Like :func:`~.core.compare_bytes` for a frame of characters: the first character that differs,
    shown as a character (the learner writes characters, not their codes)."""
    for index, (mine, theirs) in enumerate(zip(got, expected)):
        if mine != theirs:
            return (f"{what} differs at character {index}{_character_field(expected, index)}: you have "
                    f"{chr(mine)!r}, it should be {chr(theirs)!r} ({len(got)} characters given, "
                    f"{len(expected)} expected).")
    if len(got) < len(expected):
        return (f"{what} has {len(got)} characters, it should have {len(expected)}; what is missing starts "
                f"with{_character_field(expected, len(got), lead='')}.")
    return f"{what} has {len(got)} characters, it should have {len(expected)}." if got != expected else None


def _character_field(expected: bytes, index: int, lead: str = ", in") -> str:
    """The field of the ASCII frame ``expected`` that character ``index`` belongs to, and what it should
    hold: ", in the function code (characters 3-4), which should hold '03'", or ''."""
    try:
        rows = explain(expected, mode="ascii").rows
    except ModbusError:
        return ""
    for row in rows:
        if row.offset <= index < row.offset + len(row.raw):
            last = row.offset + len(row.raw) - 1
            span = f"character {row.offset}" if last == row.offset else f"characters {row.offset}-{last}"
            return f"{lead} the {row.field} ({span}), which should hold {row.raw.decode('ascii')!r}"
    return ""


def ascii_frame_answer(answer: Any) -> bytes:
    """An ASCII frame exactly as the learner wrote it: text starting with ':' is taken character for
    character (a typed backslash-r backslash-n counts as CR LF), so a missing CR LF stays missing; so is
    text that ends with CR LF or LF (a frame whose ':' is missing)."""
    if isinstance(answer, str) and (answer.lstrip().startswith(":")
                                    or answer.rstrip(" \t").endswith(("\r\n", "\\r\\n", "\n", "\\n"))):
        text = answer.strip(" \t").replace("\\r", "\r").replace("\\n", "\n")
        if len(text) > 600 or not text.isascii():
            raise AnswerError("an ASCII frame is a short text of ':', hex digits and CR LF.")
        return text.encode("ascii")
    return as_bytes(answer)


@exercise("04.3", "the length of an ASCII response",
          hint=("an ASCII frame writes each byte (address, PDU, LRC) as two characters, between ':' and CR "
                "LF.",
                "count the response's bytes first: address, function code, byte count, 2 bytes per "
                "register, LRC; then 2 characters each, plus ':' and the 2 of CR LF.",
                "a response with one register is 1 + 1 + 1 + 2 + 1 = 6 bytes: 1 + 12 + 2 = 15 characters."),
          accepts=[23, 0x17],
          refuses=[(21, "ascii-without-crlf"), (11, "rtu-length-for-ascii"), (10, None),
                   (22, "ascii-colon-forgotten"),
                   (25, "crc-in-ascii"), (17, None)])
def _check_04_3(answer: Any) -> str | None:
    pdu = ReadHoldingRegistersResponse(registers=(0, 0, 0))
    expected = len(AsciiFrame(unit=5, pdu=pdu).encode())
    rtu = len(RtuFrame(unit=5, pdu=pdu).encode())
    got = int_answer(answer, "a number of characters")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    if got == rtu:
        return name("rtu-length-for-ascii") + f" {rtu} bytes are the RTU frame's."
    if got == rtu - 1:
        return "that is the number of bytes (address, PDU, LRC); ASCII writes each as two characters."
    if got == expected - 2:
        return name("ascii-without-crlf") + " Those two characters count too."
    named = diagnose(("ascii-colon-forgotten", "crc-in-ascii"), got, expected)
    if named:
        return named
    return f"{got} is not the number of characters from ':' to CR LF."


@exercise("04.4", "the PDU inside an ASCII frame",
          hint=("an ASCII frame is ':', then the address, the PDU and the LRC written as hex characters, "
                "then CR LF: the PDU is what lies between the address and the LRC.",
                "turn the characters into bytes, two characters a byte, then leave out the first byte (the "
                "address) and the last (the LRC); mb.AsciiFrame.decode(..., role='response') does the same.",
                "in :010600010003F5 the bytes are 01 06 00 01 00 03 F5: the PDU is 06 00 01 00 03."),
          accepts=["03 04 FF 06 00 64", "0304ff060064", bytes.fromhex("0304FF060064")],
          refuses=[("05 03 04 FF 06 00 64", "unit-in-pdu"), ("03 04 FF 06 00 64 8B", "frame-for-pdu"),
                   ("05 03 04 FF 06 00 64 8B", "frame-for-pdu"), (":050304FF0600648B", None),
                   ("04 FF 06 00 64", "function-code-missing")])
def _check_04_4(answer: Any) -> str | None:
    frame = AsciiFrame.decode(parse_hex(":050304FF0600648B"), role="response")
    expected = frame.pdu.encode()
    got = as_bytes(answer)
    if got[:1] == b":":
        return "give the bytes of the PDU, not the ASCII characters of the frame."
    return compare_pdu(got, expected, "your PDU", unit=frame.unit)


def _lrc_inputs(rng) -> tuple:
    return (rng.randbytes(rng.randrange(1, 40)),)


def _diagnose_lrc(args, expected, got) -> str | None:
    return diagnose(("lrc-plain-sum", "lrc-ones-complement", "lrc-of-characters", "lrc-not-8-bits"), args[0],
                    got)


build_exercise(
    "04.5", "write lrc yourself",
    reference=_library_lrc, inputs=_lrc_inputs,
    # every input the task allows: no bytes, one byte, a frame, a sum of 0, longer than 256 bytes
    edge_cases=[(b"",), (b"\x01",), (bytes.fromhex("050610010200"),), (bytes.fromhex("0503100000 02"),),
                (b"\xff" * 3,), (b"\x80\x80",), (bytes(range(256)) + b"\xfe",)],
    hint="add up the bytes and keep the low 8 bits; the LRC is the byte that brings that sum to 0 (modulo "
         "256): its two's complement.",
    refuses=[(lambda data: sum(data) & 0xFF, "lrc-plain-sum"), (lambda data: ~sum(data) & 0xFF,
                                                                "lrc-ones-complement"),
             (lambda data: -sum(data), "lrc-not-8-bits")],
    diagnose=_diagnose_lrc, procedure=LRC)
line_after_tries("04.5", "sum(data) adds the bytes; & 0xFF keeps the low 8 bits of any int; the two's "
                 "complement of a byte x is (256 - x) % 256.",
                 "for 01 03 00 00 00 0A the sum is 14 = 0x0E and 256 - 14 = 242: the LRC is 0xF2.")
