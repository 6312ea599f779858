"""What the instructor assigned: the exercises that count towards the grade, and the points it is out of.

Given on the command line (``--notebooks 00,01,03,05,06,17``), or in a small JSON file beside the class
(:data:`FILE`, ``assignment.json``, in the folder given to the grader or beside the zip given)::

    {"notebooks": ["00", "01", "03", "05", "06", "17"], "points": 20}

or, exercise by exercise, ``{"exercises": ["03.1", "03.2", "03.5"], "points": 10}``.  A notebook counts
with all its exercises, the concept inventory's quizzes (00.0, 17.0) aside: they measure the course, not
the learner.  ``points`` is the grade a learner with every counted exercise right gets on the platform
(Moodle's maximum grade, Canvas's points); ``--points`` overrides it, and without either it is 100.

**Points per exercise.**  Either list may be an object that gives points instead:
``{"exercises": {"03.1": 1, "03.5": 4}}`` (each exercise its points), ``{"notebooks": {"03": 10, "05": 6}}``
(a notebook's points shared evenly by its exercises), or both keys at once (an exercise in neither twice).
A list gives each exercise 1 point.  The score is the sum of the points of the exercises answered right,
out of the total of the points assigned; the platform's grade is that share of ``points``, which is the
total itself when points per exercise are given and ``points`` is not.

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
    given exercise by exercise), the platform's points (None: not said), where it was said, and each
    exercise's points when the file gave them (empty: 1 point each)."""

    exercises: tuple[str, ...]
    notebooks: tuple[str, ...] = ()
    points: float | None = None
    source: str = "--notebooks"
    weights: tuple[tuple[str, float], ...] = ()

    def weight(self, key: str) -> float:
        """The points exercise ``key`` is worth (0 when it does not count)."""
        if key not in self.exercises:
            return 0.0
        return dict(self.weights).get(key, 1.0) if self.weights else 1.0

    @property
    def total(self) -> float:
        """The points of every counted exercise together."""
        return sum(self.weight(key) for key in self.exercises)

    def maximum(self) -> float | None:
        """The platform's grade for a learner with every counted exercise right: ``points`` when said,
        else the total of the points per exercise when those were given, else None (:data:`POINTS`)."""
        if self.points is not None:
            return self.points
        return self.total if self.weights else None

    def line(self) -> str:
        """One line: what the grade is out of, and who said so."""
        what = (f"notebook(s) {', '.join(self.notebooks)}" if self.notebooks
                else f"exercise(s) {', '.join(self.exercises)}")
        if not self.weights:
            return f"The grade is out of the {len(self.exercises)} exercise(s) of {what} ({self.source})."
        return (f"The grade is out of {self.total:g} points, the points of the {len(self.exercises)} "
                f"exercise(s) of {what} ({self.source}).")


@dataclass(frozen=True)
class Score:
    """A learner's score: the counted exercises right, of how many, and the points they earn, of how many
    (the same two numbers when every exercise is worth 1 point)."""

    right: int
    out_of: int
    earned: float
    possible: float

    def share(self) -> float:
        """The share of the points earned, 0 to 1."""
        return self.earned / self.possible if self.possible else 0.0


def score(right_keys: list[str], counted: list[str], assignment: Assignment | None = None) -> Score:
    """The score of a learner whose ``right_keys`` were right, over the ``counted`` exercises (each worth
    its points in ``assignment``, else 1)."""
    weight = assignment.weight if assignment is not None else (lambda key: 1.0)
    right = [key for key in right_keys if key in counted]
    return Score(len(right), len(counted), round(sum(weight(key) for key in right), 6),
                 round(sum(weight(key) for key in counted), 6))


def as_score(value: Score | tuple) -> Score:
    """A :class:`Score` from a score or a (right, out of) pair (each exercise 1 point)."""
    if isinstance(value, Score):
        return value
    if len(value) == 2:
        return Score(int(value[0]), int(value[1]), float(value[0]), float(value[1]))
    return Score(*value)


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


def _worth(value, what: str, path: Path) -> float:
    """The points of one exercise or notebook, as the file gives them."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 1_000_000:
        raise AssignmentError(f"{path}: {what} is worth {value!r}; give its points as a number above 0 "
                              '({"03.5": 4})')
    return float(value)


def _weighted(data: dict, points: float | None, path: Path) -> Assignment:
    """The assignment of a file that gives points per notebook or per exercise (either list an object),
    or names both notebooks and exercises."""
    weights: dict[str, float] = {}
    notebooks: tuple[str, ...] = ()
    given = data.get("notebooks", [])
    if given:
        numbers = list(given) if isinstance(given, dict) else given
        notebooks = from_notebooks(numbers, points, str(path)).notebooks
        for item in numbers:
            number = str(item).strip().zfill(2)
            keys = [key for key in EXERCISES if key.split(".")[0] == number and scored(key)]
            share = _worth(given[item], f"notebook {number}", path) / len(keys) if isinstance(given, dict) \
                else 1.0
            weights.update(dict.fromkeys(keys, share))
    listed = data.get("exercises", [])
    keys = [str(key) for key in listed]
    if keys:
        from_exercises(keys, points, str(path))  # the same checks
    twice = sorted({key for key in keys if key in weights}, key=_order)
    if twice:
        raise AssignmentError(f"{path}: {', '.join(twice[:5])} counted twice, by its notebook and by itself; "
                              "name it once")
    for key in keys:
        weights[key] = _worth(listed[key], key, path) if isinstance(listed, dict) else 1.0
    if not weights:
        raise AssignmentError(f"{path}: no notebook and no exercise given")
    exercises = tuple(sorted(weights, key=_order))
    by_points = isinstance(given, dict) or isinstance(listed, dict)
    return Assignment(exercises, notebooks if not keys else (), points, str(path),
                      tuple((key, weights[key]) for key in exercises) if by_points else ())


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
    lists = [data[key] for key in ("notebooks", "exercises") if key in data]
    if not all(isinstance(listed, (list, dict)) for listed in lists):
        raise AssignmentError(f"{path}: the notebooks or exercises are a list, [\"03\", \"05\"], or an "
                              "object of their points, {\"03\": 10}")
    if len(lists) == 1 and isinstance(lists[0], list):
        if "notebooks" in data:
            return from_notebooks(lists[0], points, str(path))
        return from_exercises(lists[0], points, str(path))
    return _weighted(data, points, path)


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
