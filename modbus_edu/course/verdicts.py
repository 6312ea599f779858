"""A learner's verdicts: each exercise's status and the checker's feedback, from the notebooks' runs.

Also what a class's runs decide together: which copy of a notebook counts when a learner handed in
several, and what a notebook not named after a course notebook (``Untitled.ipynb``) may still count for
(:func:`pick_copies`), which notebooks each learner handed in (:func:`handed_in`), which exercises are
the gradebook's columns (:func:`course_keys`: only the
course's own, in the notebooks the class handed in, so a key a learner makes up is a flag, never a
column), the name of each slip (:func:`slip`: the catalogue's label the checker's feedback begins
with), and each learner's marks on the concept inventory (:func:`inventory_marks`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
from dataclasses import dataclass
from datetime import datetime

from ..exercises import EXERCISES, PLACEHOLDER, inventory
from ..exercises.misconceptions import CATALOGUE
from ..exercises.plain import PlainError, revive
from .runner import NotebookRun, exercise_keys
from .submissions import Submission

RIGHT, WRONG, NOT_ANSWERED, ERRORED = "right", "wrong", "not answered", "errored"
NOT_HANDED_IN = "not handed in"
"""An exercise of a notebook the learner did not hand in (``not answered``: handed in, left blank)."""
SHARED_CELL = 80
"""The fewest characters an answer cell must have for two identical copies of it to be worth a look
(shorter ones, ``answer = 0x4B37``, are what every right answer looks like)."""
COURSE_NOTEBOOK = re.compile(r"\d\d_")
"""A course notebook's title starts with its number: ``03_rtu_and_crc``."""
SHOWN_KEYS = 5
"""Made-up keys a flag names (each cut to 40 characters); the rest are counted."""


@dataclass
class Verdict:
    status: str
    message: str = ""


def verdicts(runs: list[NotebookRun]) -> dict[str, Verdict]:
    """Each exercise's verdict for one learner: the last check its notebooks ran, or why none did."""
    found: dict[str, Verdict] = {}
    for run in runs:
        for key in run.keys:
            found[key] = Verdict(ERRORED, run.errored_cells.get(key)
                                 or "the notebook stopped before this exercise: " + "; ".join(run.problems))
        for record in run.records:
            status = RIGHT if record["ok"] else NOT_ANSWERED if record["ok"] is None else WRONG
            found[record["key"]] = Verdict(status, record["message"])
        for key, error in run.errored_cells.items():
            if found.get(key, Verdict(ERRORED)).status == ERRORED:
                found[key] = Verdict(ERRORED, error)
    return found


def inventory_marks(runs: list[NotebookRun]) -> dict[str, dict[str, bool] | None]:
    """A learner's marks on the concept inventory, before (``"00.0"``) and after (``"17.0"``): the last
    answer each notebook of its own number submitted, question by question (:func:`.inventory.score`);
    None for a quiz not answered, or answered in a form that cannot be read."""
    marks: dict[str, dict[str, bool] | None] = {inventory.PRE: None, inventory.POST: None}
    for run in runs:
        for submission in run.submissions:
            key = submission.get("key")
            if key not in marks or "answer" not in submission or not _belongs(key, run.notebook):
                continue
            try:
                answer = revive(submission["answer"])
                if answer is not PLACEHOLDER:
                    marks[key] = inventory.score(inventory.read(answer, key))
            except (PlainError, inventory.InventoryError):
                marks[key] = None
    return marks


def answers(run: NotebookRun) -> int:
    """How many exercises a run answered (right or wrong)."""
    return len({record["key"] for record in run.records if record["ok"] is not None})


def _number(key: str) -> str:
    return key.split(".")[0]


def _only(run: NotebookRun, keep) -> NotebookRun:
    """``run`` with only the checks, submissions and errors of the keys ``keep`` accepts."""
    return dataclasses.replace(
        run, keys=[k for k in run.keys if keep(str(k))],
        records=[r for r in run.records if keep(str(r["key"]))],
        submissions=[r for r in run.submissions if keep(str(r.get("key")))],
        errored_cells={k: v for k, v in run.errored_cells.items() if keep(str(k))})


def _scratch(submission: Submission, run: NotebookRun, handed: set[str]) -> tuple[NotebookRun, str | None]:
    """A notebook not named after a course notebook (``Untitled.ipynb``): only its checks of notebooks the
    learner did not hand in count, never one over a course notebook's answers; and one line saying so."""
    checked = [str(key) for key in [*run.keys, *(r["key"] for r in run.records)] if str(key) in EXERCISES]
    if not checked:
        return run, None
    dropped = list(dict.fromkeys(key for key in checked if _number(key) in handed))
    kept = list(dict.fromkeys(key for key in checked if _number(key) not in handed))
    line = f"{submission.path.name}: not named after a course notebook, so it never overrides one"
    if kept:
        numbers = sorted({_number(key) for key in kept})
        line += f"; graded for {', '.join(kept)} (no notebook {', '.join(numbers)} handed in)"
    if dropped:
        numbers = sorted({_number(key) for key in dropped})
        line += f"; its checks of {', '.join(dropped)} not graded (notebook {', '.join(numbers)} handed in)"
    return _only(run, lambda key: key not in EXERCISES or _number(key) not in handed), line


def _when(seconds: float) -> str:
    return datetime.fromtimestamp(seconds).strftime("%Y-%m-%d %H:%M:%S")


def _why(best: tuple[Submission, NotebookRun], others: list[tuple[Submission, NotebookRun]]) -> str:
    """Why ``best`` counts over ``others``: the first of the marks that told them apart."""
    chosen, run = best
    if all(other.version < chosen.version for other, _ in others):
        return "the platform's newest resubmission"
    if all(answers(other_run) < answers(run) for _, other_run in others):
        return "the most answers"
    if all(other.mtime < chosen.mtime for other, _ in others):
        return f"as many answers, and the newest: {_when(chosen.mtime)} by the zip's or the file's time"
    if all(other.mark < chosen.mark for other, _ in others):
        return f"as many answers, the same time, and the later copy by its ({chosen.mark}) mark"
    return "as many answers, the same time and marks: the last by name"


def copy_order(submission: Submission) -> tuple:
    """The order of a learner's copies of one notebook, newest last: the platform's resubmission, then the
    zip's or the file's time, then the download's ``(N)`` mark, then the name."""
    return submission.version, submission.mtime, submission.mark, submission.path.name


def pick_copies(graded: list[tuple[Submission, NotebookRun]]
                ) -> tuple[dict[str, list[tuple[Submission, NotebookRun]]], dict[str, list[str]]]:
    """Per learner, one run per notebook: of several copies, the platform's newest resubmission, else the
    one with the most answers, then the newest by the zip's (or the file's) time, then the download's
    ``(N)`` mark; a notebook not named after a course notebook counts only for exercises of course
    notebooks the learner did not hand in.  And, per learner, one line for each choice made, saying which
    copy counted and why."""
    groups: dict[tuple[str, str], list[tuple[Submission, NotebookRun]]] = {}
    for submission, run in graded:
        groups.setdefault((submission.learner, submission.notebook), []).append((submission, run))
    chosen: dict[str, list[tuple[Submission, NotebookRun]]] = {}
    choices: dict[str, list[str]] = {}
    for (learner, notebook), copies in sorted(groups.items()):
        best = max(copies, key=lambda pair: (pair[0].version, answers(pair[1]), *copy_order(pair[0])[1:]))
        chosen.setdefault(learner, []).append(best)
        if len(copies) > 1:
            rest = [pair for pair in copies if pair[0] is not best[0]]
            others = ", ".join(f"{other.path.name!r} ({answers(run)} answered)" for other, run in rest)
            choices.setdefault(learner, []).append(
                f"{notebook} graded from {best[0].path.name!r} ({answers(best[1])} answered; "
                f"{_why(best, rest)}), not {others}")
    for learner, pairs in chosen.items():
        handed = {s.notebook[:2] for s, _ in pairs if COURSE_NOTEBOOK.match(s.notebook)}
        for index, (submission, run) in enumerate(pairs):
            if not COURSE_NOTEBOOK.match(submission.notebook):
                kept, line = _scratch(submission, run, handed)
                pairs[index] = (submission, kept)
                if line:
                    choices.setdefault(learner, []).append(line)
    return chosen, choices


def filled(row: dict[str, Verdict], columns: list[str], handed: set[str]) -> dict[str, Verdict]:
    """A learner's verdicts with every column: an exercise no cell checked is "not answered" when its
    notebook was handed in (blank), "not handed in" when it was not."""
    full = dict(row)
    for key in columns:
        if key not in full:
            number = key.split(".")[0]
            full[key] = (Verdict(NOT_ANSWERED, "no cell of the notebook handed in checks this exercise")
                         if number in handed else
                         Verdict(NOT_HANDED_IN, f"notebook {number} was not handed in"))
    return full


def _answer_cells(path, keys: set[str]) -> list[tuple[str, str]]:
    """(exercise, source) of each code cell of a notebook file that checks one of ``keys``."""
    try:
        cells = json.loads(path.read_text(encoding="utf-8")).get("cells", [])
    except (OSError, ValueError, AttributeError):
        return []
    found = []
    for cell in cells if isinstance(cells, list) else []:
        if not isinstance(cell, dict) or cell.get("cell_type") != "code":
            continue
        source = cell.get("source", "")
        source = "".join(source) if isinstance(source, list) else str(source)
        checked = [key for key in exercise_keys(source) if key in keys]
        if checked and len(source.strip()) >= SHARED_CELL:
            found.append((checked[-1], source))
    return found


def identical_answers(chosen: dict[str, list[tuple[Submission, NotebookRun]]]) -> list[str]:
    """The answer cells that two or more learners handed in byte for byte (a hash of each answered cell of
    :data:`SHARED_CELL` characters or more), one line each: for the instructor to look at, never a
    verdict.  A cell every one of three or more learners shares is the notebook's own, not a copy."""
    holders: dict[str, dict] = {}
    answered_by: dict[str, set[str]] = {}
    for learner, pairs in chosen.items():
        for submission, run in pairs:
            keys = {str(r["key"]) for r in run.records if r["ok"] is not None}
            for key in keys:
                answered_by.setdefault(key, set()).add(learner)
            for key, source in _answer_cells(submission.path, keys):
                digest = hashlib.sha256(source.encode("utf-8", "surrogatepass")).hexdigest()
                entry = holders.setdefault(digest, {"key": key, "learners": set(), "size": len(source)})
                entry["learners"].add(learner)
    lines = []
    for entry in sorted(holders.values(), key=lambda e: (_key_order(e["key"]), sorted(e["learners"]))):
        learners, everyone = entry["learners"], answered_by.get(entry["key"], set())
        if len(learners) < 2 or (len(everyone) >= 3 and learners >= everyone):
            continue
        lines.append(f"{entry['key']}: the same answer cell, byte for byte ({entry['size']} characters), "
                     f"from {len(learners)} learners: {', '.join(sorted(learners))}")
    return lines


def handed_in(chosen: dict[str, list[tuple[Submission, NotebookRun]]]) -> dict[str, set[str]]:
    """The numbers of the course notebooks each learner handed in (``{"03", "05"}``), a notebook not named
    after one counting for the exercises it is graded for."""
    handed: dict[str, set[str]] = {}
    for learner, pairs in chosen.items():
        numbers = handed.setdefault(learner, set())
        for submission, run in pairs:
            if COURSE_NOTEBOOK.match(submission.notebook):
                numbers.add(submission.notebook[:2])
            else:
                numbers |= {_number(str(key)) for key in [*run.keys, *(r["key"] for r in run.records)]
                            if str(key) in EXERCISES}
    return handed


def _key_order(key: str) -> tuple:
    return tuple(int(p) if p.isdigit() else 0 for p in key.split("."))


def _belongs(key: str, notebook: str) -> bool:
    """``key`` is an exercise of the course, and of ``notebook`` when the notebook's title numbers it."""
    if key not in EXERCISES:
        return False
    return not re.match(r"\d\d_", notebook) or key.split(".")[0] == notebook[:2]


def course_keys(chosen: dict[str, list[tuple[Submission, NotebookRun]]]
                ) -> tuple[list[str], dict[str, list[NotebookRun]], dict[str, str]]:
    """The gradebook's columns (the course's exercises the class's notebooks check, the concept inventory's
    quizzes aside: a pre-test is no exercise to score), each learner's runs
    without the checks of any other key, and a flag for each learner who checked other keys."""
    columns: set[str] = set()
    runs: dict[str, list[NotebookRun]] = {}
    flags: dict[str, str] = {}
    for learner, pairs in chosen.items():
        foreign: list[str] = []
        for submission, run in pairs:
            keep = {str(key) for key in [*run.keys, *(r["key"] for r in run.records)]
                    if _belongs(str(key), submission.notebook)}
            foreign += [str(key) for key in [*run.keys, *(r["key"] for r in run.records)]
                        if str(key) not in keep]
            columns |= keep - {inventory.PRE, inventory.POST}  # the quizzes have columns of their own
            runs.setdefault(learner, []).append(dataclasses.replace(
                run, keys=[k for k in run.keys if k in keep],
                records=[r for r in run.records if str(r["key"]) in keep],
                errored_cells={k: v for k, v in run.errored_cells.items() if k in keep}))
        foreign = list(dict.fromkeys(foreign))
        if foreign:
            shown = ", ".join(repr(key[:40]) for key in foreign[:SHOWN_KEYS])
            more = f" and {len(foreign) - SHOWN_KEYS} more" if len(foreign) > SHOWN_KEYS else ""
            flags[learner] = f"checks keys that are not its notebooks' exercises (not graded): {shown}{more}"
    return sorted(columns, key=_key_order), runs, flags


def misconception(message: str) -> str:
    """A checker's feedback without the learner's own numbers, so that the same slip counts once."""
    text = message.split("\nHint:")[0].removeprefix("Not yet: ")
    text = re.sub(r"0x[0-9A-Fa-f]+|\b[0-9A-F]{2}(?: [0-9A-F]{2})+\b|\b\d+(?:\.\d+)?\b", "#", text)
    return text.strip()


def feedback(message: str) -> str:
    """A checker's feedback as the learner read it, numbers kept, without the hint."""
    return message.split("\nHint:")[0].removeprefix("Not yet: ").strip()


def slip(message: str) -> tuple[str, bool]:
    """The name of the slip a wrong answer's feedback describes, and whether the catalogue names it: the
    longest catalogue label the feedback holds (a checker's verdict begins with the label, then ``:``),
    else the feedback without the learner's numbers."""
    text = feedback(message).casefold()
    labels = [entry.label for entry in CATALOGUE.values() if entry.label.casefold() + ":" in text]
    if labels:
        return max(labels, key=len), True
    return misconception(message), False


def concerns(run: NotebookRun) -> list[str]:
    """Why an instructor should open a notebook: what went wrong running it (with the cell that did not
    finish), a cell that raised around an exercise, or nothing answered."""
    found = list(run.problems)
    if run.unfinished:
        found.append(f"the cell that did not finish: {run.unfinished}")
    found += [f"{key}: {error}" for key, error in run.errored_cells.items()]
    if not run.problems:
        if not run.keys and not run.records:
            found.append("empty: it checks no exercise")
        elif not answers(run) and not run.errored_cells:
            found.append(f"unanswered: none of its {len(set(run.keys))} exercises answered")
    return found
