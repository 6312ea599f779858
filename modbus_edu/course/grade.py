"""The instructor's gradebook: ``modbus-edu grade SUBMISSIONS... --out DIR``.

A class's notebooks come as one folder per learner (``class/ada/03_rtu_and_crc.ipynb``) or as files named
by learner (``ada_03_rtu_and_crc.ipynb``, or ``ada.ipynb``).  Every notebook runs from the top in a fresh
kernel, in a process of its own, with a time limit per notebook and a memory limit per learner (the
kernel's address space, set with ``resource.setrlimit`` before the kernel starts).

Each exercise's result comes from the library's own checker *as the notebook runs*, never from the outputs
stored in the file, which a learner can edit.  Before running a cell, the grader finds every
``check(KEY, ANSWER)`` call in it (by parsing the cell) and turns it into a call of its own recorder, which
checks ANSWER with :func:`modbus_edu.exercises.evaluate` (the real checker, captured before any learner
code ran), writes the verdict to a log outside the notebook, then calls whatever ``check`` the learner's
cell names, so the notebook behaves as written.  A learner who rebinds ``check`` (``def check``,
``check = ...``, an import under that name) is flagged, and still graded by the real checker.

A notebook that hangs, kills its kernel, floods memory or prints megabytes is reported as such; its
exercises that did not run are "errored", and the other notebooks and learners go on.

One learner is one row however the files were named (:mod:`.submissions`); of several copies of one
notebook, the one with the most answers counts, then the newest; the columns are the course's exercises
that the class's notebooks check, and a key the course does not have is a flag (:mod:`.verdicts`).

The grader writes ``gradebook.csv`` (learner x exercise, then totals and flags), ``learners/NAME.html``
(each exercise's verdict and the checker's feedback) and ``summary.html`` / ``summary.csv`` (each
exercise's success rate, the slips the checkers named, by the catalogue's names, with the learners who
made them, the notebooks to look at, and how the submissions were read), all escaped (:mod:`.reports`).
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .._optional import load_tqdm
from .reports import _write_csv, _write_learner, _write_summary, page_name
from .runner import exercise_keys, instrument, rebinds_check, run_isolated
from .submissions import collect, find_submissions
from .verdicts import (
    ERRORED,
    NOT_ANSWERED,
    RIGHT,
    WRONG,
    Verdict,
    concerns,
    course_keys,
    misconception,
    pick_copies,
    verdicts,
)

__all__ = ["ERRORED", "NOT_ANSWERED", "RIGHT", "WRONG", "Verdict", "exercise_keys", "find_submissions",
           "grade", "instrument", "misconception", "rebinds_check", "verdicts"]


def grade(paths: list[Path], out: Path, *, timeout: float = 300, memory_mb: int = 1024,
          jobs: int | None = None, progress: bool = True) -> dict:
    """Grade a class; write the gradebook, the learners' pages and the summary into ``out``."""
    tqdm = load_tqdm()

    found = collect(paths)
    tasks = found.submissions
    jobs = jobs or max(1, min(len(tasks), os.cpu_count() or 1))
    start = time.monotonic()
    with ThreadPoolExecutor(jobs) as pool, tqdm(total=len(tasks), unit="notebook", disable=not progress,
                                                desc="grading") as bar:
        futures = [(task, pool.submit(run_isolated, task.path, timeout, memory_mb)) for task in tasks]
        graded = []
        for task, future in futures:
            graded.append((task, future.result()))
            bar.update()
    chosen, choices = pick_copies(graded)
    exercises, runs, foreign = course_keys(chosen)
    learners = found.learners
    table = {learner: verdicts(runs.get(learner, [])) for learner in learners}
    flags = {learner: sorted({f"{run.notebook}: {problem}" for run in runs.get(learner, [])
                              for problem in run.problems}) + found.refused.get(learner, [])
             + ([foreign[learner]] if learner in foreign else []) + choices.get(learner, [])
             for learner in learners}
    look_at = {learner: [f"{run.notebook}: {concern}" for run in runs.get(learner, [])
                         for concern in concerns(run)] + found.refused.get(learner, [])
               for learner in learners}
    out.mkdir(parents=True, exist_ok=True)
    _write_csv(out / "gradebook.csv", table, exercises, flags)
    (out / "learners").mkdir(exist_ok=True)
    for learner in learners:
        _write_learner(out / "learners" / page_name(learner), learner, table[learner], exercises,
                       flags[learner])
    notes = found.notes + [f"{learner}: {choice}" for learner, made in choices.items() for choice in made]
    summary = _write_summary(out, table, exercises, flags, look_at, notes)
    summary["seconds"] = time.monotonic() - start
    return summary
