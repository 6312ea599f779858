"""The gradebook's scores as a learning platform's grade import reads them: ``--export moodle|canvas``.

- **Moodle**: the assignment's offline grading worksheet ("Upload grading worksheet", with the
  assignment's "Offline grading worksheet" feedback type on).  Moodle finds each row's learner by the
  ``Identifier`` column, ``Participant `` and the participant id its "Download all submissions" put in
  every file name, reads ``Grade`` (at most the assignment's maximum grade) and skips a row whose grade
  was changed in Moodle after ``Last modified (grade)``; ``Feedback comments`` fills the comments when
  that feedback type is on too.
  Moodle matches those headers, and the ``Participant`` before each id, in the language of the page you
  upload from (``get_string`` of ``recordid``, ``gradenoun``, ``lastmodifiedgrade``, ``hiddenuser`` and
  the comments plugin's name): ``language`` writes them as that language's Moodle pack has them
  (:data:`MOODLE_WORDS`: English, French, German, Spanish, read from Moodle 4.5's packs).
- **Canvas**: the Gradebook's "Import" CSV: ``Student``, ``ID`` (the user id that Canvas's "Download
  submissions" put in every file name, which the import matches rows by), ``SIS User ID``, ``SIS Login
  ID``, ``Section``, then one column per assignment, named as Canvas's own export names it
  (``Notebooks (4321)`` updates assignment 4321: :func:`canvas_column` makes it from the id; without an
  id the import takes the column for an assignment of exactly that title, else makes a new assignment,
  and :func:`canvas_line` says so).  Under the header, as in Canvas's own export, a ``Points Possible``
  row gives the column's points: a new assignment is made with them.

The grade is the share of the counted exercises' points (:mod:`.assignment`) a learner earned, out of
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
from .assignment import Score, as_score
from .reports import csv_cell
from .submissions import PLATFORMS, Identity

FORMATS = ("moodle", "canvas")
MAXIMUM = 100
"""The grade of a learner with every exercise right."""
ASSIGNMENT = "Modbus notebooks"
"""The Canvas column's name when none is given."""


class ExportError(ModbusError):
    """An export the platform's import could not match to its learners."""


MOODLE_WORDS = {
    "en": ("Identifier", "Full name", "Email address", "Grade", "Maximum grade", "Last modified (grade)",
           "Feedback comments", "Participant "),
    "fr": ("Identifiant", "Nom complet", "Adresse de courriel", "Note", "Note maximale",
           "Dernière modification (note)", "Feedback par commentaires", "Participant"),
    "de": ("ID", "Vollständiger Name", "E-Mail-Adresse", "Bewertung", "Bestwertung",
           "Zuletzt geändert (Bewertung)", "Feedback als Kommentar", "Teilnehmer/in"),
    "es": ("Identificador", "Nombre completo", "Dirección de correo", "Calificación", "Calificación máxima",
           "Última modificación (calificación)", "Comentarios de retroalimentación", "Participante"),
}
"""Moodle's grading worksheet in each language: the headers (``recordid``, ``fullname``, ``email``,
``gradenoun``, ``maxgrade``, ``lastmodifiedgrade``, the comments plugin's ``pluginname``) and the word
before each participant id (``hiddenuser``), as Moodle's own English strings and its 4.5 language packs
(fr, de, es) write them.  The import strips as many characters as that word has, so it is kept exactly
(English ``"Participant "`` with its space, the packs' without)."""
LANGUAGES = tuple(MOODLE_WORDS)
CANVAS_POINTS_ROW = "    Points Possible"
"""The first cell of the row under the header of Canvas's own Gradebook export, which its import reads
as each assignment's points."""


def grade_of(right: float, total: float, points: float = MAXIMUM) -> float:
    """The grade out of ``points`` for ``right`` of ``total`` points (or exercises), two decimals."""
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
    column = canvas_column(assignment)
    return (f"Canvas: no assignment id (--assignment 4321, the number in the assignment's address), so its "
            f"import fills the assignment titled exactly {column!r} if the course has one, else makes a new "
            f"assignment {column!r} of {points:g} points possible, in a new Gradebook column")


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


def _comment(mark: Score) -> str:
    said = f"{mark.right} of {mark.out_of} exercises right"
    if (mark.earned, mark.possible) != (mark.right, mark.out_of):
        said += f", {mark.earned:g} of {mark.possible:g} points"
    return said + " (modbus-edu grade)"


def export(path: Path, platform: str, scores: dict[str, Score | tuple], identities: dict[str, Identity],
           assignment: str | None = ASSIGNMENT, when: datetime | None = None,
           points: float = MAXIMUM, language: str = "en") -> list[str]:
    """Write ``path`` for ``platform``'s grade import from each learner's score (a :class:`.Score`, or
    a (right, out of) pair), each grade that share of ``points``; Moodle's worksheet in ``language``
    (:data:`MOODLE_WORDS`); the learners left out (no id of that platform) are returned."""
    check_layout(platform, identities)
    if language not in MOODLE_WORDS:
        raise ExportError(f"no Moodle worksheet in {language!r}: choose one of {', '.join(LANGUAGES)} (the "
                          "language of the Moodle page you upload from)")
    known = {learner: identities[learner] for learner in scores
             if learner in identities and identities[learner].platform == platform}
    marks = {learner: as_score(scores[learner]) for learner in known}
    when = when or datetime.now(timezone.utc)
    if platform == "moodle":
        *headers, participant = MOODLE_WORDS[language]
        rows: list[list] = [list(headers)]
        for learner, person in sorted(known.items(), key=lambda item: int(item[1].id)):
            mark = marks[learner]
            rows.append([f"{participant}{person.id}", csv_cell(person.name), "",
                         grade_of(mark.earned, mark.possible, points), points,
                         when.isoformat(timespec="seconds"), _comment(mark)])
    else:
        column = csv_cell(canvas_column(assignment))
        rows = [["Student", "ID", "SIS User ID", "SIS Login ID", "Section", column],
                [CANVAS_POINTS_ROW, "", "", "", "", points]]
        for learner, person in sorted(known.items(), key=lambda item: (item[1].name, int(item[1].id))):
            mark = marks[learner]
            rows.append([csv_cell(person.name), int(person.id), "", "", "",
                         grade_of(mark.earned, mark.possible, points)])
    with path.open("w", newline="", encoding="utf-8") as stream:
        csv.writer(stream).writerows(rows)
    return sorted(learner for learner in scores if learner not in known)
