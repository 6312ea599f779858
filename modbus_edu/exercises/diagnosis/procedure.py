"""Diagnosis from the procedure: a concept's right procedure, and the same procedure with one step changed.

This is the "bug library" of intelligent tutoring (Brown and Burton's BUGGY; model tracing).  A
:class:`Procedure` computes a concept's right answer (the CRC of some bytes, an MBAP header, a transaction
time) and, on request, its answer with one named step changed (a :class:`Perturbation`: the CRC register
started at 0, the polynomial unreflected, the bytes high first...).  A checker asks the concept's procedure
which perturbations reproduce the learner's answer, and names the change:

* one change reproduces it, or several that all point to the same misconception: the verdict names that
  misconception (its catalogue entry, :mod:`.misconceptions`), so one slip reads the same in every
  exercise that uses the concept;
* several changes that point to different misconceptions reproduce it: the verdict names the candidates,
  never one of them ("your answer is what the register started at 0 gives, or what ... gives");
* none does: the checker says so with the field or the boundary the answer falls on.

For a build exercise the evidence is every input the learner's function was called on
(:meth:`Procedure.reproducing` over a whole trace): a change is named only if it gives what the learner's
function gave on every input, so a function that is wrong only for the empty input is not told "register
started at 0", though on that one input the two agree.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from .catalogue import CATALOGUE


@dataclass(frozen=True)
class Perturbation:
    """One step of a procedure changed: its short key, the change in words (``step``, read after "what ...
    gives"), the catalogue key of the misconception it shows (None: no catalogued misconception), and the
    changed procedure itself (same arguments as the right one; None when the change does not apply)."""

    key: str
    step: str
    misconception: str | None
    compute: Callable[..., Any]
    fields: dict = field(default_factory=dict)
    also: str | None = None
    """A second misconception, for a change made of two slips (a step and a slip of form)."""

    def answer(self, *args: Any) -> Any:
        """The changed procedure's answer, or :data:`NOT_APPLICABLE` when it raises or does not apply."""
        try:
            result = self.compute(*copy.deepcopy(args))
        except Exception:  # a change that cannot run on these arguments does not apply to them
            return NOT_APPLICABLE
        return NOT_APPLICABLE if result is None and not self.returns_none else result

    returns_none: bool = False

    def words(self) -> str:
        """What the verdict says when this change is named: the catalogue's words, or the step's."""
        if self.also is not None:
            labels = " and ".join(CATALOGUE[key].label for key in (self.misconception, self.also) if key)
            return f"{labels}: your answer is what {self.step} gives."
        if self.misconception is None:
            return f"your answer is what {self.step} gives."
        entry = CATALOGUE[self.misconception]
        try:
            return f"{entry.say(**self.fields)} (Your answer is what {self.step} gives.)"
        except (KeyError, IndexError):
            return f"{entry.label}: your answer is what {self.step} gives."


REFUSED = "raises an error (refuses the input)"
"""A build exercise's answer where the function raises, for a procedure that models refusals."""

NOT_APPLICABLE = object()
"""What a perturbation gives where its change does not apply (never equal to any answer)."""


class Choices(tuple):
    """What a perturbation gives when the changed step may go several ways (any word order but the one
    asked): the learner's answer fits it if it equals any of them."""


def _equal(expected: Any, got: Any) -> bool:
    if isinstance(expected, bool) or isinstance(got, bool):
        return type(expected) is type(got) and expected == got
    if isinstance(expected, (bytes, bytearray)) and isinstance(got, (bytes, bytearray)):
        return bytes(expected) == bytes(got)
    if isinstance(expected, float) or isinstance(got, float):
        return (
            isinstance(got, (int, float))
            and isinstance(expected, (int, float))
            and abs(expected - got) <= 1e-9 * max(1.0, abs(expected))
        )
    try:
        return type(expected) is type(got) and bool(expected == got)
    except Exception:
        return False


@dataclass(frozen=True)
class Procedure:
    """A concept's procedure (``right``) and its perturbations, each one step changed."""

    concept: str
    right: Callable[..., Any]
    perturbations: tuple[Perturbation, ...]
    same: Callable[[Any, Any], bool] = _equal
    forms: tuple[Perturbation, ...] = ()
    """Slips of the answer's form (milliseconds for seconds, a percentage for a share): each ``compute``
    takes the answer.  They are tried on the right answer and on every perturbation's, so that a learner
    who made one slip of the procedure and one of the form is named for both."""
    refusals: bool = False
    """Whether the procedure's answer may be :data:`REFUSED` (the input refused): a build checker then
    counts the inputs the learner's function raised on as evidence too."""

    def answer(self, *args: Any, perturbation: str | None = None) -> Any:
        """The right answer for ``args``, or the answer with the step ``perturbation`` (a key) changed."""
        if perturbation is None:
            return self.right(*args)
        return self.perturbation(perturbation).answer(*args)

    def perturbation(self, key: str) -> Perturbation:
        return next(item for item in self.perturbations if item.key == key)

    @property
    def misconceptions(self) -> frozenset[str]:
        """The catalogue keys this procedure's perturbations name."""
        return frozenset(key for item in (*self.perturbations, *self.forms)
                         for key in (item.misconception, item.also) if key)

    def fits(self, item: Perturbation, args: Sequence, got: Any, *, applicable: bool = True) -> bool:
        """Whether the perturbation ``item`` gives ``got`` for ``args``; where the change does not apply to
        ``args`` (it cannot run on them), True unless ``applicable`` is asked for."""
        mine = item.answer(*args)
        if mine is NOT_APPLICABLE:
            return not applicable
        return any(self.same(one, got) for one in mine) if isinstance(mine, Choices) else self.same(mine, got)

    def candidates(self) -> list[Perturbation]:
        """Every change tried: each perturbation, each slip of form, and each of those on each other."""
        combined = []
        for form in self.forms:
            combined.append(Perturbation(form.key, form.step, form.misconception,
                                         lambda *args, form=form: form.compute(self.right(*args))))
            combined += [Perturbation(f"{item.key}+{form.key}", f"{item.step}, and {form.step}",
                                      item.misconception,
                                      lambda *args, item=item, form=form: form.compute(item.compute(*args)),
                                      also=form.misconception) for item in self.perturbations]
        return [*self.perturbations, *combined]

    def reproducing(self, cases: Iterable[tuple[Sequence, Any]]) -> list[Perturbation]:
        """The changes that give the learner's answer on every ``(args, got)`` of ``cases``: on the first
        (the failing input, where the change must apply), then on every other where it applies.  Where one
        change alone explains the answer, the changes of two steps that also do are left out, and so are
        the changes that show two misconceptions where one showing one does."""
        cases = list(cases)
        if not cases:
            return []
        (first_args, first_got), rest = cases[0], cases[1:]
        try:
            right = self.right(*copy.deepcopy(first_args))
        except Exception:  # no right answer to compare: every change may be one
            right = NOT_APPLICABLE
        if right is not NOT_APPLICABLE and self.same(right, first_got):
            return []  # the right answer (to the procedure's precision) is no slip
        found = [item for item in self.candidates() if self.fits(item, first_args, first_got)
                 and all(self.fits(item, args, got, applicable=False) for args, got in rest)]
        found = [item for item in found if "+" not in item.key] or found
        return [item for item in found if item.also is None] or found  # one slip before two

    def explain(self, cases: Iterable[tuple[Sequence, Any]]) -> str | None:
        """The verdict's words for the learner's answers ``cases`` (``(args, got)`` pairs, the failing one
        first): the one misconception that reproduces them all, the candidates when several different ones
        do, or None."""
        return say(self.reproducing(cases))

    def nearest(self, args: Sequence, got: Any, other: str) -> str | None:
        """Where no change reproduces every answer: the changes that reproduce this one alone, as a clue
        that names no misconception (``other`` says on which input it stops fitting)."""
        found = self.reproducing([(args, got)])
        if not found:
            return None
        steps = " or ".join(dict.fromkeys(item.step for item in found))
        return (
            f"On this input your answer is what {steps} gives, but that change does not give your answers "
            f"on {other}."
        )


def say(found: Sequence[Perturbation]) -> str | None:
    """Name what the perturbations ``found`` (all reproducing the answer) have in common: one
    misconception, or one uncatalogued change; else the candidates, naming none of them."""
    if not found:
        return None
    keys = list(dict.fromkeys((item.misconception, item.also) for item in found))
    if len(keys) == 1 and (keys[0] != (None, None) or len(found) == 1):
        return found[0].words()
    steps = list(dict.fromkeys(item.step for item in found))
    return (
        f"your answer is what {', or what '.join(steps)} gives: the answer alone cannot tell which. "
        "Check each."
    )
