"""Exercises of notebook 01: The data model."""

from __future__ import annotations

from typing import Any

from ...datamodel import DataBank, format_reference, parse_reference, table_kind
from ...errors import ModbusError
from ..build import build_exercise
from ..core import address_diagnosis, exercise, field_diagnosis, int_answer, kind, right_value_in_another_form
from ..diagnosis.misconceptions import diagnose


@exercise("01.1", "the address behind a reference number",
          hint="a reference number is the table prefix (4 = holding registers) followed by address + 1.",
          accepts=[249, 0xF9], refuses=[(250, "one-based-address"), (40250, "reference-number"),
                                         (40249, "reference-number"), (107, None)])
def _check_01_1(answer: Any) -> str | None:
    ref = "40250"
    expected = parse_reference(ref).address
    got = int_answer(answer, "an address")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    return (address_diagnosis(got, expected) or field_diagnosis(got, expected)
            or f"{got} is not the address of holding register {ref}.")


@exercise("01.2", "the reference number of an address",
          hint="input registers have the prefix 3; the number after the prefix is address + 1, written with "
               "four digits.",
          accepts=["30010", " 30010"],
          refuses=[("30009", "zero-based-number"), ("40010", "holding-for-input"), ("30011", None),
                   ("300010", "another-form"), (30010, "another-form")])
def _check_01_2(answer: Any) -> str | None:
    expected = format_reference("input_registers", 9)
    whole = isinstance(answer, (int, float)) and not isinstance(answer, bool) and float(answer).is_integer()
    got = str(int(answer)) if whole and abs(answer) < 10 ** 9 else str(answer).strip()
    try:
        reference = parse_reference(got)
    except ModbusError:
        return f"{got!r} is not a reference number such as 30001."
    if (reference.kind, reference.address) == ("input_registers", 9):
        if not isinstance(answer, str):
            return right_value_in_another_form(
                f"text, {expected!r}: a reference number is written with its table's digit in front, and "
                f"as {kind(answer)} a coil's 00010 would lose its leading zeros")
        if len(got) != len(expected):
            return right_value_in_another_form(
                f"the {len(expected)}-digit reference number the exercise asks for, {expected} ({got} is the "
                f"{len(got)}-digit form)")
        return None
    if reference.kind != "input_registers":
        return diagnose("holding-for-input", reference.kind, "input_registers") or \
            f"input registers use the prefix {expected[0]} (3x), your answer starts with {got[:1]!r}."
    return (diagnose("zero-based-number", int(str(reference)), int(expected))
            or f"{got!r} is not the 5-digit reference number of input register address 9.")


@exercise("01.3", "which table a function code reaches",
          hint="answer a pair (table name, may a master write it?), e.g. ('coils', True); "
               "mb.table_kind(code) names the table.",
          accepts=[("input_registers", False), ["input registers", False], ("Input_Registers", False)],
          refuses=[(("holding_registers", True), "holding-for-input"), (("input_registers", True), None),
                   (("coils", False), None), (("discrete_inputs", False), "bit-table-for-register-table")])
def _check_01_3(answer: Any) -> str | None:
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair: (table name, True or False)."
    kind, writable = answer
    expected_kind = table_kind(4)
    try:
        got_kind = table_kind(str(kind))
    except ModbusError:
        return f"{kind!r} is not a table name; the tables are coils, discrete_inputs, input_registers, " \
               f"holding_registers."
    if got_kind != expected_kind:
        return (diagnose(("holding-for-input", "bit-table-for-register-table"), got_kind, expected_kind)
                or f"function code 4 does not reach the {got_kind.replace('_', ' ')}.")
    expected_writable = DataBank(sparse=True).table(expected_kind).writable
    if bool(writable) != expected_writable or not isinstance(writable, bool):
        return f"the table is right, but may a master write the {expected_kind.replace('_', ' ')}? " \
               f"Answer True or False."
    return None


RANGES_01_4 = ((100, 149), (300, 309))
"""Exercise 01.4's two ranges of holding registers, first and last."""


@exercise("01.4", "counting the registers of a sparse bank",
          hint=("holding registers 100 to 149 means numbers 100, 101, ..., 149: count both ends, then add "
                "the two ranges.",
                "a range from first to last holds last - first + 1 registers; a sparse DataBank counts them "
                "too, once each range is declared in its holding registers.",
                "registers 5 to 7 and 20 to 21: (7 - 5 + 1) + (21 - 20 + 1) = 3 + 2 = 5."),
          accepts=[60], refuses=[(58, "range-one-end"), (52, None), (59, "range-one-end"),
                                 (50, "one-range-only"), (62, "range-one-extra")])
def _check_01_4(answer: Any) -> str | None:
    bank = DataBank(sparse=True)
    for first, last in RANGES_01_4:
        bank.holding_registers.declare(first - 1, last - first + 1)
    expected = len(bank.holding_registers)
    got = int_answer(answer, "a count")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = (diagnose(("range-one-end", "range-one-extra"), got, expected, 2)
             or diagnose("range-one-end", got, expected, 1)
             or diagnose("one-range-only", got, [last - first + 1 for first, last in RANGES_01_4]))
    if named:
        return named
    return f"{got} registers is not right."


def _parse_reference(text: str) -> tuple:
    reference = parse_reference(text)
    return reference.kind, reference.address


def _reference_inputs(rng) -> tuple:
    prefix = rng.choice("01234")
    number = rng.randrange(0, 10000) if rng.random() < 0.05 else rng.randrange(1, 10000)
    return (f"{prefix}{number:04d}",)


def _tables_by_digit(text: str) -> tuple:
    """A plausible wrong parser: the digit indexes a list of tables, so 2 finds one too."""
    number = int(text[1:])
    if not 1 <= number <= 9999:
        raise ValueError(f"{text}: numbers count from 1")
    kinds = ("coils", "discrete_inputs", "input_registers", "input_registers", "holding_registers")
    return kinds[int(text[0])], number - 1


def _diagnose_reference(args, expected, got) -> str | None:
    if args[0][:1] == "2":
        return diagnose("table-2x", args[0], got)
    if isinstance(got, tuple) and len(got) == 2 and isinstance(got[1], int) and isinstance(expected, tuple):
        return diagnose("holding-for-input", got[0], expected[0]) or address_diagnosis(got[1], expected[1])
    return None


build_exercise(
    "01.5", "read a reference number yourself",
    reference=_parse_reference, inputs=_reference_inputs,
    edge_cases=[("40001",), ("40108",), ("00308",), ("30001",), ("19999",), ("40000",), ("20001",),
                # both ends of every table's range
                ("00001",), ("09999",), ("10001",), ("39999",), ("49999",), ("30000",)],
    hint="the first digit is the table (0 coils, 1 discrete inputs, 3 input registers, 4 holding registers); "
         "the other four digits are a number counted from 1, so the address is that number minus 1. A "
         "number 0000 does not exist: raise an exception for it.",
    refuses=[(lambda text: ({"0": "coils", "1": "discrete_inputs", "3": "input_registers",
                             "4": "holding_registers"}[text[0]], int(text[1:])), "one-based-address"),
             (_tables_by_digit, "table-2x")],
    diagnose=_diagnose_reference)
