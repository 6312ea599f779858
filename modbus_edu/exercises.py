"""Checkers for the course's exercises.

Each exercise in a notebook ends with a cell like::

    answer = ...          # replace ... with your answer
    check("03.1", answer)

Run unanswered, ``check`` prints a hint and raises nothing, so the notebook still runs from top to
bottom.  With an answer it says whether it is right and, if not, why.  The expected values are computed
here with the library itself, never typed in.  Worked solutions live in ``notebooks/solutions/`` and
load into a cell with ``%load solutions/03_1.py``.

Adding an exercise: write a function that takes the learner's answer and returns ``None`` when it is
right or a sentence saying what is wrong, and register it with :func:`exercise`, giving the hint and
one wrong answer (the test suite checks that the solution passes and the wrong answer fails).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .errors import ModbusError

PLACEHOLDER = ...
"""What an unanswered exercise cell holds: the Ellipsis, ``...``."""


@dataclass(frozen=True)
class Exercise:
    """One exercise: its key (``"NN.k"``: notebook and number), a hint, a checker and a wrong answer."""

    key: str
    title: str
    hint: str
    checker: Callable[[Any], str | None]
    wrong: Any


@dataclass(frozen=True)
class Result:
    """What :func:`check` found.  ``ok`` is None while the exercise is unanswered."""

    key: str
    ok: bool | None
    message: str

    def __str__(self) -> str:
        return self.message

    def __bool__(self) -> bool:
        return bool(self.ok)


EXERCISES: dict[str, Exercise] = {}


def exercise(key: str, title: str, *, hint: str, wrong: Any) -> Callable:
    """Register a checker under ``key`` (decorator)."""

    def register(checker: Callable[[Any], str | None]) -> Callable[[Any], str | None]:
        if key in EXERCISES:
            raise ValueError(f"exercise {key} is registered twice")
        EXERCISES[key] = Exercise(key, title, hint, checker, wrong)
        return checker

    return register


def evaluate(key: str, answer: Any) -> Result:
    """Check ``answer`` against exercise ``key`` without printing anything."""
    if key not in EXERCISES:
        known = ", ".join(sorted(EXERCISES))
        return Result(key, False, f"There is no exercise {key!r}; the exercises are {known}.")
    item = EXERCISES[key]
    if answer is PLACEHOLDER:
        return Result(key, None, f"Exercise {key} ({item.title}) is not answered yet. Hint: {item.hint}")
    try:
        problem = item.checker(answer)
    except ModbusError as exc:
        problem = f"the library could not use your answer: {exc}"
    except (TypeError, ValueError, KeyError, IndexError, AttributeError) as exc:
        problem = f"your answer has the wrong shape ({type(exc).__name__}: {exc})"
    if problem is None:
        return Result(key, True, f"Right! Exercise {key} ({item.title}) is solved.")
    return Result(key, False, f"Not yet: {problem} Hint: {item.hint}")


def check(key: str, answer: Any) -> Result:
    """Check an answer, print the verdict, and return it (falsy unless right)."""
    result = evaluate(key, answer)
    print(result.message)
    return result


# --- helpers for checkers ---------------------------------------------------------------------------

def as_bytes(answer: Any) -> bytes:
    """Accept bytes, a bytearray, a list of ints or a hex string ("01 03 00 ...") as a byte answer."""
    if isinstance(answer, (bytes, bytearray)):
        return bytes(answer)
    if isinstance(answer, str):
        from .framing import parse_hex

        return parse_hex(answer)
    return bytes(answer)


def compare_bytes(answer: Any, expected: bytes, what: str) -> str | None:
    """None if ``answer`` is exactly ``expected``; otherwise which byte differs first."""
    got = as_bytes(answer)
    if got == expected:
        return None
    for index, (mine, theirs) in enumerate(zip(got, expected)):
        if mine != theirs:
            return (f"{what} differs at byte {index}: you have 0x{mine:02X}, it should be 0x{theirs:02X} "
                    f"({len(got)} bytes given, {len(expected)} expected).")
    return f"{what} has {len(got)} bytes, it should have {len(expected)}."
