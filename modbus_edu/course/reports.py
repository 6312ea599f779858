"""The gradebook's reports: ``gradebook.csv``, a page per learner, and the class summary.

Everything in them that a learner wrote (a name, a folder's name, an exercise key, a checker's feedback
quoting an answer, a flag) is data, never markup or a formula: every HTML cell is escaped, and every CSV
cell of text that a spreadsheet would read as a formula (one starting with ``=``, ``+``, ``-``, ``@``, a
tab or a carriage return), a number or a date (an exercise ``03.1``, a learner ``6/12``) starts with a
single quote, as OWASP advises for formulas.  Scores are numbers, in columns of their own (right, then
out of how many), never a fraction a spreadsheet takes for a date.  :func:`printable` does the same for
a terminal.
"""

from __future__ import annotations

import csv
import hashlib
import html
import re
from collections import Counter
from pathlib import Path

from ..codes import _printable
from ..exercises import inventory
from .assignment import Score
from .verdicts import ERRORED, NOT_ANSWERED, NOT_HANDED_IN, RIGHT, WRONG, Verdict, feedback, slip

FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
MONTH = r"(?:jan|feb|mar|apr|may|jun|jul|aug|sep|oct|nov|dec)[a-z]*\.?"
LOOKS_LIKE_DATA = re.compile(rf"""\s*(?:
    [(]?[$€£]?[\d.,' ]*\d[\d.,' ]*(?:e[-+]?\d+)?\s*%?[)]?            # 3, 03.1, 1,5, 1 000, 1e5, 50%
  | \d{{1,4}}\s*[-/.]\s*\d{{1,4}}(?:\s*[-/.]\s*\d{{1,4}})?(?:[ t].*)?   # 6/12, 2024-01-05, 1.2.3
  | \d{{1,2}}:\d{{2}}(?::\d{{2}})?\s*(?:[ap]\.?m\.?)?                    # 10:30, 10:30 pm
  | \d{{1,4}}[-/ ]*{MONTH}(?:[-/ ,]*\d{{1,4}})?                       # 5-May, 5 may 2024
  | {MONTH}[-/ ,]*\d{{1,4}}(?:[-/ ,]+\d{{1,4}})?                       # May-5, March 2024
  | true | false
)\s*""", re.IGNORECASE | re.VERBOSE)
"""Text a spreadsheet turns into a number, a date, a time or a truth value when it opens a CSV."""
SLIPS_SHOWN = 3
"""Slips the summary names per exercise (the most frequent)."""


def csv_cell(value: object) -> str:
    """A CSV cell as a spreadsheet should read it: a number (int, float) as itself; text that starts like
    a formula, or that a spreadsheet would turn into a number or a date, after a ``'``."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return str(value)
    text = str(value)
    return "'" + text if text.startswith(FORMULA_START) or LOOKS_LIKE_DATA.fullmatch(text) else text


def _csv(path: Path, rows: list[list]) -> None:
    with path.open("w", newline="", encoding="utf-8", errors="replace") as stream:
        csv.writer(stream).writerows([[csv_cell(cell) for cell in row] for row in rows])


def _h(value: object) -> str:
    return html.escape(str(value), quote=True)


def printable(text: object) -> str:
    """``text`` for a terminal: every control character (an escape sequence's ESC, a line break, a
    bidirectional override) written as Python writes it (``\\x1b``), so a name cannot act on the screen."""
    return _printable(str(text))


def page_name(learner: str, digits: int = 12) -> str:
    """The file name of a learner's page: the name itself when it is plain (``[a-z0-9_-]``), else a plain
    form of it, a dot and a hash: no name reaches outside ``learners/``, and a plain name (which holds no
    dot) never takes a hashed one's place (``ada-99a563ab`` is not ``Ada``'s page)."""
    plain = re.sub(r"[^a-z0-9_-]+", "_", learner.casefold()).strip("_")[:40]
    if plain == learner:
        return f"{plain}.html"
    digest = hashlib.sha256(learner.encode("utf-8", "surrogatepass")).hexdigest()
    return f"{plain or 'learner'}.{digest[:digits]}.html"


def page_names(learners: list[str]) -> dict[str, str]:
    """Each learner's page name (:func:`page_name`), the hash made longer for any two that would share
    one, so that no page ever overwrites another."""
    pages: dict[str, str] = {}
    taken: set[str] = set()
    for learner in sorted(set(learners)):
        digits = 12
        page = page_name(learner, digits)
        while page in taken and digits < 64:
            digits += 4
            page = page_name(learner, digits)
        pages[learner] = page
        taken.add(page)
    return pages


def _counts(row: dict, exercises: list[str]) -> Counter:
    return Counter(row.get(key, Verdict(NOT_ANSWERED)).status for key in exercises)


def inventory_score(marks: dict[str, bool] | None) -> int | str:
    """A learner's right answers on one concept-inventory quiz (a number), or "" when not answered."""
    return "" if marks is None else sum(marks.values())


OUT_OF = "out of"
"""The gradebook's column of how many exercises a score is out of."""
POINTS, POINTS_OUT_OF = "points", "points out of"
"""The gradebook's columns of the points a learner earned and of the points assigned."""


def _number(value: float) -> int | float:
    """A number of points as a spreadsheet should show it: ``4`` rather than ``4.0``."""
    return int(value) if float(value).is_integer() else round(value, 2)
INVENTORY_QUESTIONS = "inventory questions"


NOT_COUNTED = " (not counted)"
"""What the gradebook's header adds to an exercise graded beyond the assignment."""


def _write_csv(path: Path, table: dict, exercises: list[str], flags: dict,
               marks: dict[str, dict] | None = None, counted: list[str] | None = None,
               scores: dict[str, Score] | None = None) -> None:
    """``gradebook.csv``: a row per learner, each exercise's verdict (an exercise beyond the assignment,
    ``counted``, headed "03.4 (not counted)"), the counts of each verdict over the counted exercises
    (``right``, ``out of`` how many exercises), the points earned (``points``, of ``points out of``: the
    score the grade is the share of; each exercise 1 point unless the assignment gives its points), the
    concept inventory's right answers before and after (of ``inventory questions``), and the flags; every
    score a number."""
    counted = exercises if counted is None else counted
    header = [key if key in counted else key + NOT_COUNTED for key in exercises]
    rows: list[list] = [["learner", *header, RIGHT, WRONG, NOT_ANSWERED, NOT_HANDED_IN, ERRORED, OUT_OF,
                         POINTS, POINTS_OUT_OF, "inventory pre", "inventory post", INVENTORY_QUESTIONS,
                         "flags"]]
    for learner, row in table.items():
        counts = _counts(row, counted)
        mark = (scores or {}).get(learner) or Score(counts[RIGHT], len(counted), counts[RIGHT], len(counted))
        quiz = (marks or {}).get(learner, {})
        answered = quiz.get(inventory.PRE) is not None or quiz.get(inventory.POST) is not None
        rows.append([learner, *(row.get(key, Verdict(NOT_ANSWERED)).status for key in exercises),
                     counts[RIGHT], counts[WRONG], counts[NOT_ANSWERED], counts[NOT_HANDED_IN],
                     counts[ERRORED], len(counted), _number(mark.earned), _number(mark.possible),
                     inventory_score(quiz.get(inventory.PRE)), inventory_score(quiz.get(inventory.POST)),
                     len(inventory.QUESTIONS) if answered else "", " | ".join(flags[learner])])
    _csv(path, rows)


PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>{title}</title><style>
body {{ font-family: sans-serif; max-width: 60em; margin: 2em auto; }} td, th {{ padding: .3em .6em;
vertical-align: top; border-bottom: 1px solid #ddd; text-align: left; }} .right {{ color: #1a7f37; }}
.wrong {{ color: #b35900; }} .errored {{ color: #c62828; }} pre {{ white-space: pre-wrap; margin: 0; }}
</style></head><body><h1>{title}</h1>{body}</body></html>
"""


def _list(items: list[str]) -> str:
    """An HTML list of already escaped items."""
    return "<ul>" + "".join(f"<li>{item}</li>" for item in items) + "</ul>"


def _write_learner(path: Path, learner: str, row: dict, exercises: list[str], flags: list[str],
                   out_of: str = "", beyond: dict[str, Verdict] | None = None, mark: Score | None = None,
                   worth: dict[str, float] | None = None) -> None:
    """A learner's page: the score (and the points, when the assignment gives each exercise its points,
    ``worth``), what it is out of, the flags, then one row per exercise asked (``exercises``: the
    counted ones, each with its points), a notebook not handed in as one row, and the exercises handed in
    beyond the assignment in one line (graded, not counted)."""
    points = (f": {_number(mark.earned)} of {_number(mark.possible)} points" if worth and mark is not None
              else "")
    parts = [f"<p>{_counts(row, exercises)[RIGHT]} of {len(exercises)} exercises right{points}. "
             f"{_h(out_of)}</p>"]
    if flags:
        parts.append("<h2>About the notebooks</h2>" + _list([_h(flag) for flag in flags]))
    parts.append("<table><tr><th>exercise</th><th>result</th><th>the checker's feedback</th></tr>")
    missing: dict[str, list[str]] = {}
    for key in exercises:
        verdict = row.get(key, Verdict(NOT_ANSWERED, "no cell of the notebooks checks this exercise"))
        if verdict.status == NOT_HANDED_IN:
            missing.setdefault(key.split(".")[0], []).append(key)
            continue
        shown = f"{key} ({_number(worth[key])} pt)" if worth and key in worth else key
        parts.append(f"<tr><td>{_h(shown)}</td><td class='{_h(verdict.status.split()[0])}'>"
                     f"{_h(verdict.status)}</td><td><pre>{_h(verdict.message)}</pre></td></tr>")
    for number, keys in missing.items():
        parts.append(f"<tr><td>{_h(', '.join(keys))}</td><td class='not'>{NOT_HANDED_IN}</td><td><pre>"
                     f"notebook {_h(number)} was not handed in</pre></td></tr>")
    parts.append("</table>")
    if beyond:
        shown = "; ".join(f"{key} {verdict.status}" for key, verdict in beyond.items()
                          if verdict.status != NOT_HANDED_IN)
        if shown:
            parts.append(f"<p>Also graded, not counted (not in the assignment): {_h(shown)}.</p>")
    path.write_text(PAGE.format(title=f"Feedback for {_h(learner)}", body="".join(parts)), encoding="utf-8",
                    errors="replace")


def _slips(table: dict, key: str) -> list[dict]:
    """The slips of an exercise, most learners first: the slip's name, whether the catalogue names it,
    the learners who made it and one real feedback message (numbers kept)."""
    found: dict[str, dict] = {}
    for learner, row in table.items():
        verdict = row.get(key)
        if verdict is None or verdict.status != WRONG:
            continue
        name, named = slip(verdict.message)
        entry = found.setdefault(name, {"slip": name, "named": named, "learners": [],
                                        "example": feedback(verdict.message)})
        entry["learners"].append(learner)
    return sorted(found.values(), key=lambda s: (-len(s["learners"]), not s["named"], s["slip"]))


def _slip_html(entry: dict, where: str = "") -> str:
    name = f"<b>{_h(entry['slip'])}</b>" if entry["named"] else f"unnamed: {_h(entry['slip'])}"
    return (f"{name}{where} ({len(entry['learners'])}: {_h(', '.join(entry['learners']))})"
            f"<br><small>e.g. “{_h(entry['example'])}”</small>")


def question_numbers(question: str) -> str:
    """A concept-inventory question as notebooks 00 and 17 number it: ``"5 / 9"`` (its number in 00, then
    in 17); the overall row as it is."""
    if question not in inventory.BY_ID:
        return question
    return " / ".join(str(inventory.ORDERS[quiz].index(question) + 1)
                      for quiz in (inventory.PRE, inventory.POST))


def gain_shown(row: inventory.Gain) -> str:
    """g as the summary shows it; where g is undefined (the class all right before), what happened after:
    "—" when it stayed all right, the drop ("100% → 75% (−25)") when it did not."""
    if row.g is None and row.post < row.pre:
        return f"{row.pre:.0%} → {row.post:.0%} (−{round((row.pre - row.post) * 100)})"
    return row.shown


def _gain_html(marks: dict[str, dict]) -> tuple[str, list[inventory.Gain]]:
    """The concept inventory's section of the summary: per question (numbered as notebooks 00 and 17
    print it), what it probes, the class's share right before and after, and the normalised gain g;
    then the overall g.  Empty when no learner answered both quizzes."""
    rows, overall = inventory.gains({learner: (quiz.get(inventory.PRE), quiz.get(inventory.POST))
                                     for learner, quiz in marks.items()})
    if overall is None:
        return "", []
    learners = sum(1 for quiz in marks.values() if quiz.get(inventory.PRE) and quiz.get(inventory.POST))
    parts = [f"<h2>Concept inventory: what moved</h2><p>{learners} learners answered the twelve questions "
             f"before (00.0) and after (17.0) the course. g = (post - pre) / (100 % - pre): the share of "
             f"what was left to learn that was learned; where the class was all right before, g is "
             f"undefined: “—” when it stayed all right, else the drop.</p>"
             "<table><tr><th>question (00 / 17)</th><th>what it probes</th><th>pre</th><th>post</th>"
             "<th>g</th></tr>"]
    for row in [*rows, overall]:
        parts.append(f"<tr><td>{_h(question_numbers(row.question))}</td><td>{_h(row.label)}</td>"
                     f"<td>{row.pre:.0%}</td><td>{row.post:.0%}</td><td>{_h(gain_shown(row))}</td></tr>")
    parts.append(f"</table><p>Overall normalised gain: g = {_h(overall.shown)}.</p>")
    return "".join(parts), [*rows, overall]


def _handed(table: dict, key: str, handed: dict[str, set[str]] | None) -> list[str]:
    """The learners who handed in the notebook of exercise ``key`` (by its number, as
    :func:`.verdicts.handed_in` gives them; without that, those whose notebooks check it)."""
    def checked(row: dict) -> bool:  # a verdict, and not the "not handed in" of a filled row
        return row.get(key, Verdict(NOT_HANDED_IN)).status != NOT_HANDED_IN

    if handed is None:
        return [learner for learner, row in table.items() if checked(row)]
    number = key.split(".")[0]
    return [learner for learner in table if number in handed.get(learner, set()) or checked(table[learner])]


def _write_summary(out: Path, table: dict, exercises: list[str], flags: dict,
                   look_at: dict[str, list[str]] | None = None, notes: list[str] | None = None,
                   marks: dict[str, dict] | None = None, handed: dict[str, set[str]] | None = None, *,
                   counted: list[str] | None = None, out_of: str = "", shared: list[str] | None = None,
                   worth: dict[str, float] | None = None) -> dict:
    """``summary.csv`` and ``summary.html``: what the grade is out of (``out_of``) and the exercises
    graded beyond it (not ``counted``), each exercise's success rate (among the learners who handed its
    notebook in) and slips, the class's slips by their catalogue names, the concept inventory's gains,
    the answer cells learners share byte for byte (``shared``), the notebooks to look at and how the
    submissions were read."""
    counted = exercises if counted is None else counted
    beyond = [key for key in exercises if key not in counted]
    look_at = {learner: found for learner, found in (look_at or {}).items() if found}
    rows = []
    for key in exercises:
        learners = _handed(table, key, handed)
        counts = Counter(table[learner].get(key, Verdict(NOT_ANSWERED)).status for learner in learners)
        rows.append({"exercise": key, "learners": len(learners), **{s: counts[s] for s in
                     (RIGHT, WRONG, NOT_ANSWERED, ERRORED)},
                     "success rate": counts[RIGHT] / len(learners) if learners else 0.0,
                     "slips": _slips(table, key), "counted": key in counted})
    lines: list[list] = [["exercise", "learners who handed it in", RIGHT, WRONG, NOT_ANSWERED, ERRORED,
                          "success rate (%)", "most frequent misconception", "learners with it", "who",
                          "example feedback", "counted", POINTS]]
    for row in rows:
        top = row["slips"][0] if row["slips"] else {"slip": "", "learners": [], "example": ""}
        lines.append([row["exercise"], row["learners"], row[RIGHT], row[WRONG], row[NOT_ANSWERED],
                      row[ERRORED], round(100 * row["success rate"], 1), top["slip"], len(top["learners"]),
                      ", ".join(top["learners"]), top["example"], "yes" if row["counted"] else "no",
                      _number((worth or {}).get(row["exercise"], 1.0 if row["counted"] else 0.0))])
    _csv(out / "summary.csv", lines)

    parts = [f"<p>{len(table)} learners, {len(exercises)} exercises graded. {_h(out_of)}</p>"]
    if beyond:
        handing = {key: len(_handed(table, key, handed)) for key in beyond}
        parts.append("<p>Graded but not counted (handed in beyond the assignment): " + _h(", ".join(
            f"{key} ({handing[key]} learner(s))" for key in beyond)) + ".</p>")
    if shared:
        parts.append("<h2>Identical answers (for you to look at; never a verdict)</h2>" + _list(
            [_h(line) for line in shared]))
    named: dict[str, dict] = {}
    for row in rows:
        for entry in row["slips"]:
            if entry["named"]:
                merged = named.setdefault(entry["slip"], {**entry, "learners": [], "exercises": []})
                merged["exercises"].append(row["exercise"])
                merged["learners"] += [name for name in entry["learners"] if name not in merged["learners"]]
    if named:
        parts.append("<h2>The class's frequent slips</h2>" + _list([
            _slip_html(entry, f" in {_h(', '.join(entry['exercises']))}")
            for entry in sorted(named.values(), key=lambda e: (-len(e["learners"]), e["slip"]))]))
    parts.append("<h2>Exercises</h2><p>A success rate counts the learners who handed the exercise's notebook "
                 "in.</p><table><tr><th>exercise</th><th>success rate</th><th>learners who handed it in</th>"
                 "<th>right / wrong / not answered / errored</th><th>slips (learners)</th></tr>")
    for row in sorted(rows, key=lambda r: r["success rate"]):
        slips = _list([_slip_html(entry) for entry in row["slips"][:SLIPS_SHOWN]]) if row["slips"] else ""
        parts.append(f"<tr><td>{_h(row['exercise'])}</td><td>{row['success rate']:.0%}</td>"
                     f"<td>{row['learners']}</td><td>{row[RIGHT]} "
                     f"/ {row[WRONG]} / {row[NOT_ANSWERED]} / {row[ERRORED]}</td><td>{slips}</td></tr>")
    parts.append("</table>")
    gain_section, gain_rows = _gain_html(marks or {})
    parts.append(gain_section)
    if look_at:
        parts.append("<h2>Notebooks to look at</h2>" + _list([
            f"{_h(learner)}: {_h('; '.join(found))}" for learner, found in look_at.items()]))
    if notes:
        parts.append("<h2>How the submissions were read</h2>" + _list([_h(note) for note in notes]))
    page = PAGE.format(title="Class summary", body="".join(parts))
    (out / "summary.html").write_text(page, encoding="utf-8", errors="replace")
    flagged = {learner: found for learner, found in flags.items() if found}
    return {"learners": len(table), "exercises": rows, "flags": flagged, "look_at": look_at,
            "notes": list(notes or []), "inventory": gain_rows, "out of": out_of, "beyond": beyond,
            "identical": list(shared or [])}
