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
import re
from dataclasses import dataclass

from ..exercises import EXERCISES, PLACEHOLDER, inventory
from ..exercises.misconceptions import CATALOGUE
from ..exercises.plain import PlainError, revive
from .runner import NotebookRun
from .submissions import Submission

RIGHT, WRONG, NOT_ANSWERED, ERRORED = "right", "wrong", "not answered", "errored"
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


def pick_copies(graded: list[tuple[Submission, NotebookRun]]
                ) -> tuple[dict[str, list[tuple[Submission, NotebookRun]]], dict[str, list[str]]]:
    """Per learner, one run per notebook: of several copies, the platform's newest resubmission, else the
    one with the most answers, then the newest file; a notebook not named after a course notebook counts
    only for exercises of course notebooks the learner did not hand in.  And, per learner, one line for
    each choice made."""
    groups: dict[tuple[str, str], list[tuple[Submission, NotebookRun]]] = {}
    for submission, run in graded:
        groups.setdefault((submission.learner, submission.notebook), []).append((submission, run))
    chosen: dict[str, list[tuple[Submission, NotebookRun]]] = {}
    choices: dict[str, list[str]] = {}
    for (learner, notebook), copies in sorted(groups.items()):
        best = max(copies, key=lambda pair: (pair[0].version, answers(pair[1]), pair[0].mtime,
                                             pair[0].path.name))
        chosen.setdefault(learner, []).append(best)
        if len(copies) > 1:
            others = ", ".join(f"{other.path.name!r} ({answers(run)} answered)" for other, run in copies
                               if other is not best[0])
            newest = all(other.version < best[0].version for other, _ in copies if other is not best[0])
            why = ("the platform's newest resubmission" if newest else "the most, then the newest")
            choices.setdefault(learner, []).append(
                f"{notebook} graded from {best[0].path.name!r} ({answers(best[1])} answered; {why}), not "
                f"{others}")
    for learner, pairs in chosen.items():
        handed = {s.notebook[:2] for s, _ in pairs if COURSE_NOTEBOOK.match(s.notebook)}
        for index, (submission, run) in enumerate(pairs):
            if not COURSE_NOTEBOOK.match(submission.notebook):
                kept, line = _scratch(submission, run, handed)
                pairs[index] = (submission, kept)
                if line:
                    choices.setdefault(learner, []).append(line)
    return chosen, choices


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
