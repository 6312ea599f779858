"""``modbus-edu grade``: grade a class's notebooks into a gradebook."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..course.grade import grade
from ..course.reports import printable


def cmd_grade(args: argparse.Namespace) -> int:
    summary = grade(args.submissions, args.out, timeout=args.timeout, memory_mb=args.memory, jobs=args.jobs,
                    progress=not args.quiet)
    out = printable(args.out)
    print(f"graded {summary['learners']} learner(s) in {summary['seconds']:.1f} s: {out}/gradebook.csv, "
          f"{out}/summary.html, {out}/learners/")
    for row in summary["exercises"]:
        print(f"  {printable(row['exercise']):>6}  {row['success rate']:4.0%} right")
    for learner, flags in summary["flags"].items():
        print(f"  {printable(learner)}: {printable('; '.join(flags))}")
    for note in summary["notes"]:
        print(f"  {printable(note)}")
    return 0


def _options_grade(subs: Any) -> argparse.ArgumentParser:
    """The ``grade`` subcommand's options."""
    p = subs.add_parser("grade", help="grade a class's notebooks into a gradebook",
                        description="Run every learner's notebooks in fresh kernels, each exercise checked "
                                    "by the library's own checker as it runs, and write a CSV gradebook, a "
                                    "feedback page per learner and a class summary. SUBMISSIONS: folders of "
                                    "learners' folders, a learner's folder, or notebooks named by learner "
                                    "(ada_03_rtu_and_crc.ipynb). Example: modbus-edu grade class --out out")
    p.add_argument("submissions", nargs="+", type=Path, metavar="SUBMISSIONS")
    p.add_argument("--out", type=Path, default=Path("grades"), help="folder to write into (default grades)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per notebook (default 300)")
    p.add_argument("--memory", type=int, default=1024, help="MB of memory per kernel (default 1024)")
    p.add_argument("--jobs", type=int, default=None, help="notebooks run at once (default: the CPU count)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p
