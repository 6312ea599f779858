"""The gradebook's scores as a learning platform's grade import reads them: ``--export moodle|canvas``.

- **Moodle**: the assignment's offline grading worksheet ("Upload grading worksheet", with the
  assignment's "Offline grading worksheet" feedback type on).  Moodle finds each row's learner by the
  ``Identifier`` column, ``Participant ID`` with the participant id its "Download all submissions" put in
  every file name, reads ``Grade`` (at most the assignment's maximum grade) and skips a row whose grade
  was changed in Moodle after ``Last modified (grade)``; ``Feedback comments`` fills the comments when
  that feedback type is on too.
  Its headers are matched in the site's language: the worksheet a French Moodle exports says
  ``Identifiant``, ``Note``; this one writes Moodle's English headers, which a site in another language
  may not match (download that site's worksheet once and compare, or switch your language to English
  for the upload).
- **Canvas**: the Gradebook's "Import" CSV: ``Student``, ``ID`` (the user id that Canvas's "Download
  submissions" put in every file name, which the import matches rows by), ``SIS User ID``, ``SIS Login
  ID``, ``Section``, then one column per assignment, named as Canvas's own export names it
  (``Notebooks (4321)`` updates assignment 4321: :func:`canvas_column` makes it from the id; without an
  id the import makes a new assignment, and :func:`canvas_line` says so).

The grade is the share of the counted exercises (:mod:`.assignment`) a learner got right, out of
``points`` (the assignment's maximum grade; 100 unless said).  A learner the platform did not name (a
folder gathered by hand) has no id the import could match, so is left out, and said.
:func:`check_layout` says, before anything is graded, whether the class as read can be exported at all.
"""

from __future__ import annotations

import csv
import re
from datetime import datetime, timezone
from pathlib import Path

from ..errors import ModbusError
from .reports import csv_cell
from .submissions import PLATFORMS, Identity

FORMATS = ("moodle", "canvas")
MAXIMUM = 100
"""The grade of a learner with every exercise right."""
ASSIGNMENT = "Modbus notebooks"
"""The Canvas column's name when none is given."""


class ExportError(ModbusError):
    """An export the platform's import could not match to its learners."""


def grade_of(right: int, total: int, points: float = MAXIMUM) -> float:
    """The grade out of ``points`` for ``right`` of ``total`` exercises, two decimals."""
    return round(points * right / total, 2) if total else 0.0


def canvas_column(assignment: str | None) -> str:
    """The Canvas column for ``--assignment``: an assignment's id (``4321``, the number in its address)
    becomes ``"Modbus notebooks (4321)"``, which Canvas's import matches to that assignment; a name is
    kept as written (``"Notebooks (4321)"``); none gives :data:`ASSIGNMENT`, a new assignment."""
    if assignment is None:
        return ASSIGNMENT
    text = assignment.strip()
    return f"{ASSIGNMENT} ({text})" if text.isdigit() else text


def canvas_line(assignment: str | None, points: float) -> str | None:
    """The one line said when no Canvas assignment id was given (None when one was)."""
    if assignment is not None and re.search(r"\(\d+\)\s*$|^\s*\d+\s*$", assignment):
        return None
    return (f"Canvas: no assignment id (--assignment 4321, the number in the assignment's address), so its "
            f"import makes a new assignment column {canvas_column(assignment)!r}, out of {points:g} points")


def check_layout(platform: str, identities: dict[str, Identity]) -> None:
    """Raise :class:`ExportError` unless some learner of the class as read has an id of ``platform`` (so
    that a wrong ``--export`` stops before the class is graded, not after)."""
    if platform not in FORMATS:
        raise ExportError(f"no export for {platform!r}: choose one of {', '.join(FORMATS)}")
    if not any(person.platform == platform for person in identities.values()):
        name = PLATFORMS[platform]
        download = "Download all submissions" if platform == "moodle" else "Download submissions"
        found = sorted({PLATFORMS.get(person.platform, person.platform) for person in identities.values()})
        read = f"they came from {', '.join(found)}" if found else "they were gathered by hand"
        raise ExportError(f"none of the learners came from a {name} download ({read}), so none has the id "
                          f"{name}'s import matches rows by: grade the files as {name}'s \"{download}\" "
                          "names them (or its zip), then export (nothing was graded)")


def export(path: Path, platform: str, scores: dict[str, tuple[int, int]], identities: dict[str, Identity],
           assignment: str | None = ASSIGNMENT, when: datetime | None = None,
           points: float = MAXIMUM) -> list[str]:
    """Write ``path`` for ``platform``'s grade import from each learner's (right, out of) exercises, each
    grade out of ``points``; the learners left out (no id of that platform) are returned."""
    check_layout(platform, identities)
    known = {learner: identities[learner] for learner in scores
             if learner in identities and identities[learner].platform == platform}
    when = when or datetime.now(timezone.utc)
    if platform == "moodle":
        rows: list[list] = [["Identifier", "Full name", "Email address", "Grade", "Maximum Grade",
                             "Last modified (grade)", "Feedback comments"]]
        for learner, person in sorted(known.items(), key=lambda item: int(item[1].id)):
            right, total = scores[learner]
            rows.append([f"Participant {person.id}", csv_cell(person.name), "",
                         grade_of(right, total, points), points, when.isoformat(timespec="seconds"),
                         f"{right} of {total} exercises right (modbus-edu grade)"])
    else:
        column = csv_cell(canvas_column(assignment))
        rows = [["Student", "ID", "SIS User ID", "SIS Login ID", "Section", column]]
        for learner, person in sorted(known.items(), key=lambda item: (item[1].name, int(item[1].id))):
            right, total = scores[learner]
            rows.append([csv_cell(person.name), int(person.id), "", "", "", grade_of(right, total, points)])
    with path.open("w", newline="", encoding="utf-8") as stream:
        csv.writer(stream).writerows(rows)
    return sorted(learner for learner in scores if learner not in known)
