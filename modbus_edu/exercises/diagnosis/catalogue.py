"""The catalogue of misconceptions itself: what an entry is, how one registers, and how a checker asks.

An entry has a key (``"crc-swapped"``), a label (the name a learner reads), the shape of what its
detector reads, a teaching sentence (which may name the learner's case: ``{used}``) and a detector.
:func:`name` gives the verdict's words; :func:`detect` runs one detector; :func:`diagnose` tries several
and names the first that fits.  Detectors never raise: a value of the wrong kind simply does not fit.
The entries live in :mod:`.misconceptions` and :mod:`.misconceptions_counting`; checkers import
``CATALOGUE``, ``diagnose`` and ``name`` from :mod:`.misconceptions`, which registers them all.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Misconception:
    """One mistake: its key, the label a learner reads, what its detector reads, one teaching sentence."""

    key: str
    label: str
    shape: str
    sentence: str
    detector: Callable[..., Any]

    def say(self, **fields: Any) -> str:
        """The words of a verdict: the label, then the teaching sentence with ``fields`` filled in."""
        return f"{self.label}: {self.sentence.format(**fields)}"


CATALOGUE: dict[str, Misconception] = {}


def _entry(key: str, label: str, shape: str, sentence: str) -> Callable:
    def register(detector: Callable[..., Any]) -> Callable[..., Any]:
        if key in CATALOGUE:
            raise ValueError(f"misconception {key} is catalogued twice")
        CATALOGUE[key] = Misconception(key, label, shape, sentence, detector)
        return detector

    return register


def name(key: str, **fields: Any) -> str:
    """The verdict for the misconception ``key``: its label and its teaching sentence."""
    return CATALOGUE[key].say(**fields)


def detect(key: str, *args: Any) -> Any:
    """What the detector of ``key`` finds in ``args``: falsy when the mistake is not there, else True or
    a dict of the fields its sentence names."""
    try:
        return CATALOGUE[key].detector(*args)
    except Exception:  # a learner's value of another kind: the mistake is not this one
        return None


def diagnose(keys: str | tuple[str, ...] | list[str], *args: Any) -> str | None:
    """The verdict of the first misconception among ``keys`` whose detector fits ``args``, or None."""
    for key in (keys,) if isinstance(keys, str) else keys:
        found = detect(key, *args)
        if found:
            return name(key, **found) if isinstance(found, dict) else name(key)
    return None


# --- small helpers the detectors share -----------------------------------------------------------------

def _int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _bytes(value: Any) -> bool:
    return isinstance(value, (bytes, bytearray))


def _near(got: float, expected: float, tolerance: float = 0.0) -> bool:
    return abs(got - expected) <= max(tolerance, 2e-3 * abs(expected), 1e-12)


def _same_time(got: Any, other: Any) -> bool:
    """The learner's number is (near) ``other``, the time a slip gives."""
    return _number(got) and _number(other) and _near(got, other)


def _swap16(value: int) -> int:
    return (value & 0xFF) << 8 | (value >> 8) & 0xFF
