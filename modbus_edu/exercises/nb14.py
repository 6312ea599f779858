"""Exercises of notebook 14: Beyond the eight functions."""

from __future__ import annotations

from typing import Any

from ..pdu import mask_write
from .build import build_exercise
from .core import exercise, int_answer
from .misconceptions import diagnose


@exercise("14.1", "a register after Mask Write Register",
          hint="keep the bits where the AND mask has 1 (current & and_mask), take the OR mask's bits where "
               "it has 0 (or_mask & ~and_mask), and OR the two.",
          accepts=[0x0135, 309], refuses=[(0x00A5 | 0x0130, "mask-write-or"), (0x0005, None)])
def _check_14_1(answer: Any) -> str | None:
    expected = mask_write(0x00A5, 0x000F, 0x0130)
    got = int_answer(answer, "a register value")
    if isinstance(got, str):
        return got
    if got == expected:
        return None
    named = diagnose("mask-write-or", 0x00A5, 0x000F, 0x0130, got)
    if named:
        return named
    return f"0x{got:04X} is not what the register holds after FC 22."


build_exercise(
    "14.2", "write FC 22's arithmetic",
    reference=mask_write,
    inputs=lambda rng: (rng.randrange(0x10000), rng.randrange(0x10000), rng.randrange(0x10000)),
    edge_cases=[(0x12, 0xF2, 0x25), (0, 0, 0xFFFF), (0xFFFF, 0xFFFF, 0), (0xFFFF, 0, 0)],
    hint="(current & and_mask) | (or_mask & ~and_mask), kept to 16 bits with & 0xFFFF.",
    refuses=[(lambda current, and_mask, or_mask: (current & and_mask) | or_mask, "mask-write-or")],
    diagnose=lambda args, expected, got: diagnose("mask-write-or", *args, got))
