"""``modbus-edu grade``: grade a class's notebooks into a gradebook, and export it for a platform."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..course import grade as grading
from ..course.assignment import POINTS, resolve
from ..course.export import FORMATS, LANGUAGES, canvas_line, export
from ..course.reports import printable
from .common import CliError


def _canvas_line(args: argparse.Namespace, points: float) -> None:
    """Say on stderr what Canvas's import will do with a column that names no assignment id."""
    line = canvas_line(args.assignment, points) if args.export == "canvas" else None
    if line:
        print(printable(line), file=sys.stderr)


def _export(args: argparse.Namespace, summary: dict, folder: Path) -> None:
    points = args.points or summary.get("points") or POINTS
    path = folder / f"{args.export}-import.csv"
    left_out = export(path, args.export, summary["scores"], summary["identities"], args.assignment,
                      points=points, language=args.language)
    print(f"{args.export} grade import: {printable(path)} (grades out of {points:g})")
    if left_out:
        print(f"  not in it (no {args.export} id): {printable(', '.join(left_out))}")


def cmd_grade(args: argparse.Namespace) -> int:
    if args.from_ is not None:
        if args.submissions or not args.export:
            raise CliError("--from exports a finished gradebook again: give it with --export and no "
                                  "SUBMISSIONS (modbus-edu grade --from grades --export moodle)")
        summary = grading.load(args.from_)
        print(printable(summary["out of"]))
        _canvas_line(args, args.points or summary.get("points") or POINTS)
        _export(args, summary, args.from_)
        return 0
    if not args.submissions:
        raise CliError("give the class to grade (SUBMISSIONS), or --from a finished gradebook with "
                              "--export")
    assignment = resolve(args.submissions, args.notebooks, args.assigned)
    _canvas_line(args, args.points or (assignment.maximum() if assignment else None) or POINTS)
    summary = grading.grade(args.submissions, args.out, timeout=args.timeout, memory_mb=args.memory,
                            jobs=args.jobs, progress=not args.quiet, container=args.container,
                            assignment=assignment, export=args.export)
    out = printable(args.out)
    print(f"graded {summary['learners']} learner(s) in {summary['seconds']:.1f} s: {out}/gradebook.csv, "
          f"{out}/summary.html, {out}/learners/")
    if summary.get("out of"):
        print(printable(summary["out of"]))
    if summary.get("beyond"):
        print(printable(f"graded but not counted (beyond the assignment): {', '.join(summary['beyond'])}"))
    for row in summary["exercises"]:
        print(f"  {printable(row['exercise']):>6}  {row['success rate']:4.0%} right")
    for learner, flags in summary["flags"].items():
        print(f"  {printable(learner)}: {printable('; '.join(flags))}")
    for note in summary["notes"]:
        print(f"  {printable(note)}")
    for line in summary.get("identical", []):
        print(f"  identical (look at them; not a verdict): {printable(line)}")
    if args.export:
        _export(args, summary, args.out)
    return 0


def _options_grade(subs: Any) -> argparse.ArgumentParser:
    """The ``grade`` subcommand's options."""
    p = subs.add_parser("grade", help="grade a class's notebooks into a gradebook",
                        description="Run every learner's notebooks in fresh kernels, each learner sealed "
                                    "off, every answer judged by the grader's own checkers, and write a CSV "
                                    "gradebook, a "
                                    "feedback page per learner and a class summary. SUBMISSIONS: Moodle's or "
                                    "Canvas's download of an assignment's submissions (the zip or its "
                                    "folder), an nbgrader submitted/ tree, folders of learners' folders, a "
                                    "folder of learners' own zips (one zip, one learner), a "
                                    "learner's folder, or notebooks named by learner "
                                    "(ada_03_rtu_and_crc.ipynb). Example: modbus-edu grade class --out out "
                                    "--notebooks 00,01,03")
    p.add_argument("submissions", nargs="*", type=Path, metavar="SUBMISSIONS")
    p.add_argument("--out", type=Path, default=Path("grades"), help="folder to write into (default grades)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per notebook (default 300)")
    p.add_argument("--memory", type=int, default=1024, help="MB of memory per learner (default 1024)")
    p.add_argument("--jobs", type=int, default=None, help="learners graded at once (default: the CPU count)")
    p.add_argument("--notebooks", metavar="LIST",
                   help="the notebooks that count towards the grade, by number: 00,01,03,05,06,17 (others "
                        "handed in are graded, not counted; default: an assignment.json beside the class, "
                        "else every exercise the class's notebooks check)")
    p.add_argument("--assigned", type=Path, metavar="FILE",
                   help='the assignment file: {"notebooks": ["00", "01"], "points": 20} or {"exercises": '
                        '["03.1", "03.5"]} (default: assignment.json beside the class)')
    p.add_argument("--points", type=float, default=None,
                   help="the grade of a learner with every counted exercise right, for the export (the "
                        "platform's maximum grade or points; default: the assignment file's points, else "
                        "the total of its points per exercise, else 100)")
    p.add_argument("--export", choices=FORMATS, help="also write OUT/PLATFORM-import.csv for the platform's "
                                                     "grade import (Moodle's grading worksheet, Canvas's "
                                                     "Gradebook import), matched by the ids in the "
                                                     "download's file names; checked against the class "
                                                     "before anything is graded")
    p.add_argument("--from", dest="from_", type=Path, metavar="GRADES",
                   help="export a finished gradebook (the folder of an earlier run) without grading again; "
                        "with --export")
    p.add_argument("--assignment", default=None,
                   help="the Canvas assignment to fill: its id (4321, the number in its address) or its "
                        "column as Canvas's export names it (\"Notebooks (4321)\"); without an id, Canvas's "
                        "import makes a new assignment (said in one line)")
    p.add_argument("--language", choices=LANGUAGES, default="en",
                   help="the language of the Moodle page you upload the worksheet from: Moodle matches the "
                        "worksheet's headers in it (default en)")
    p.add_argument("--container", metavar="IMAGE", help="run each kernel in a docker or podman container of "
                                                        "IMAGE (Python, ipykernel and modbus_edu inside)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p
