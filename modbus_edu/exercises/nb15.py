"""Exercises of notebook 15: Gateways and converters."""

from __future__ import annotations

from typing import Any

from ..registermap import datasheet_to_address
from .build import build_exercise
from .core import address_diagnosis, exercise, number_answer
from .misconceptions import diagnose


@exercise("15.1", "one transaction behind a gateway at 9600 baud",
          hint="request 8 characters + 3.5 of silence + response 7 characters + 3.5 of silence, each "
               "character 10 bits at 9600 baud; give milliseconds.",
          accepts=[22.9, 22.92], refuses=[(15.6, "silences-forgotten"), (0.0229, "seconds-for-milliseconds"),
                                          (30.0, None)])
def _check_15_1(answer: Any) -> str | None:
    named = diagnose("silences-forgotten", answer, 15 * 10 / 9600 * 1000)
    if named:
        return named
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
    refuses=[(lambda number: number, "one-based-address")],
    diagnose=lambda args, expected, got: address_diagnosis(got, expected) if isinstance(expected,
                                                                                        int) else None)
