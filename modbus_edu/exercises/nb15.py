"""Exercises of notebook 15: Gateways and converters."""

from __future__ import annotations

from typing import Any

from ..registermap import datasheet_to_address
from .build import build_exercise
from .core import exercise, number_answer


@exercise("15.1", "one transaction behind a gateway at 9600 baud",
          hint="request 8 characters + 3.5 of silence + response 7 characters + 3.5 of silence, each "
               "character 10 bits at 9600 baud; give milliseconds.",
          wrong=15.6)
def _check_15_1(answer: Any) -> str | None:
    return number_answer(answer, 22 * 10 / 9600 * 1000, decimals=1, unit="ms",
                         what="the time in milliseconds")


def _one_based(number: int) -> int:
    return datasheet_to_address(number, "1-based")


build_exercise(
    "15.2", "datasheet register number (1-based) to protocol address",
    reference=_one_based,
    inputs=lambda rng: (rng.randrange(1, 65537),),
    edge_cases=[(1,), (2,), (65536,), (0,), (65537,)],
    hint="register 1 is address 0: subtract one; a number below 1 or above 65536 has no address, so raise "
         "an error there.",
    wrong=lambda number: number)
