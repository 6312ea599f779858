"""The instructor's gradebook: ``modbus-edu grade SUBMISSIONS... --out DIR``.

A class's notebooks come as Moodle, Canvas or nbgrader hand them over (their downloads, zipped or not),
as one folder per learner (``class/ada/03_rtu_and_crc.ipynb``) or as files named by learner
(``ada_03_rtu_and_crc.ipynb``, or ``ada.ipynb``): :mod:`.submissions`.  Every notebook runs from the top
in a fresh kernel, with a time limit per notebook.

**The kernel submits, the grader judges.**  Inside the kernel ``check`` judges nothing: it sends the
answer as plain data over the kernel's own message channel, and the grader computes every verdict in its
own process, with its own checkers (:mod:`.runner`).  For a build exercise the grader takes the learner's
function, with what it uses, from the handed-in notebook, runs it in a clean room where the library's own
answer is not available (:mod:`.cleanroom`), on inputs drawn from a seed of its own for each learner, and
compares the outputs itself.  Verdicts never come from the outputs stored in the file, nor from anything
the learner's code could reach: patching the checkers, ``json`` or ``check`` in the kernel changes nothing,
and an always-equal object is read as the plain value it holds.  A learner who rebinds ``check`` is flagged.

**Each learner sealed off, deny by default** (:mod:`.sandbox`, its level said in one line at the start):
each kernel and each clean room in a root that bubblewrap builds from nothing but the places of
:data:`.boundary.BOUNDARY` (Python, the kernel's environment and the library, read-only, and a fresh room),
in user, PID, network, IPC and UTS namespaces of its own, reached by the grader only through Unix sockets
in a folder of the grader's made for that kernel; as root, under a user id of the learner's own where
Python lets it, with the learner's CPU, memory and processes bounded by cgroups; every process ends with
its kernel, and the grader writes no file where a learner writes.  Without bubblewrap or user
namespaces: a process group and per-process limits; with ``--container IMAGE``: a docker or podman
container per kernel.

A notebook that hangs, kills its kernel, floods memory or prints megabytes is reported as such; its
exercises that did not run are "errored", and the other notebooks and learners go on.  So is an answer
the grader's checker fails on: that exercise is errored, with a flag, and the grading goes on.

One learner is one row however the files were named (:mod:`.submissions`); of several copies of one
notebook (copies, resubmissions), only the newest :data:`MAX_COPIES` run (a flag names the others), and
of those the platform's newest resubmission counts, else the one with the most answers, then the newest
by the zip's time, then the download's ``(N)``; a notebook not named after a course notebook
(``Untitled.ipynb``) counts only for notebooks the learner did not hand in; the columns are the course's
exercises that the class's notebooks check and those assigned, and a key the course does not have is a
flag (:mod:`.verdicts`).

**What counts** (:mod:`.assignment`): the grade is out of the exercises the instructor assigned
(``--notebooks``, ``assignment.json``, with points per exercise or per notebook if it gives them: the
score is then the points of the exercises right, of their total), else out of every column, said in one
line; an exercise of a notebook not handed in is "not handed in", one left blank "not answered".
``export`` is checked against
the class as read before anything is graded, and ``gradebook.json`` lets an export run again without
grading (:func:`load`).

**Time.** A notebook's cells get ``--timeout`` seconds in all, then each of its own build exercises
:data:`~.runner.TRACE_TIMEOUT` seconds to be traced, besides the kernel's start; so a learner takes at
most :data:`MAX_COPIES` x ``--timeout`` (plus those) per notebook handed in (its copies counted once),
however many copies, answers or made-up keys the notebooks hold; judging a notebook's answers stops after
:data:`~.runner.JUDGE_SECONDS` seconds.

The grader writes ``gradebook.csv`` (learner x exercise, then totals, the concept inventory's scores
before and after, and flags), ``learners/NAME.html``
(each exercise's verdict and the checker's feedback) and ``summary.html`` / ``summary.csv`` (each
exercise's success rate among the learners who handed its notebook in, the slips the checkers named, by
the catalogue's names, with the learners who made them, the class's normalised gain per question of the
concept inventory, the notebooks to look at, and how the submissions were read), all escaped
(:mod:`.reports`); ``--export moodle|canvas`` adds the platform's grade import (:mod:`.export`).
"""

from __future__ import annotations

import functools
import json
import os
import secrets
import shutil
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .._optional import load_tqdm
from .assignment import Assignment, Score, score, unassigned_line
from .cleanroom import trace_built
from .export import ExportError, check_layout
from .reports import _write_csv, _write_learner, _write_summary, page_names
from .runner import NotebookRun, exercise_keys, instrument, rebinds_check, run_isolated
from .sandbox import MARKER, Sandbox, Seal, detect
from .submissions import Found, Identity, Submission, collect, find_submissions
from .verdicts import (
    ERRORED,
    NOT_ANSWERED,
    NOT_HANDED_IN,
    RIGHT,
    WRONG,
    Verdict,
    _key_order,
    concerns,
    copy_order,
    course_keys,
    filled,
    handed_in,
    identical_answers,
    inventory_marks,
    misconception,
    pick_copies,
    verdicts,
)

MAX_COPIES = 2
"""The most copies of one notebook run for one learner: the newest ones."""

GRADEBOOK_JSON = "gradebook.json"
"""What an export reads from a finished gradebook (``--from``): each learner's score and platform id."""

__all__ = ["ERRORED", "MARKER", "NOT_ANSWERED", "NOT_HANDED_IN", "RIGHT", "WRONG", "Verdict", "exercise_keys",
           "find_submissions", "grade", "instrument", "misconception", "rebinds_check", "verdicts"]


def _hidden(paths: list[Path], out: Path) -> list[Path]:
    """The folders a learner's kernel must not see: the class's and the output (when it exists), wherever
    they lie.  The seal is deny by default (:mod:`.boundary`), so none of them is in a kernel's root; the
    list is kept for callers that name them."""
    folders = {(p if p.is_dir() else p.parent).resolve() for p in paths}
    if out.is_dir():
        folders.add(out.resolve())
    return sorted(folders)


def newest_copies(tasks: list[Submission]) -> tuple[list[Submission], list[str]]:
    """A learner's submissions with at most :data:`MAX_COPIES` of each notebook (the newest: the platform's
    latest resubmission first, then by time; the others not run), and one line per notebook whose copies
    were cut."""
    groups: dict[str, list[Submission]] = {}
    for task in tasks:
        groups.setdefault(task.notebook, []).append(task)
    kept: list[Submission] = []
    lines = []
    for notebook, copies in groups.items():
        copies.sort(key=copy_order, reverse=True)
        kept += copies[:MAX_COPIES]
        if len(copies) > MAX_COPIES:
            left = ", ".join(repr(task.path.name) for task in copies[MAX_COPIES:MAX_COPIES + 3])
            more = f" and {len(copies) - MAX_COPIES - 3} more" if len(copies) > MAX_COPIES + 3 else ""
            lines.append(f"{notebook}: {len(copies)} copies handed in, the newest {MAX_COPIES} graded; not "
                         f"run: {left}{more}")
    chosen = set(kept)
    return [task for task in tasks if task in chosen], lines


def _grade_learner(sandbox: Sandbox, index: int, notebooks: list[Path], scratch: Path, hide: list[Path],
                   timeout: float, memory_mb: int, token: str) -> list[NotebookRun]:
    """Run one learner's notebooks in a seal of its own; every process of the learner ends with it.

    Its build exercises run in clean rooms sealed the same way, on copies of the library made once per
    grading run in ``scratch/rooms`` (which a room reads, and nothing else of the grader's folder)."""
    rooms = scratch / "rooms"
    rooms.mkdir(exist_ok=True)
    seal = Seal.open(sandbox, index, scratch, notebooks, hide, memory_mb, f"{token}-{index}", reads=[rooms])
    seed = secrets.token_hex(8)
    runs = []
    try:
        builds = [functools.partial(trace_built, source=original, seed=seed, rooms=rooms,
                                    seal=seal.run) for original in notebooks]
        runs = run_isolated(seal.notebooks, timeout, memory_mb, seal.kernel_argv(timeout), seal.folder,
                            builds=builds, user=seal.user, worker=seal.worker_argv)
        for original, run in zip(notebooks, runs):
            run.notebook = original.name
    finally:
        if seal.out_of_memory() and runs:
            note = f"ran out of memory (the limit is {memory_mb} MB for the learner)"
            runs[-1].problems.append(note)
        seal.close()
    return runs


def grade(paths: list[Path], out: Path, *, timeout: float = 300, memory_mb: int = 1024,
          jobs: int | None = None, progress: bool = True, container: str | None = None,
          assignment: Assignment | None = None, export: str | None = None) -> dict:
    """Grade a class; write the gradebook, the learners' pages and the summary into ``out``; the summary
    also holds each learner's (right, out of) counted exercises and identity on the platform (for an
    export).  ``assignment`` says what counts (:mod:`.assignment`); ``export`` (a platform) is checked
    against the class's layout before anything is graded."""
    found = collect(paths)
    try:
        if export:
            check_layout(export, found.identities)
        return _grade(found, paths, out, timeout=timeout, memory_mb=memory_mb, jobs=jobs, progress=progress,
                      container=container, assignment=assignment)
    finally:
        found.cleanup()


def _grade(found: Found, paths: list[Path], out: Path, *, timeout: float, memory_mb: int, jobs: int | None,
           progress: bool, container: str | None, assignment: Assignment | None = None) -> dict:
    tqdm = load_tqdm()
    by_learner: dict[str, list[Submission]] = {}
    for task in found.submissions:
        by_learner.setdefault(task.learner, []).append(task)
    capped: dict[str, list[str]] = {}
    for learner, tasks in by_learner.items():
        by_learner[learner], lines = newest_copies(tasks)
        if lines:
            capped[learner] = lines
    sandbox = detect(container)
    print(sandbox.note, file=sys.stderr)
    jobs = jobs or max(1, min(len(by_learner), os.cpu_count() or 1))
    start = time.monotonic()
    token = f"{os.getpid()}-{secrets.token_hex(4)}"
    scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-grade-"))
    hide = _hidden(paths + ([found.scratch] if found.scratch else []), out)
    graded: list[tuple[Submission, NotebookRun]] = []
    try:
        with ThreadPoolExecutor(jobs) as pool, tqdm(total=len(by_learner), unit="learner",
                                                    disable=not progress, desc="grading") as bar:
            futures = [(tasks, pool.submit(_grade_learner, sandbox, index, [task.path for task in tasks],
                                           scratch, hide, timeout, memory_mb, token))
                       for index, tasks in enumerate(by_learner.values())]
            for tasks, future in futures:
                graded.extend(zip(tasks, future.result()))
                bar.update()
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    return _report(found, graded, out, capped, assignment, {"seconds": time.monotonic() - start,
                                                             "isolation": sandbox.note})


def _report(found: Found, graded: list[tuple[Submission, NotebookRun]], out: Path,
            capped: dict[str, list[str]], assignment: Assignment | None, extra: dict) -> dict:
    """Decide the class's verdicts from its runs and write the gradebook, the pages, the summary and
    ``gradebook.json`` (what ``--from`` exports)."""
    chosen, choices = pick_copies(graded)
    checked, runs, foreign = course_keys(chosen)
    counted = list(assignment.exercises) if assignment else checked
    exercises = sorted(set(checked) | set(counted), key=_key_order)
    beyond = [key for key in exercises if key not in counted]
    learners = found.learners
    handed = handed_in(chosen)
    table = {learner: filled(verdicts(runs.get(learner, [])), exercises, handed.get(learner, set()))
             for learner in learners}
    flags = {learner: sorted({f"{run.notebook}: {problem}" for run in runs.get(learner, [])
                              for problem in run.problems}) + found.refused.get(learner, [])
             + ([foreign[learner]] if learner in foreign else []) + choices.get(learner, [])
             + found.flags.get(learner, []) + capped.get(learner, [])
             for learner in learners}
    look_at = {learner: [f"{run.notebook}: {concern}" for run in runs.get(learner, [])
                         for concern in concerns(run)] + found.refused.get(learner, [])
               for learner in learners}
    marks = {learner: inventory_marks(runs.get(learner, [])) for learner in learners}
    out_of = assignment.line() if assignment else unassigned_line(len(counted))
    worth = {key: assignment.weight(key) for key in counted} if assignment and assignment.weights else None
    scores = {learner: score([key for key in counted if table[learner][key].status == RIGHT], counted,
                             assignment) for learner in learners}
    out.mkdir(parents=True, exist_ok=True)
    _write_csv(out / "gradebook.csv", table, exercises, flags, marks, counted, scores)
    (out / "learners").mkdir(exist_ok=True)
    pages = page_names(learners)
    for learner in learners:
        _write_learner(out / "learners" / pages[learner], learner, table[learner], counted, flags[learner],
                       out_of, {key: table[learner][key] for key in beyond}, scores[learner], worth)
    notes = found.notes + [f"{learner}: {choice}" for learner, made in choices.items() for choice in made]
    shared = identical_answers(chosen)
    summary = _write_summary(out, table, exercises, flags, look_at, notes, marks, handed, counted=counted,
                             out_of=out_of, shared=shared, worth=worth)
    summary["scores"] = scores
    summary["identities"] = dict(found.identities)
    summary["out of"] = out_of
    summary["beyond"] = beyond
    summary["identical"] = shared
    summary["points"] = assignment.maximum() if assignment else None
    summary.update(extra)
    _write_json(out / GRADEBOOK_JSON, summary, pages)
    return summary


def _write_json(path: Path, summary: dict, pages: dict[str, str]) -> None:
    """``gradebook.json``: what the grade is out of, the points, and each learner's score, page and id on
    the platform: enough to export again without grading again (``--from``)."""
    identities = summary["identities"]
    learners = {learner: {"right": mark.right, "out of": mark.out_of, "points": mark.earned,
                          "points out of": mark.possible, "page": f"learners/{pages[learner]}",
                          "identity": vars(identities[learner]) if learner in identities else None}
                for learner, mark in summary["scores"].items()}
    data = {"out of": summary["out of"], "points": summary["points"], "learners": learners}
    path.write_text(json.dumps(data, indent=1, ensure_ascii=False), encoding="utf-8")


def load(folder: Path) -> dict:
    """A finished gradebook's summary as :func:`grade` returns it (scores, identities, points, what the
    grade is out of), read from ``folder/gradebook.json``."""
    path = folder / GRADEBOOK_JSON
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        learners = data["learners"]
        return {"scores": {name: Score(int(row["right"]), int(row["out of"]),
                                       float(row.get("points", row["right"])),
                                       float(row.get("points out of", row["out of"])))
                           for name, row in learners.items()},
                "identities": {name: Identity(**row["identity"]) for name, row in learners.items()
                               if row.get("identity")},
                "points": data.get("points"), "out of": str(data.get("out of", ""))}
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise ExportError(f"{path}: not a finished gradebook ({type(exc).__name__}: {exc}); grade the class "
                          "into that folder first (modbus-edu grade SUBMISSIONS --out FOLDER)") from exc
