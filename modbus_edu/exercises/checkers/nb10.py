"""Exercises of notebook 10: A power meter."""

from __future__ import annotations

import struct
from typing import Any

from ...devices.meter import METER_BY_NAME, TRIALS, meter_blocks
from ...framing import RtuFrame, parse_hex
from ...values import ORDERS, decode_value, encode_value
from ..build import build_exercise
from ..core import Written, address_diagnosis, exercise, field_diagnosis, number_answer, real_answer
from ..diagnosis.misconceptions import diagnose
from ..diagnosis.procedures import FLOAT32


@exercise("10.1", "a voltage from a register pair",
          hint=("the two registers after the byte count form one 32-bit number, high word first; VL2 is in "
                "tenths of a volt.",
                "decode the pair with mb.decode_value(registers, 'uint32') and divide by 10; the meter's "
                "map, METER_BY_NAME, checks it.",
                "registers 0x0001 and 0x0002 are 0x00010002 = 65538 tenths: 6553.8 V."),
          accepts=[410.5, 410.50, 410.48],
          refuses=[(4105, "raw-for-scaled"), (26902528.0, "word-order"), (41.05, "scale-wrong"), (410, None)])
def _check_10_1(answer: Any) -> str | None:
    registers = RtuFrame.decode(parse_hex("01 03 04 00 00 10 09 37 F5"), role="response").pdu.registers
    expected = METER_BY_NAME["VL2"].value(registers)
    got = real_answer(answer, "a voltage in volts")
    if isinstance(got, str):
        return got
    raw = decode_value(registers, "uint32", "ABCD")
    named = (diagnose(("raw-for-scaled", "scale-wrong"), got, raw, expected)
             or diagnose("word-order", registers, "uint32", round(got * 10), "ABCD"))
    if named:
        return named
    return number_answer(got, expected, decimals=1, unit="V", what="what those registers carry")


@exercise("10.2", "the registers that carry a current",
          hint=("the meter sends a current in milliamperes as one 32-bit number in two registers, high word "
                "first.",
                "288.9 A is 288 900 mA; the high word is that number // 65536, the low word that number % "
                "65536.",
                "100 000 mA = 0x000186A0: registers [1, 34464] (0x0001, 0x86A0); mb.encode_value(100000, "
                "'uint32', 'ABCD') gives the same."),
          accepts=[[0x0004, 0x6884], (4, 26756)],
          refuses=[([0x6884, 0x0004], "word-order"), ([288900], "one-register-for-32-bits"),
                   ([0, 2889], "current-not-in-milliamperes"), ([4, 0x6885], None),
                   ([4, 0x8468], "field-low-byte-first")])
def _check_10_2(answer: Any) -> str | None:
    expected = METER_BY_NAME["AL1"].registers(_al1_of_trial_2())
    if not isinstance(answer, (list, tuple)) or any(
            isinstance(x, bool) or not isinstance(x, int) for x in answer):
        return "answer with a list of two ints, e.g. [0x0001, 0x2345]."
    got = list(answer)
    if got == expected:
        return None
    value = round(_al1_of_trial_2() * 1000)
    named = diagnose("one-register-for-32-bits", len(got), 2) or (
        diagnose("word-order", got, "uint32", value, "ABCD")
        or diagnose("current-not-in-milliamperes", got[0] * 65536 + got[1], _al1_of_trial_2())
        or (diagnose("field-low-byte-first", got[1], expected[1]) if got[0] == expected[0] else None)
        if len(got) == 2 else None)
    if named:
        return named
    return f"{got} is not 288 900 mA split high word first."


def _al1_of_trial_2() -> float:
    """AL1 of the meter's trial 2, from the library's copy of the published trials."""
    return TRIALS[2]["AL1"]


_10_3_NAMES = ("THD_AL1", "THD_AL2", "THD_AL3")


@exercise("10.3", "one request for the three current THDs",
          hint="look up the three pairs in the register map (METER_BY_NAME[...].address): they are "
               "consecutive; one FC3 request from the first address, two registers each, and nothing more.",
          accepts=[(3, 54, 6), [3, 0x36, 6]],
          refuses=[((3, 55, 6), "one-based-address"), ((3, 54, 3), "one-register-for-32-bits"),
                   ((4, 54, 6), "holding-for-input"), ((3, 40055, 6), "reference-number"),
                   ((3, 0x30, 6), None), ((3, 54, 5), None), ((3, 54, 12), "bytes-for-registers"),
                   ((3, 36, 6), "hex-read-as-decimal")])
def _check_10_3(answer: Any) -> str | None:
    members = [METER_BY_NAME[name] for name in _10_3_NAMES]
    [(address, count, _)] = meter_blocks(members)
    expected = (3, address, count)
    if not isinstance(answer, (tuple, list)) or len(answer) != 3:
        return "answer with three ints: (function, address, count)."
    function, got_address, got_count = answer
    if function != 3:
        return (diagnose("holding-for-input", function, 3)
                or "the meter is read with function 3, read holding registers.")
    if got_address != address:
        if got_address == 0x30:
            return "0x30 is where the THD of the voltages starts; the question asks for the currents' only."
        return (address_diagnosis(got_address, address) or field_diagnosis(got_address, address)
                or f"address {got_address!r} is not where THD_AL1 starts.")
    if got_count != count:
        named = (diagnose("one-register-for-32-bits", got_count, count, len(members))
                 or diagnose("bytes-for-registers", got_count, count))
        if named:
            return named
        return f"{got_count!r} registers do not cover exactly the three pairs."
    return None if tuple(answer) == expected else "not quite."


def _float32(registers: list, order: str) -> float:
    return decode_value(registers, "float32", order)


def _registers(*registers: int) -> list:
    """Registers as exercise 10.4 writes them, in hex (0x43C9) in every message."""
    return [Written(register, "0x{:04X}") for register in registers]


def _float_inputs(rng) -> tuple:
    order = rng.choice(ORDERS)
    if rng.random() < 0.8:
        value = struct.unpack(">f", struct.pack(">f", rng.uniform(-1e4, 1e4)))[0]
        return _registers(*encode_value(value, "float32", order)), order
    return _registers(rng.randrange(65536), rng.randrange(65536)), order


def _diagnose_float(args, expected, got) -> str | None:
    registers, order = args
    if isinstance(got, float):
        return (diagnose("word-order", registers, "float32", got, order)
                or diagnose("result-rounded", got, expected, 2))
    return diagnose("integer-for-float", got, registers, order)


build_exercise(
    "10.4", "decode float32 in any word order",
    reference=_float32, inputs=_float_inputs,
    edge_cases=[(_registers(0x43C9, 0xCCCD), "ABCD"), (_registers(0xCCCD, 0x43C9), "CDAB"),
                (_registers(0xC943, 0xCDCC), "BADC"), (_registers(0xCDCC, 0xC943), "DCBA"),
                (_registers(0, 0), "ABCD"),
                # a negative value (the sign bit in the first byte A) in the orders that move A
                (_registers(0xC2F6, 0x8000), "ABCD"), (_registers(0x8000, 0xC2F6), "CDAB"),
                (_registers(0xF6C2, 0x0080), "BADC"), (_registers(0x0080, 0xF6C2), "DCBA")],
    hint="put the four bytes in the order A B C D that the order names (register 0 holds the first two "
         "letters), then struct.unpack('>f', ...)[0]. CDAB swaps the registers; BADC swaps the bytes inside "
         "each register; DCBA does both.",
    refuses=[(lambda registers, order: _float32(registers, "ABCD"), "word-order"),
             (lambda registers, order: _float32(registers[::-1], order), "word-order"),
             (lambda registers, order: decode_value(list(registers), "uint32", order), "integer-for-float"),
             (lambda registers, order: round(decode_value(list(registers), "float32", order), 2),
              "result-rounded")],
    diagnose=_diagnose_float, procedure=FLOAT32)
