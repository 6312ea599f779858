"""Exercises of notebook 03: RTU frames and the CRC."""

from __future__ import annotations

from typing import Any

from ...crc import crc16, crc_bytes
from ...errors import ModbusError
from ...framing import RtuFrame, parse_hex
from ...pdu import ReadHoldingRegistersResponse, WriteSingleRegisterRequest
from ..build import build_exercise
from ..core import (
    as_bytes,
    compare_bytes,
    compare_rtu_frame,
    exercise,
    int_answer,
    right_value_in_another_form,
)
from ..diagnosis.frameslip import frame_slip
from ..diagnosis.misconceptions import crc16_reflected, crc16_unreflected, crc_bit_loop, name
from ..diagnosis.procedures import CRC, CRC_WIRE, response_length_procedure, rtu_frame_procedure


@exercise("03.1", "a CRC in wire order",
          hint=("compute the CRC over the frame's bytes (mb.crc16 gives the register value); on the wire "
                "its low byte goes first.",
                "split the register value into its two bytes: 0xABCD is AB (high) and CD (low); the wire "
                "order is CD AB.",
                "for 01 03 00 00 00 01 the register value is 0x0A84, and the frame ends 84 0A."),
          accepts=["B2 98", "b298", b"\xb2\x98", [0xB2, 0x98]],
          refuses=[("98 B2", "crc-swapped"), (0x98B2, "another-form"), ("76 87", None),
                   ("B2", "crc-one-byte"),
                   ("11 04 00 08 00 01 B2 98", "another-question")])
def _check_03_1(answer: Any) -> str | None:
    data = parse_hex("11 04 00 08 00 01")
    expected = crc_bytes(data)
    if answer == crc16(data) and not isinstance(answer, bool):
        return right_value_in_another_form("the two bytes in the order they are sent, low byte first")
    if isinstance(answer, int) and not isinstance(answer, bool):
        return (f"0x{answer:04X} is a number; give the two bytes in the order they are sent, "
                f"e.g. \"12 34\" or bytes([0x12, 0x34]).")
    got = as_bytes(answer)
    return CRC_WIRE.explain([((data,), got)]) or compare_bytes(got, expected, "your CRC")


@exercise("03.2", "build an RTU frame",
          hint=("an RTU frame is the slave address, the PDU, then the CRC low byte first; function 6's PDU "
                "is 06, the address and the value, 2 bytes each, high byte first. The address goes in as it "
                "is: 2 is sent as 00 02.",
                "mb.WriteSingleRegisterRequest(address=..., value=...) is the PDU; mb.RtuFrame(unit=..., "
                "pdu=...) wraps it, and .encode() appends the CRC.",
                "slave 3, 0x00FF into address 7: 03 06 00 07 00 FF 79 A9."),
          accepts=["01 06 00 02 12 34 25 7D", "01060002123425 7d", bytes.fromhex("010600021234257D")],
          refuses=[("01 06 00 02 12 34 7D 25", "crc-swapped"), ("01 06 00 03 12 34 74 BD",
                                                                "one-based-address"),
                   ("01 06 00 02 12 34", "crc-forgotten"), ("01 06 00 02 12 34 25 7E", None),
                   ("01 06 00 02 34 12 BE C7", "field-low-byte-first"),
                   ("01 06 02 00 12 34 85 05", "field-low-byte-first"),
                   ("01 06 00 02 04 D2 AA 97", "hex-read-as-decimal"),
                   ("01 06 00 02 12 34 00 B7", "checksum-without-address")])
def _check_03_2(answer: Any) -> str | None:
    pdu = WriteSingleRegisterRequest(address=2, value=0x1234)
    expected = RtuFrame(unit=1, pdu=pdu).encode()
    got = as_bytes(answer)
    if got == expected:
        return None
    return (rtu_frame_procedure(1, pdu).explain([((), got)]) or frame_slip(got, expected, tail=2)
            or compare_rtu_frame(got, expected, "your frame"))


@exercise("03.3", "will the slave answer?",
          hint="a slave answers only a frame whose CRC is right; check it with mb.RtuFrame.decode or "
               "mb.explain. Answer True or False.",
          accepts=[False], refuses=[(True, "answer-to-damaged-request"), ("no", None)])
def _check_03_3(answer: Any) -> str | None:
    try:
        RtuFrame.decode(parse_hex("11 03 00 6B 00 03 76 86"))
        expected = True
    except ModbusError:
        expected = False
    if not isinstance(answer, bool):
        return "answer True or False."
    if answer == expected:
        return None
    return (name("answer-to-damaged-request") + " Here the frame carries 0x8676, but the CRC of its first "
            "six bytes is different.")


@exercise("03.4", "the length of an FC3 response",
          hint="an RTU response to read holding registers: address (1) + function (1) + byte count (1) "
               "+ 2 bytes per register + CRC (2).",
          accepts=[45], refuses=[(43, "crc-forgotten"), (25, "register-one-byte"), (44, None),
                                 (40, "data-bytes-only"), (8, "another-question"), (85, None)])
def _check_03_4(answer: Any) -> str | None:
    expected = len(RtuFrame(unit=1, pdu=ReadHoldingRegistersResponse(registers=[0] * 20)).encode())
    got = int_answer(answer, "a number of bytes")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = response_length_procedure(20, mbap=False).explain([((), got)])
    if named:
        return named
    return f"{got} bytes is not the length of that response."


def _crc_inputs(rng) -> tuple:
    """Mostly short messages, one in ten longer than 256 bytes."""
    return (rng.randbytes(rng.randrange(1, 64) if rng.random() < 0.9 else rng.randrange(257, 700)),)


def _crc_without_final_step(data: bytes) -> int:
    """A plausible wrong CRC: the right loop, but the register starts at 0 (CRC-16/ARC)."""
    return crc16_reflected(data, initial=0)


def _crc_swapped(data: bytes) -> int:
    """A plausible wrong CRC: the register with its two bytes swapped, as they travel."""
    value = crc16(data)
    return (value & 0xFF) << 8 | value >> 8


build_exercise(
    "03.5", "write crc16 yourself",
    reference=crc16,
    inputs=_crc_inputs,
    # every input the task allows: no bytes, one byte, a frame, and longer than 256 bytes ("any data")
    edge_cases=[(b"",), (b"\x00",), (b"\xff",), (b"123456789",), (bytes.fromhex("11 03 00 6B 00 03"),),
                (bytes(range(256)) + b"\x01",), (b"\xa5" * 600,)],
    hint=("CRC-16/MODBUS: a 16-bit register starts at 0xFFFF; each byte is XORed into it, then the register "
          "is shifted right 8 times, and each time the bit that falls out is 1 it is XORed with 0xA001.",
          "two loops: one over the bytes, and inside it one of 8 shifts; test the lowest bit (register & 1) "
          "before you shift it out. Return the register as an int.",
          "the byte 0x01: 0xFFFF ^ 0x01 = 0xFFFE; the 8 shifts give 0x7FFF, 0x9FFE, 0x4FFF, 0x87FE, 0x43FF, "
          "0x81FE, 0x40FF, 0x807E: the CRC of 01 is 0x807E."),
    refuses=[(_crc_without_final_step, "crc-initial-zero"), (_crc_swapped, "crc-swapped"),
             (crc16_unreflected, "crc-msb-first"), (lambda data: crc16(data).to_bytes(2, "little"),
                                                    "crc-as-bytes"),
             (lambda data: crc16(data) & 0xFF, "crc-one-byte"),
             (lambda data: crc_bit_loop(data, test_after=True), "crc-bit-loop"),
             (lambda data: crc16(data[:256]), "crc-not-every-byte")],
    procedure=CRC)
