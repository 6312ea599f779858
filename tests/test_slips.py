"""The slips a newcomer makes (modbus_edu.exercises.slips): every one is refused and named.

Each slip of :data:`~modbus_edu.exercises.slips.SLIPS` and :data:`~modbus_edu.exercises.build_slips.SLIPS`
must be refused; a slip with a misconception must be named by the catalogue's label of it, a slip without
must not be named as any misconception; and no verdict may read like a Python error.  The share named, of all
slips and of the slips with a misconception, is reported per notebook (``pytest -s``); both must stay at or
above :data:`NAMED_AT_LEAST`.
"""

from __future__ import annotations

import builtins
import re
from collections import defaultdict

import build_slips
import pytest
import slips

from modbus_edu import exercises
from modbus_edu.exercises.inventory import PRE
from modbus_edu.exercises.misconceptions import CATALOGUE

NAMED_AT_LEAST = 0.90
"""The share of slips whose verdict names their misconception: of the slips with a catalogued
misconception, and of all slips (the pre-test's and the slips of the wrong Python form included)."""

ALL_SLIPS = {**slips.SLIPS, **build_slips.SLIPS}
CASES = [(key, index) for key in sorted(ALL_SLIPS) for index in range(len(ALL_SLIPS[key]))]

PYTHON_ERRORS = re.compile(r"\b(" + "|".join(
    name for name, value in vars(builtins).items()
    if isinstance(value, type) and issubclass(value, BaseException)
    and name.endswith(("Error", "Exit", "Interrupt", "Iteration", "BaseException"))) + r")\b")
"""The names of Python's own exceptions: no verdict may mention one (unless the learner's answer does)."""


def python_errors(message: str, answer: object) -> list[str]:
    """The Python exception names in ``message`` that the learner's ``answer`` itself does not name."""
    given = set(PYTHON_ERRORS.findall(repr(answer)))
    return [name for name in PYTHON_ERRORS.findall(message) if name not in given]


def verdict(key: str, index: int) -> tuple[slips.Slip, str, bool]:
    """The slip, the verdict's message, and whether the verdict refuses it, naming its misconception."""
    slip = ALL_SLIPS[key][index]
    result = exercises.evaluate(key, slip.answer)
    named = result.ok is False and slip.misconception is not None and \
        CATALOGUE[slip.misconception].label.lower() in result.message.lower()
    return slip, result.message, named


def test_every_exercise_has_five_slips_or_more_and_every_slip_says_what_the_newcomer_did():
    assert set(ALL_SLIPS) == set(exercises.EXERCISES)
    for key, items in ALL_SLIPS.items():
        assert len(items) >= 5, key
        for slip in items:
            assert slip.why.strip(), key
            assert slip.misconception is None or slip.misconception in CATALOGUE, (key, slip.misconception)
            if exercises.EXERCISES[key].kind == "build":
                assert callable(slip.answer), key
    assert sum(map(len, ALL_SLIPS.values())) >= 395


@pytest.mark.parametrize("key, index", CASES, ids=[f"{k}-slip-{i}" for k, i in CASES])
def test_each_slip_is_refused_with_a_message_that_reads_like_a_teacher(key, index):
    slip, message, _named = verdict(key, index)
    if key == PRE:  # the pre-test records any 12 letters: it says nothing of which are wrong
        assert message.startswith("Recorded:" if len(str(slip.answer)) == 12 else "Not yet:"), (key, message)
        assert not [entry.label for entry in CATALOGUE.values() if entry.label.lower() in message.lower()]
        return
    assert message.startswith("Not yet:"), f"{key} accepts the slip {slip.answer!r} ({slip.why})"
    assert not python_errors(message, slip.answer), f"{key}: {slip.answer!r} gets {message!r}"
    if slip.misconception is None:
        labels = [entry.label for entry in CATALOGUE.values() if entry.label.lower() in message.lower()]
        assert not labels, f"{key}: {slip.answer!r} is named {labels}, but the slip names none ({slip.why})"


def outcome(key: str, index: int) -> str:
    """How the checker took a slip: "named" (its misconception's label), "wrongly named" (another
    misconception's label and not its own), "accepted", or "generic" (refused, no misconception named)."""
    slip, message, named = verdict(key, index)
    if named:
        return "named"
    if not message.startswith("Not yet:") and key != PRE:
        return "accepted"
    labels = {entry.key for entry in CATALOGUE.values() if entry.label.lower() in message.lower()}
    return "wrongly named" if labels - {slip.misconception} else "generic"


def test_the_slips_are_named_by_their_misconception(capsys):
    rows: dict[str, list[int]] = defaultdict(lambda: [0, 0, 0, 0, 0, 0])  # named, catalogued, all, ...
    kinds = ("generic", "wrongly named", "accepted")
    unnamed = []
    for key, index in CASES:
        slip, message, named = verdict(key, index)
        row = rows[key.split(".")[0]]
        row[0] += named
        row[1] += slip.misconception is not None
        row[2] += 1
        taken = outcome(key, index)
        if taken in kinds:
            row[3 + kinds.index(taken)] += 1
        if slip.misconception is not None and not named:
            unnamed.append(f"{key} {slip.misconception}: {message[:160]!r}")
    named, catalogued, every = (sum(row[i] for row in rows.values()) for i in range(3))
    with capsys.disabled():
        print("\nnotebook  named / all slips        named / slips with a misconception   generic"
              "  wrongly named  accepted")
        for notebook in sorted(rows):
            n, c, a, g, w, x = rows[notebook]
            print(f"{notebook:>8}  {n:>3} / {a:<3} {n / a:6.0%}    {n:>3} / {c:<3} {n / c if c else 1:6.0%}"
                  f"                 {g:>5}  {w:>13}  {x:>8}")
        print(f"{'overall':>8}  {named:>3} / {every:<3} {named / every:6.1%}    {named:>3} / {catalogued:<3} "
              f"{named / catalogued:6.1%}                 "
              + "  ".join(f"{sum(row[3 + i] for row in rows.values()):>{width}}"
                          for i, width in enumerate((5, 13, 8))))
        print("\n".join(unnamed))
    assert named / catalogued >= NAMED_AT_LEAST, "\n".join(unnamed)
    assert named / every >= NAMED_AT_LEAST, (
        f"only {named} of {every} slips are named by their misconception: catalogue more of the "
        "misconceptions behind the slips that carry none")
