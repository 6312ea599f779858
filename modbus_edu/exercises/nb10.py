"""Exercises of notebook 10: A power meter."""

from __future__ import annotations

from typing import Any

from .build import build_exercise
from .core import close, exercise, number_answer, real_answer


@exercise("10.1", "a voltage from a register pair",
          hint="the two registers after the byte count form one 32-bit number, high word first; VL2 is in "
               "tenths of a volt. METER_BY_NAME['VL2'].value(registers) does both steps.",
          wrong=4105)
def _check_10_1(answer: Any) -> str | None:
    from ..devices.meter import METER_BY_NAME
    from ..framing import RtuFrame, parse_hex
    from ..values import decode_value

    registers = RtuFrame.decode(parse_hex("01 03 04 00 00 10 09 37 F5"), role="response").pdu.registers
    expected = METER_BY_NAME["VL2"].value(registers)
    got = real_answer(answer, "a voltage in volts")
    if isinstance(got, str):
        return got
    raw = decode_value(registers, "uint32", "ABCD")
    if close(got, raw):
        return "that is the raw register value; the map says V x 10: divide by 10."
    if close(got, decode_value(registers, "uint32", "CDAB") / 10):
        return "you put the words in the wrong order: the high word (0x0000) comes first."
    return number_answer(got, expected, decimals=1, unit="V", what="what those registers carry")


@exercise("10.2", "the registers that carry a current",
          hint="288.9 A is 288 900 mA; split it into a high and a low 16-bit word, high word first: "
               "mb.encode_value(288900, 'uint32', 'ABCD'), or METER_BY_NAME['AL1'].registers(288.9).",
          wrong=[0x6884, 0x0004])
def _check_10_2(answer: Any) -> str | None:
    from ..devices.meter import METER_BY_NAME

    expected = METER_BY_NAME["AL1"].registers(_al1_of_trial_2())
    if not isinstance(answer, (list, tuple)) or any(
            isinstance(x, bool) or not isinstance(x, int) for x in answer):
        return "answer with a list of two ints, e.g. [0x0001, 0x2345]."
    got = list(answer)
    if got == expected:
        return None
    if got == expected[::-1]:
        return "the words are swapped: this meter sends the high word at the lower address."
    if len(got) == 1:
        return f"{got[0]} does not fit in one 16-bit register (at most 65535): it takes two."
    if len(got) == 2 and got[0] * 65536 + got[1] == 2889:
        return "the current travels in milliamperes: 288.9 A is 288 900 mA."
    return f"{got} is not 288 900 mA split high word first."


def _al1_of_trial_2() -> float:
    """AL1 of trial 2, from the library's copy of the published trials."""
    from ..devices.meter import TRIALS

    return TRIALS[2]["AL1"]


_10_3_NAMES = ("THD_AL1", "THD_AL2", "THD_AL3")


@exercise("10.3", "one request for the three current THDs",
          hint="look up the three pairs in the register map (METER_BY_NAME[...].address): they are "
               "consecutive; one FC3 request from the first address, two registers each, and nothing more.",
          wrong=(3, 0x36, 3))
def _check_10_3(answer: Any) -> str | None:
    from ..devices.meter import METER_BY_NAME, meter_blocks

    members = [METER_BY_NAME[name] for name in _10_3_NAMES]
    [(address, count, _)] = meter_blocks(members)
    expected = (3, address, count)
    if not isinstance(answer, (tuple, list)) or len(answer) != 3:
        return "answer with three ints: (function, address, count)."
    function, got_address, got_count = answer
    if function != 3:
        return "the meter is read with function 3, read holding registers."
    if got_address != address:
        if got_address == address + 1:
            return (f"the address in the frame is 0-based: THD_AL1 is at 0x{address:02X} = {address}; "
                    f"{got_address} counts from 1.")
        if got_address == 0x30:
            return "0x30 is where the THD of the voltages starts; the question asks for the currents' only."
        return f"address {got_address!r} is not where THD_AL1 starts."
    if got_count != count:
        if got_count == len(members):
            return "each quantity takes a pair of registers: count registers, not quantities."
        return f"{got_count!r} registers do not cover exactly the three pairs."
    return None if tuple(answer) == expected else "not quite."


def _float32(registers: list, order: str) -> float:
    from ..values import decode_value

    return decode_value(registers, "float32", order)


def _float_inputs(rng) -> tuple:
    import struct

    from ..values import ORDERS, encode_value

    order = rng.choice(ORDERS)
    if rng.random() < 0.8:
        value = struct.unpack(">f", struct.pack(">f", rng.uniform(-1e4, 1e4)))[0]
        return list(encode_value(value, "float32", order)), order
    return [rng.randrange(65536), rng.randrange(65536)], order


def _diagnose_float(args, expected, got) -> str | None:
    from ..values import ORDERS, decode_value

    registers, order = args
    for other in ORDERS:
        if other != order and isinstance(got, float) and decode_value(registers, "float32", other) == got:
            return f"your result is the {other} reading; the question asks for {order}."
    return None


build_exercise(
    "10.4", "decode float32 in any word order",
    reference=_float32, inputs=_float_inputs,
    edge_cases=[([0x43C9, 0xCCCD], "ABCD"), ([0xCCCD, 0x43C9], "CDAB"), ([0xC943, 0xCDCC], "BADC"),
                ([0xCDCC, 0xC943], "DCBA"), ([0, 0], "ABCD")],
    hint="put the four bytes in the order A B C D that the order names (register 0 holds the first two "
         "letters), then struct.unpack('>f', ...)[0]. CDAB swaps the registers; BADC swaps the bytes inside "
         "each register; DCBA does both.",
    wrong=lambda registers, order: _float32(registers, "ABCD"),
    diagnose=_diagnose_float)
