"""Exercises of notebook 16: Your first real device."""

from __future__ import annotations

from typing import Any

from ..registermap import datasheet_to_address
from .build import build_exercise
from .core import address_diagnosis, exercise, int_answer


@exercise("16.1", "requests the poll planner needs for the energy meter",
          hint="group the points of one table whose registers follow each other without a gap; a point "
               "never splits, and holding and input registers need separate functions (3 and 4).",
          accepts=[4], refuses=[(10, None), (3, None)])
def _check_16_1(answer: Any) -> str | None:
    got = int_answer(answer, "a number of requests")
    if isinstance(got, str):
        return got
    if got == 4:
        return None
    if got == 10:
        return "that is one request per point; neighbouring points of one table go in one request."
    return f"{got} is not the number of requests: count the runs of adjacent registers per table."


def _reference(number: int) -> int:
    return datasheet_to_address(number, "reference")


def _draw(rng: Any) -> tuple[int]:
    base = rng.choice((30001, 40001, 300001, 400001))
    span = 9999 if base < 100000 else 65536
    return (base + rng.randrange(span),)


build_exercise(
    "16.2", "reference number (30001/40001 style) to protocol address",
    reference=_reference,
    inputs=_draw,
    edge_cases=[(30001,), (40001,), (39999,), (49999,), (400001,), (465536,), (10001,), (40000,), (50001,)],
    hint="drop the leading table digit (3 or 4) and subtract one: 40001 is address 0; six-digit numbers "
         "(400001) work the same way; anything else is not a 3x/4x register, so raise an error.",
    refuses=[(lambda number: number, "reference-number"), (lambda number: number % 10000,
                                                           "one-based-address"),
             (lambda number: number - 40001, None)],
    diagnose=lambda args, expected, got: address_diagnosis(got, expected) if isinstance(expected,
                                                                                        int) else None)
