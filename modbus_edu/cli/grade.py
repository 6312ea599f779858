"""``modbus-edu grade``: grade a class's notebooks into a gradebook."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..course import grade as grading
from ..course.export import ASSIGNMENT, FORMATS, export
from ..course.reports import printable


def cmd_grade(args: argparse.Namespace) -> int:
    summary = grading.grade(args.submissions, args.out, timeout=args.timeout, memory_mb=args.memory,
                            jobs=args.jobs, progress=not args.quiet, container=args.container)
    out = printable(args.out)
    print(f"graded {summary['learners']} learner(s) in {summary['seconds']:.1f} s: {out}/gradebook.csv, "
          f"{out}/summary.html, {out}/learners/")
    for row in summary["exercises"]:
        print(f"  {printable(row['exercise']):>6}  {row['success rate']:4.0%} right")
    for learner, flags in summary["flags"].items():
        print(f"  {printable(learner)}: {printable('; '.join(flags))}")
    for note in summary["notes"]:
        print(f"  {printable(note)}")
    if args.export:
        path = args.out / f"{args.export}-import.csv"
        left_out = export(path, args.export, summary["scores"], summary["identities"], args.assignment)
        print(f"{args.export} grade import: {printable(path)}")
        if left_out:
            print(f"  not in it (no {args.export} id): {printable(', '.join(left_out))}")
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
                                    "learner's folder, or notebooks named by learner "
                                    "(ada_03_rtu_and_crc.ipynb). Example: modbus-edu grade class --out out")
    p.add_argument("submissions", nargs="+", type=Path, metavar="SUBMISSIONS")
    p.add_argument("--out", type=Path, default=Path("grades"), help="folder to write into (default grades)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per notebook (default 300)")
    p.add_argument("--memory", type=int, default=1024, help="MB of memory per learner (default 1024)")
    p.add_argument("--jobs", type=int, default=None, help="learners graded at once (default: the CPU count)")
    p.add_argument("--export", choices=FORMATS, help="also write OUT/PLATFORM-import.csv for the platform's "
                                                     "grade import (Moodle's grading worksheet, Canvas's "
                                                     "Gradebook import), matched by the ids in the "
                                                     "download's file names")
    p.add_argument("--assignment", default=ASSIGNMENT,
                   help="the Canvas column's name: \"Notebooks (4321)\" as Canvas's export names assignment "
                        f"4321 (default {ASSIGNMENT!r}: a new assignment)")
    p.add_argument("--container", metavar="IMAGE", help="run each kernel in a docker or podman container of "
                                                        "IMAGE (Python, ipykernel and modbus_edu inside)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p
