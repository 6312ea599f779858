"""What the instructor assigned: the exercises that count towards the grade, and the points it is out of.

Given on the command line (``--notebooks 00,01,03,05,06,17``), or in a small JSON file beside the class
(:data:`FILE`, ``assignment.json``, in the folder given to the grader or beside the zip given)::

    {"notebooks": ["00", "01", "03", "05", "06", "17"], "points": 20}

or, exercise by exercise, ``{"exercises": ["03.1", "03.2", "03.5"], "points": 10}``.  A notebook counts
with all its exercises, the concept inventory's quizzes (00.0, 17.0) aside: they measure the course, not
the learner.  ``points`` is the grade a learner with every counted exercise right gets on the platform
(Moodle's maximum grade, Canvas's points); ``--points`` overrides it, and without either it is 100.

The grade is out of the counted exercises, whatever the class handed in: a learner who did not hand
notebook 05 in has its exercises "not handed in", out of the same total as everyone.  Exercises handed in
beyond the assignment are graded and shown, but not counted, and the summary says so.  Without an
assignment the grade is out of every exercise that the class's notebooks check, and one line says so.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

from ..errors import ModbusError
from ..exercises import EXERCISES, inventory

FILE = "assignment.json"
"""The assignment file's name, looked for beside the class."""
POINTS = 100
"""The grade of a learner with every counted exercise right, when neither ``--points`` nor the assignment
file says."""
FILE_LIMIT = 100_000
"""The largest assignment file read, in bytes."""


class AssignmentError(ModbusError, ValueError):
    """An assignment the grader cannot read: a notebook or exercise the course does not have, a file that
    is not the JSON described in :mod:`.assignment`."""


def _order(key: str) -> tuple:
    return tuple(int(p) if p.isdigit() else 0 for p in key.split("."))


def course_notebooks() -> list[str]:
    """The numbers of the course's notebooks that have exercises ("00" ... "17")."""
    return sorted({key.split(".")[0] for key in EXERCISES})


def scored(key: str) -> bool:
    """Whether an exercise can count towards a grade (the concept inventory's quizzes do not)."""
    return key in EXERCISES and key not in (inventory.PRE, inventory.POST)


@dataclass(frozen=True)
class Assignment:
    """The exercises that count (in the course's order), the notebooks they were given by (empty when
    given exercise by exercise), the points (None: not said) and where it was said."""

    exercises: tuple[str, ...]
    notebooks: tuple[str, ...] = ()
    points: float | None = None
    source: str = "--notebooks"

    def line(self) -> str:
        """One line: what the grade is out of, and who said so."""
        what = (f"notebook(s) {', '.join(self.notebooks)}" if self.notebooks
                else f"exercise(s) {', '.join(self.exercises)}")
        return f"The grade is out of the {len(self.exercises)} exercise(s) of {what} ({self.source})."


def unassigned_line(count: int) -> str:
    """The line said when no assignment was given."""
    return (f"No assignment given (--notebooks 00,01,03, or {FILE} beside the class): the grade is out of "
            f"the {count} exercise(s) that the class's notebooks check, whoever handed them in.")


def _numbers(given: list) -> tuple[str, ...]:
    known = course_notebooks()
    numbers = []
    for item in given:
        text = str(item).strip()
        if not re.fullmatch(r"\d{1,2}", text):
            raise AssignmentError(f"{text!r} is not a notebook number: write the notebooks as numbers, "
                                  "--notebooks 00,01,03 (or [\"00\", \"01\"] in the file)")
        number = text.zfill(2)
        if number not in known:
            raise AssignmentError(f"notebook {number} has no exercises; the course's notebooks with "
                                  f"exercises are {', '.join(known)}")
        numbers.append(number)
    return tuple(sorted(set(numbers)))


def from_notebooks(numbers: list, points: float | None = None, source: str = "--notebooks") -> Assignment:
    """The assignment of whole notebooks (``["00", "3"]``), each with all its scored exercises."""
    chosen = _numbers(numbers)
    if not chosen:
        raise AssignmentError("no notebook given: --notebooks 00,01,03 names the notebooks that count")
    keys = sorted((key for key in EXERCISES if key.split(".")[0] in chosen and scored(key)), key=_order)
    return Assignment(tuple(keys), chosen, points, source)


def from_exercises(keys: list, points: float | None = None, source: str = FILE) -> Assignment:
    """The assignment of single exercises (``["03.1", "03.5"]``)."""
    wrong = [str(key) for key in keys if not scored(str(key))]
    if wrong:
        raise AssignmentError(f"{', '.join(map(repr, wrong[:5]))}: not exercises a grade can count (the "
                              "course's exercises are written like 03.1; the inventory's 00.0 and 17.0 are "
                              "not graded)")
    if not keys:
        raise AssignmentError("no exercise given")
    return Assignment(tuple(sorted({str(key) for key in keys}, key=_order)), (), points, source)


def _points(value) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 1_000_000:
        raise AssignmentError(f"points must be a number above 0 (the platform's maximum grade), not "
                              f"{value!r}")
    return value


def read(path: Path) -> Assignment:
    """The assignment in the JSON file ``path``."""
    try:
        with path.open("rb") as stream:
            text = stream.read(FILE_LIMIT + 1)
        if len(text) > FILE_LIMIT:
            raise ValueError(f"more than {FILE_LIMIT:,} bytes")
        data = json.loads(text.decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise AssignmentError(f"{path}: cannot be read as JSON ({type(exc).__name__}: {exc}); write it as "
                              '{"notebooks": ["00", "01", "03"], "points": 20}') from exc
    if not isinstance(data, dict) or not ({"notebooks", "exercises"} & set(data)) or \
            set(data) - {"notebooks", "exercises", "points"}:
        raise AssignmentError(f'{path}: expected {{"notebooks": [...]}} or {{"exercises": [...]}}, with '
                              f'"points" if you like; found {str(data)[:80]!r}')
    points = _points(data.get("points"))
    listed = data.get("notebooks", data.get("exercises"))
    if not isinstance(listed, list):
        raise AssignmentError(f"{path}: the notebooks or exercises are a list, [\"03\", \"05\"]")
    if "notebooks" in data:
        return from_notebooks(listed, points, str(path))
    return from_exercises(listed, points, str(path))


def beside(paths: list[Path]) -> list[Path]:
    """The assignment files beside the class: in a folder given, or in the folder of a zip or notebook
    given (never inside a learner's folder or zip)."""
    found = []
    for path in paths:
        for folder in ([path] if path.is_dir() else []) + [path.resolve().parent]:
            candidate = folder / FILE
            if candidate.is_file() and candidate.resolve() not in [p.resolve() for p in found]:
                found.append(candidate)
    return found


def resolve(paths: list[Path], notebooks: str | None = None, file: Path | None = None) -> Assignment | None:
    """The assignment the instructor gave: ``--notebooks`` (a comma-separated list), else the file given,
    else the one beside the class; None when there is none.  ``--notebooks`` with a file keeps the file's
    points."""
    files = [file] if file is not None else beside(paths)
    if len(files) > 1:
        raise AssignmentError(f"two assignment files beside the class ({', '.join(map(str, files))}): keep "
                              "one, or name it with --assigned")
    from_file = read(files[0]) if files else None
    if notebooks is not None:
        points = from_file.points if from_file else None
        return from_notebooks([part for part in notebooks.split(",") if part.strip()], points, "--notebooks")
    return from_file
