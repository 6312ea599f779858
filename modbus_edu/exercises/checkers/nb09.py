"""Exercises of notebook 09: An Arduino-style slave."""

from __future__ import annotations

import math
from typing import Any

from ...datamodel import DataBank, parse_reference, table_kind
from ...devices.arduino import (
    EXPERIMENT_TIMEOUT,
    SLOW_LOOP,
    expected_answered_fraction,
    reply_time,
)
from ..build import build_exercise
from ..core import address_diagnosis, exercise, field_diagnosis, real_answer
from ..diagnosis.misconceptions import diagnose, name
from ..diagnosis.procedures import ANSWERED


@exercise("09.1", "function and address for a reference number",
          hint=("3xxxx are input registers, read with function 4; the address in the frame is the number "
                "after the prefix minus one.",
                "the number after the prefix is counted from 1; the address is counted from 0.",
                "40108 is read with function 3 at address 107; mb.parse_reference('40108') shows both."),
          accepts=[(4, 9), [4, 9], (0x04, 0x09)],
          refuses=[((3, 9), "holding-for-input"), ((4, 10), "one-based-address"), ((4, 30009),
                                                                                   "reference-number"),
                   ((4, 30010), "reference-number"), ((4, 8), "address-one-too-low")])
def _check_09_1(answer: Any) -> str | None:
    ref = parse_reference("30010")
    function = next(fc for fc in (1, 2, 3, 4) if table_kind(fc) == ref.kind)
    if not isinstance(answer, (tuple, list)) or len(answer) != 2:
        return "answer with a pair of ints: (function, address)."
    got_function, got_address = answer
    if got_function != function:
        return (diagnose("holding-for-input", got_function, function)
                or f"function {got_function!r} does not read the table 30010 is in.")
    if got_address != ref.address:
        return (address_diagnosis(got_address, ref.address) or field_diagnosis(got_address, ref.address)
                or field_diagnosis(got_address, ref.address + 1)
                or f"address {got_address!r} is not where 30010 is.")
    return None


def _bank_of(*runs: tuple[int, int]) -> Any:
    """A sparse bank declaring holding registers at each (first address, count) of ``runs``."""
    bank = DataBank(sparse=True)
    for first, count in runs:
        bank.holding_registers.declare(first, count)
    return bank


RANGES_09_2 = ((150, 175), (200, 225))
"""Exercise 09.2's two ranges of holding register numbers (4xxxx without the 4), first and last."""


@exercise("09.2", "a sparse bank with holding registers 150-175 and 200-225",
          hint=("a sparse board holds only the registers you declare: every register of both ranges, both "
                "ends included, and nothing between them.",
                "register 150 is reference 40150; board.add takes one reference number, and a for loop over "
                "range(first, last + 1) declares a whole range.",
                "registers 10 to 12 and 20: board.add(40010), board.add(40011), board.add(40012), "
                "board.add(40020)."),
          accepts=[_bank_of((149, 26), (199, 26))],
          refuses=[(_bank_of((150, 26), (200, 26)), "one-based-address"),
                   (_bank_of((149, 25), (199, 25)), "range-one-end"),
                   (_bank_of((149, 26)), "one-range-only"), (DataBank(sparse=False), "dense-for-sparse")])
def _check_09_2(answer: Any) -> str | None:
    bank = getattr(answer, "bank", answer)
    if not isinstance(bank, DataBank):
        return "give the board (an ArduinoSlave) or its DataBank."
    if not bank.sparse:
        return diagnose("dense-for-sparse", bank) + " Only the declared registers should exist."
    expected = sorted(parse_reference(40000 + n).address
                      for first, last in RANGES_09_2 for n in range(first, last + 1))
    got = sorted(bank.holding_registers.addresses())
    for table in (bank.coils, bank.discrete_inputs, bank.input_registers):
        if len(table):
            kind = table.kind.replace("_", " ")
            return f"only holding registers were asked for, but the bank also has {kind}."
    if got == expected:
        return None
    if got == [a + 1 for a in expected]:
        return address_diagnosis(got[0], expected[0])
    named = (diagnose("range-one-end", len(got), len(expected), 2)
             or diagnose("range-one-end", len(got), len(expected), 1)
             or diagnose("one-range-only", len(got), [last - first + 1 for first, last in RANGES_09_2]))
    if named:
        return named
    if len(got) != len(expected):
        return (f"the bank holds {len(got)} holding registers, it should hold {len(expected)} "
                "(150 to 175 and 200 to 225, both ends included).")
    return "the right number of registers, but not at the right addresses."


@exercise("09.3", "a master timeout that copes with the slow loop",
          hint="a request may wait up to the longest loop (1.65 s + 10%) plus the time of the reply; "
               "try loop_time_experiment([SLOW_LOOP], timeout=...) with a few values.",
          accepts=[1.9, 2.0, 2.5, 2],
          refuses=[(2000, "milliseconds-for-seconds"), (1.5, None), (3.0, None),
                   (1.815, "reply-time-forgotten"),
                   (10, "timeout-far-too-long"), (1.65, "loop-time-for-timeout")])
def _check_09_3(answer: Any) -> str | None:
    got = real_answer(answer, "a timeout in seconds")
    if isinstance(got, str):
        return got
    if got > 100 and got / 1000 <= 2.5:
        return name("milliseconds-for-seconds")
    named = (diagnose("timeout-far-too-long", got, SLOW_LOOP * 1.1 + reply_time(7))
             or diagnose("loop-time-for-timeout", got, SLOW_LOOP)
             or diagnose("given-figure", got, {"1 s, the timeout of the experiment": EXPERIMENT_TIMEOUT}))
    if named:
        return named
    if got > 2.5:
        return f"{got:g} s works, but it is longer than needed: stay at or below 2.5 s."
    if got <= 0:
        return "a timeout is a positive number of seconds."
    longest_loop, reply = SLOW_LOOP * 1.1, reply_time(7)
    if got < longest_loop + reply:
        # judged from the arithmetic, not from a seeded run: a run may happen to miss the longest wait
        named = diagnose("reply-time-forgotten", got, longest_loop)
        if named:
            return (f"{named} Here {longest_loop:g} s is the longest loop alone; the reply takes "
                    f"{reply * 1000:.1f} ms more, so the timeout must be at least "
                    f"{longest_loop + reply:.3f} s.")
        return (f"with a timeout of {got:g} s a request that waits the longest loop ({longest_loop:g} s) and "
                f"then its reply ({reply * 1000:.1f} ms) is given up: the timeout must be at least "
                f"{longest_loop + reply:.3f} s.")
    return None


def _answered(loop_time: float, timeout: float, reply: float) -> float:
    return expected_answered_fraction(loop_time, timeout, reply)


def _answered_inputs(rng) -> tuple:
    loop_time, timeout = round(rng.uniform(0.001, 3.0), 4), round(rng.uniform(0.05, 2.0), 4)
    return loop_time, timeout, round(rng.uniform(0.0, 0.05), 4)


def _fraction_close(expected: float, got) -> bool:
    return isinstance(got, (int, float)) and not isinstance(got, bool) and abs(got - expected) <= 1e-9


def _diagnose_answered(args, expected, got) -> str | None:
    loop_time, timeout, reply = args
    if isinstance(got, (int, float)) and abs(got - (timeout - reply) / loop_time) < 1e-9:
        return diagnose("fraction-unclamped", got)
    named = (diagnose("percentage-for-fraction", got, expected) if expected else None) or diagnose(
        "fraction-unclamped", got)
    without_reply = expected_answered_fraction(loop_time, timeout)
    return named or (diagnose("reply-time-forgotten", got, without_reply) if not math.isclose(
        without_reply, expected) else None) or diagnose("missed-for-answered", got, expected)


build_exercise(
    "09.4", "how many requests a slow loop answers",
    reference=_answered, inputs=_answered_inputs,
    edge_cases=[(1.65, 1.0, 0.0), (0.01, 1.0, 0.0), (2.0, 1.0, 0.02), (1.0, 0.01, 0.02),
                # a loop that takes no time sees a request at once: all answered if the reply fits, else none
                (0.0, 1.0, 0.0), (0.0, 0.02, 0.02), (0.0, 0.01, 0.02)],
    hint=("a request arrives at a random moment of the loop; it is answered in time only if the loop "
          "reaches it within the time the master still waits after the reply's own time.",
          "that waiting time is timeout - reply; as a share of the loop time it is the fraction answered, "
          "which can be neither below 0 nor above 1.",
          "a 2 s loop, a 1 s timeout, a 0.2 s reply: (1 - 0.2) / 2 = 0.4; a 0.5 s loop: 1.6, so 1."),
    refuses=[(lambda loop_time, timeout, reply: 100 * _answered(loop_time, timeout, reply),
              "percentage-for-fraction"),
             (lambda loop_time, timeout, reply: timeout / loop_time, "fraction-unclamped"),
             (lambda loop_time, timeout, reply: min(1.0, timeout / loop_time), "reply-time-forgotten"),
             (lambda loop_time, timeout, reply: 1 - _answered(loop_time, timeout, reply),
              "missed-for-answered")],
    diagnose=_diagnose_answered, compare=_fraction_close, procedure=ANSWERED)
