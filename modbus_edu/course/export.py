"""The gradebook's scores as a learning platform's grade import reads them: ``--export moodle|canvas``.

- **Moodle**: the assignment's offline grading worksheet ("Upload grading worksheet", with the
  assignment's "Offline grading worksheet" feedback type on).  Moodle finds each row's learner by the
  ``Identifier`` column, ``Participant ID`` with the participant id its "Download all submissions" put in
  every file name, reads ``Grade`` (at most the assignment's maximum grade) and skips a row whose grade
  was changed in Moodle after ``Last modified (grade)``; ``Feedback comments`` fills the comments when
  that feedback type is on too.
- **Canvas**: the Gradebook's "Import" CSV: ``Student``, ``ID`` (the user id that Canvas's "Download
  submissions" put in every file name, which the import matches rows by), ``SIS User ID``, ``SIS Login
  ID``, ``Section``, then one column per assignment, named as Canvas's own export names it
  (``Notebooks (4321)`` updates assignment 4321; a new name makes a new assignment).

The grade is the share of the gradebook's exercises a learner got right, out of 100.  A learner the
platform did not name (a folder gathered by hand) has no id the import could match, so is left out, and
said.
"""

from __future__ import annotations

import csv
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


def grade_of(right: int, total: int) -> float:
    """The grade out of :data:`MAXIMUM` for ``right`` of ``total`` exercises, two decimals."""
    return round(MAXIMUM * right / total, 2) if total else 0.0


def export(path: Path, platform: str, scores: dict[str, tuple[int, int]], identities: dict[str, Identity],
           assignment: str = ASSIGNMENT, when: datetime | None = None) -> list[str]:
    """Write ``path`` for ``platform``'s grade import from each learner's (right, out of) exercises; the
    learners left out (no id of that platform) are returned."""
    if platform not in FORMATS:
        raise ExportError(f"no export for {platform!r}: choose one of {', '.join(FORMATS)}")
    known = {learner: identities[learner] for learner in scores
             if learner in identities and identities[learner].platform == platform}
    if not known:
        name = PLATFORMS[platform]
        download = "Download all submissions" if platform == "moodle" else "Download submissions"
        raise ExportError(f"none of the learners came from a {name} download, so none has the id {name}'s "
                          f"import matches rows by: grade the files as {name}'s \"{download}\" names them "
                          "(or its zip), then export")
    when = when or datetime.now(timezone.utc)
    if platform == "moodle":
        rows: list[list] = [["Identifier", "Full name", "Email address", "Grade", "Maximum Grade",
                             "Last modified (grade)", "Feedback comments"]]
        for learner, person in sorted(known.items(), key=lambda item: int(item[1].id)):
            right, total = scores[learner]
            rows.append([f"Participant {person.id}", csv_cell(person.name), "", grade_of(right, total),
                         MAXIMUM, when.isoformat(timespec="seconds"),
                         f"{right} of {total} exercises right (modbus-edu grade)"])
    else:
        rows = [["Student", "ID", "SIS User ID", "SIS Login ID", "Section", csv_cell(assignment)]]
        for learner, person in sorted(known.items(), key=lambda item: item[1].name):
            right, total = scores[learner]
            rows.append([csv_cell(person.name), int(person.id), "", "", "", grade_of(right, total)])
    with path.open("w", newline="", encoding="utf-8") as stream:
        csv.writer(stream).writerows(rows)
    return sorted(learner for learner in scores if learner not in known)
