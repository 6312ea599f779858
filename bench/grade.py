"""Speed of the gradebook: grading a class against executing the same notebooks plainly.

Usage (from the repository root)::

    .venv/bin/python bench/grade.py                       # 2 learners x the 18 notebooks, 1 and 2 jobs
    .venv/bin/python bench/grade.py --learners 4 --notebooks 03,05,10
    .venv/bin/python bench/grade.py --quick               # 2 learners x 3 notebooks, a smoke test

What is measured
----------------
A class of honest learners: each learner hands in every chosen course notebook with each exercise cell
replaced by its worked solution (``notebooks/solutions/``), so every exercise is answered right and
every build exercise is judged (the gradebook must say "right" for each; the bench checks it; the
concept inventory's two quizzes are scored in columns of their own).

* **plain**: the same notebooks executed one after the other by nbclient in an ordinary ``python3``
  kernel (a fresh kernel per notebook, as Run All in JupyterLab), nothing else;
* **graded**: ``modbus-edu grade`` over the class (:func:`modbus_edu.course.grade.grade`), at the
  strongest isolation this machine offers, with 1 job and with 2.

Printed: seconds per learner-notebook for each, the ratio graded / plain (target: within 1.5x with one
job each), the speed-up from 1 to 2 jobs, and the time a class of 30 learners x 18 notebooks would take
at the measured rate on this machine.  Wall-clock time is used here and nowhere in the tests.
"""

from __future__ import annotations

import argparse
import csv
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

from modbus_edu.exercises.inventory import POST, PRE

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
SOLUTIONS = NOTEBOOKS / "solutions"
CHECK = re.compile(r"""check\(\s*["'](\d\d\.\d+)["']""")


def honest(source: Path) -> nbformat.NotebookNode:
    """A course notebook with every exercise cell replaced by the exercise's worked solution."""
    notebook = nbformat.read(source, as_version=4)
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        cell.outputs, cell.execution_count = [], None
        match = CHECK.search(cell.source)
        solution = SOLUTIONS / f"{match.group(1).replace('.', '_')}.py" if match else None
        if solution is not None and solution.exists():
            cell.source = solution.read_text(encoding="utf-8")
    return notebook


def make_class(folder: Path, learners: int, chosen: list[Path]) -> int:
    """One folder per learner holding every chosen notebook; the number of exercises each must get right
    (the concept inventory's two quizzes are scored in columns of their own, not as exercises)."""
    exercises = 0
    for number in range(learners):
        for source in chosen:
            notebook = honest(source)
            if number == 0:
                code = [cell.source for cell in notebook.cells if cell.cell_type == "code"]
                exercises += sum(bool(m) and m.group(1) not in (PRE, POST) for m in map(CHECK.search, code))
            (folder / f"learner{number:02d}").mkdir(parents=True, exist_ok=True)
            nbformat.write(notebook, folder / f"learner{number:02d}" / source.name)
    return exercises


def plain(folder: Path, timeout: float) -> tuple[float, int]:
    """Seconds to execute every notebook of the class with nbclient, one after the other; how many."""
    paths = sorted(folder.glob("*/*.ipynb"))
    start = time.perf_counter()
    for path in paths:
        notebook = nbformat.read(path, as_version=4)
        NotebookClient(notebook, kernel_name="python3", timeout=timeout, allow_errors=True,
                       resources={"metadata": {"path": str(path.parent)}}).execute()
    return time.perf_counter() - start, len(paths)


def graded(folder: Path, out: Path, timeout: float, jobs: int) -> tuple[float, int, int, str]:
    """Seconds to grade the class with ``jobs`` jobs; the right verdicts, the verdicts, the isolation."""
    from modbus_edu.course.grade import grade

    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    summary = grade([folder], out, timeout=timeout, memory_mb=1024, jobs=jobs, progress=False)
    seconds = time.perf_counter() - start
    right = total = 0
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        for row in csv.DictReader(stream):
            for column, value in row.items():
                if column and re.fullmatch(r"'?\d\d\.\d+", column) and value:  # '03.1: text in a spreadsheet
                    total += 1
                    right += value == "right"
    return seconds, right, total, str(summary.get("isolation", ""))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--learners", type=int, default=2)
    parser.add_argument("--notebooks", default="all", help="numbers, comma-separated (03,05), or all")
    parser.add_argument("--timeout", type=float, default=300)
    parser.add_argument("--quick", action="store_true", help="2 learners x notebooks 03, 05, 06")
    args = parser.parse_args(argv)
    if args.quick:
        args.learners, args.notebooks = 2, "03,05,06"
    every = sorted(NOTEBOOKS.glob("[0-9][0-9]_*.ipynb"))
    wanted = None if args.notebooks == "all" else set(args.notebooks.split(","))
    chosen = [path for path in every if wanted is None or path.name[:2] in wanted]
    with tempfile.TemporaryDirectory(prefix="modbus-edu-bench-grade-") as scratch:
        folder = Path(scratch) / "class"
        per_learner = make_class(folder, args.learners, chosen)
        print(f"a class of {args.learners} honest learners x {len(chosen)} notebooks "
              f"({per_learner} exercises each)")
        plain_seconds, count = plain(folder, args.timeout)
        rates = {}
        for jobs in (1, 2):
            seconds, right, total, _ = graded(folder, Path(scratch) / f"grades-{jobs}", args.timeout,
                                                      jobs)
            rates[jobs] = seconds
            print(f"graded, {jobs} job{'s' if jobs > 1 else ''}: {seconds:7.1f} s, "
                  f"{seconds / count:5.2f} s per learner-notebook; {right}/{total} verdicts right"
                  + ("" if right == total == per_learner * args.learners else "  (EXPECTED ALL RIGHT)"))
        print(f"plain nbclient, 1 job: {plain_seconds:7.1f} s, {plain_seconds / count:5.2f} s per "
              f"learner-notebook")
        ratio = rates[1] / plain_seconds
        print(f"graded / plain (1 job each): {ratio:.2f}x  (target: within 1.5x)")
        print(f"1 -> 2 jobs: {rates[1] / rates[2]:.2f}x faster")
        class_hours = rates[2] / count * 30 * 18 / 3600
        print(f"30 learners x 18 notebooks at 2 jobs: about {class_hours:.1f} h on this machine")
    return 0


if __name__ == "__main__":
    sys.exit(main())
