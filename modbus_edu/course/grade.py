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

The grader writes ``gradebook.csv`` (learner x exercise, then totals and flags), ``learners/NAME.html``
(each exercise's verdict and the checker's feedback) and ``summary.html`` / ``summary.csv`` (each
exercise's success rate and the misconceptions the checkers named most often).
"""

from __future__ import annotations

import ast
import csv
import html
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

RIGHT, WRONG, NOT_ANSWERED, ERRORED = "right", "wrong", "not answered", "errored"
RECORDER = "__modbus_edu_record__"
STARTUP_TIMEOUT = 120
"""Seconds a kernel may take to start (not counted in a notebook's time limit)."""
OUTPUT_LIMIT = 1_000_000
"""Characters of output a notebook may print before the grader reports an output flood (and keeps none)."""

LEARNER_FILE = re.compile(r"^(?P<learner>.+?)[_\-. ](?P<notebook>\d\d_[A-Za-z0-9_]+)$")

SETUP = """\
def __modbus_edu_grader__():
    import json, os
    from modbus_edu.exercises import check as real_check, evaluate
    log = os.environ.pop("MODBUS_EDU_GRADE_LOG")

    def record(key, answer, current):
        result = evaluate(key, answer)
        with open(log, "a", encoding="utf-8") as stream:
            stream.write(json.dumps({"key": str(key), "ok": result.ok, "message": result.message,
                                     "real_check": current is real_check}) + "\\n")
        return current(key, answer)
    return record
__modbus_edu_record__ = __modbus_edu_grader__()
del __modbus_edu_grader__
"""

KERNEL_LAUNCHER = """\
import os, sys
try:
    import resource
    limit = int(os.environ["MODBUS_EDU_GRADE_MEMORY"])
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    cpu = int(os.environ["MODBUS_EDU_GRADE_CPU"])
    resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
except ImportError:
    pass  # no resource module (Windows): no memory limit
from ipykernel import kernelapp
kernelapp.launch_new_instance()
"""


# --- finding the exercises and rewriting the cells ------------------------------------------------------

def _python_source(cell_source: str) -> str | None:
    """A cell as plain Python (IPython magics turned into calls), or None if it does not parse."""
    try:
        from IPython.core.inputtransformer2 import TransformerManager

        source = TransformerManager().transform_cell(cell_source)
    except Exception:
        source = cell_source
    try:
        ast.parse(source)
    except SyntaxError:
        return None
    return source


def _is_check(node: ast.AST) -> bool:
    return isinstance(node, ast.Call) and (
        (isinstance(node.func, ast.Name) and node.func.id == "check")
        or (isinstance(node.func, ast.Attribute) and node.func.attr == "check")) and len(node.args) >= 2


def exercise_keys(source: str) -> list[str]:
    """The exercise keys of the ``check("NN.k", ...)`` calls in a cell's source."""
    python = _python_source(source)
    if python is None:
        return re.findall(r"check\(\s*['\"](\d\d\.\d+)['\"]", source)
    return [node.args[0].value for node in ast.walk(ast.parse(python)) if _is_check(node)
            and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)]


def rebinds_check(source: str) -> bool:
    """True if a cell binds the name ``check`` to anything but the library's own."""
    python = _python_source(source)
    if python is None:
        return False
    for node in ast.walk(ast.parse(python)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.name == "check":
            return True
        if isinstance(node, ast.Name) and node.id == "check" and isinstance(node.ctx, ast.Store):
            return True
        if isinstance(node, (ast.Global, ast.Nonlocal)) and "check" in node.names:
            return True
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                if (alias.asname or alias.name) == "check" and not (
                        alias.name == "check" and (node.module or "").startswith("modbus_edu")):
                    return True
        if isinstance(node, ast.Import) and any((a.asname or a.name) == "check" for a in node.names):
            return True
    return False


class _Recorder(ast.NodeTransformer):
    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        if not _is_check(node):
            return node
        return ast.copy_location(ast.Call(func=ast.Name(RECORDER, ast.Load()),
                                          args=[node.args[0], node.args[1], node.func], keywords=[]), node)


def instrument(source: str) -> str:
    """A cell's source with each ``check(KEY, ANSWER)`` call recorded by the grader."""
    python = _python_source(source)
    if python is None or "check" not in python:
        return source
    tree = ast.fix_missing_locations(_Recorder().visit(ast.parse(python)))
    return ast.unparse(tree)


# --- running one notebook (in a process of its own) ---------------------------------------------------------

@dataclass
class NotebookRun:
    """What running one notebook found: each exercise's verdicts in order, and what went wrong."""

    notebook: str
    keys: list[str] = field(default_factory=list)
    records: list[dict] = field(default_factory=list)
    errored_cells: dict[str, str] = field(default_factory=dict)  # exercise key -> the error
    problems: list[str] = field(default_factory=list)
    seconds: float = 0.0


def _kernel_spec(folder: Path) -> str:
    name = "modbus-edu-grader"
    spec = folder / "kernels" / name
    spec.mkdir(parents=True, exist_ok=True)
    (spec / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-c", KERNEL_LAUNCHER, "-f", "{connection_file}"],
        "display_name": "modbus_edu grader", "language": "python"}))
    return name


def run_notebook(path: Path, timeout: float, memory_mb: int) -> NotebookRun:
    """Run one notebook from the top in a fresh, limited kernel; the verdicts its checks recorded."""
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellTimeoutError, DeadKernelError

    run = NotebookRun(path.name)
    start = time.monotonic()
    try:
        notebook = nbformat.read(path, as_version=4)
    except Exception as exc:
        run.problems.append(f"cannot be read as a notebook ({type(exc).__name__})")
        return run
    cell_keys: dict[int, list[str]] = {}
    cells = [c for c in notebook.cells if c.cell_type == "code"]
    for index, cell in enumerate(cells):
        keys = exercise_keys(cell.source)
        cell_keys[index + 1] = keys
        run.keys.extend(keys)
        if rebinds_check(cell.source):
            run.problems.append("redefines check (graded by the library's own checker all the same)")
        cell.source = instrument(cell.source)
        cell.outputs = []
    notebook.cells = [nbformat.v4.new_code_cell(SETUP), *cells]
    run.problems = list(dict.fromkeys(run.problems))

    with tempfile.TemporaryDirectory(prefix="modbus-edu-grade-") as scratch:
        folder = Path(scratch)
        log = folder / "verdicts.jsonl"
        os.environ["JUPYTER_PATH"] = os.pathsep.join([str(folder), os.environ.get("JUPYTER_PATH", "")])
        os.environ.update(MODBUS_EDU_GRADE_LOG=str(log), MODBUS_EDU_GRADE_MEMORY=str(memory_mb * 1024 * 1024),
                          MODBUS_EDU_GRADE_CPU=str(int(timeout) + 10), MALLOC_ARENA_MAX="2",
                          OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
        printed = 0
        flooded = []

        class Client(NotebookClient):
            def output(self, outs, msg, display_id, cell_index):  # keep nothing, count what is printed
                nonlocal printed
                content = msg.get("content", {})
                if msg["msg_type"] == "error":
                    for key in cell_keys.get(cell_index, []):
                        error = f"{content.get('ename')}: {content.get('evalue')}"
                        run.errored_cells.setdefault(key, error[:300])
                    if content.get("ename") == "MemoryError":
                        run.problems.append(f"ran out of memory (the limit is {memory_mb} MB)")
                text = content.get("text") or json.dumps(content.get("data", ""))
                printed += len(text)
                if printed > OUTPUT_LIMIT and not flooded:
                    flooded.append(True)
                    run.problems.append(f"printed more than {OUTPUT_LIMIT:,} characters (output discarded)")
                return None

        deadline: list[float] = []  # the time limit counts from the first cell, once the kernel has started

        def time_left(cell) -> float:
            if not deadline:
                deadline.append(time.monotonic() + timeout)
            return max(1.0, deadline[0] - time.monotonic())

        client = Client(notebook, kernel_name=_kernel_spec(folder), allow_errors=True,
                        startup_timeout=STARTUP_TIMEOUT, timeout_func=time_left,
                        resources={"metadata": {"path": str(path.parent.resolve())}})
        try:
            client.execute()
        except CellTimeoutError:
            run.problems.append(f"did not finish within {timeout:g} s (stopped)")
        except DeadKernelError:
            run.problems.append("killed its kernel (the kernel died)")
        except Exception as exc:  # a learner's notebook must never stop the grading of the others
            run.problems.append(f"could not be run to the end ({type(exc).__name__}: {str(exc)[:200]})")
        if log.exists():
            for line in log.read_text(encoding="utf-8").splitlines():
                try:
                    run.records.append(json.loads(line))
                except json.JSONDecodeError:
                    continue
    for record in run.records:
        if record.get("real_check") is False:
            note = "redefines check (graded by the library's own checker all the same)"
            if note not in run.problems:
                run.problems.append(note)
    run.seconds = time.monotonic() - start
    return run


def _worker(argv: list[str]) -> None:
    path, timeout, memory = Path(argv[0]), float(argv[1]), int(argv[2])
    run = run_notebook(path, timeout, memory)
    sys.stdout.write(json.dumps(run.__dict__))


def run_isolated(path: Path, timeout: float, memory_mb: int) -> NotebookRun:
    """:func:`run_notebook` in a separate process, with a backstop deadline of its own."""
    backstop = 2 * timeout + 2 * STARTUP_TIMEOUT
    try:
        done = subprocess.run([sys.executable, "-m", "modbus_edu.course.grade", str(path), str(timeout),
                               str(memory_mb)], capture_output=True, text=True, timeout=backstop)
        return NotebookRun(**json.loads(done.stdout))
    except subprocess.TimeoutExpired:
        problem = f"did not finish within {backstop:g} s (its grader was stopped)"
    except (json.JSONDecodeError, TypeError):
        problem = "its grader failed: " + (done.stderr.strip()[-300:] or "?")
    return NotebookRun(path.name, keys=_keys_of(path), problems=[problem])


def _keys_of(path: Path) -> list[str]:
    """The exercise keys a notebook checks, read from the file (for a notebook whose grader failed)."""
    try:
        import nbformat

        cells = nbformat.read(path, as_version=4).cells
    except Exception:
        return []
    return [key for cell in cells if cell.cell_type == "code" for key in exercise_keys(cell.source)]


# --- a class: learners, exercises, the gradebook ----------------------------------------------------------

def find_submissions(paths: list[Path]) -> dict[str, list[Path]]:
    """Learner name -> notebooks, from folders of learners, a learner's folder or files named by learner."""
    learners: dict[str, list[Path]] = {}

    def add_file(file: Path, learner: str | None = None) -> None:
        if learner is None:
            match = LEARNER_FILE.match(file.stem)
            learner = match.group("learner") if match else file.stem
        learners.setdefault(learner, []).append(file)

    for path in paths:
        if path.is_file():
            add_file(path)
        elif path.is_dir():
            notebooks = sorted(p for p in path.glob("*.ipynb") if not p.name.startswith("."))
            folders = sorted(p for p in path.iterdir() if p.is_dir() and any(p.glob("*.ipynb")))
            if folders:
                for folder in folders:
                    for file in sorted(folder.glob("*.ipynb")):
                        add_file(file, folder.name)
                for file in notebooks:
                    add_file(file)
            elif any(LEARNER_FILE.match(p.stem) for p in notebooks):
                for file in notebooks:
                    add_file(file)
            else:
                for file in notebooks:
                    add_file(file, path.name)
        else:
            raise FileNotFoundError(f"{path} is neither a notebook nor a folder of notebooks")
    return {name: sorted(files) for name, files in sorted(learners.items())}


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


def misconception(message: str) -> str:
    """A checker's feedback without the learner's own numbers, so that the same slip counts once."""
    text = message.split("\nHint:")[0].removeprefix("Not yet: ")
    text = re.sub(r"0x[0-9A-Fa-f]+|\b[0-9A-F]{2}(?: [0-9A-F]{2})+\b|\b\d+(?:\.\d+)?\b", "#", text)
    return text.strip()


def grade(paths: list[Path], out: Path, *, timeout: float = 300, memory_mb: int = 1024,
          jobs: int | None = None, progress: bool = True) -> dict:
    """Grade a class; write the gradebook, the learners' pages and the summary into ``out``."""
    from tqdm.auto import tqdm

    learners = find_submissions(paths)
    tasks = [(learner, notebook) for learner, files in learners.items() for notebook in files]
    jobs = jobs or max(1, min(len(tasks), os.cpu_count() or 1))
    runs: dict[str, list[NotebookRun]] = {learner: [] for learner in learners}
    start = time.monotonic()
    with ThreadPoolExecutor(jobs) as pool, tqdm(total=len(tasks), unit="notebook", disable=not progress,
                                                desc="grading") as bar:
        futures = [(learner, pool.submit(run_isolated, notebook, timeout, memory_mb))
                   for learner, notebook in tasks]
        for learner, future in futures:
            runs[learner].append(future.result())
            bar.update()
    table = {learner: verdicts(found) for learner, found in runs.items()}
    exercises = sorted({key for row in table.values() for key in row},
                       key=lambda k: tuple(int(p) if p.isdigit() else 0 for p in k.split(".")))
    flags = {learner: sorted({f"{run.notebook}: {problem}" for run in found for problem in run.problems})
             for learner, found in runs.items()}
    out.mkdir(parents=True, exist_ok=True)
    _write_csv(out / "gradebook.csv", table, exercises, flags)
    (out / "learners").mkdir(exist_ok=True)
    for learner in learners:
        page = out / "learners" / f"{learner}.html"
        _write_learner(page, learner, table[learner], exercises, flags[learner])
    summary = _write_summary(out, table, exercises, flags)
    summary["seconds"] = time.monotonic() - start
    return summary


def _write_csv(path: Path, table: dict, exercises: list[str], flags: dict) -> None:
    with path.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(["learner", *exercises, RIGHT, WRONG, NOT_ANSWERED, ERRORED, "score", "flags"])
        for learner, row in table.items():
            statuses = [row.get(key, Verdict(NOT_ANSWERED)).status for key in exercises]
            counts = Counter(statuses)
            writer.writerow([learner, *statuses, counts[RIGHT], counts[WRONG], counts[NOT_ANSWERED],
                             counts[ERRORED], f"{counts[RIGHT]}/{len(exercises)}",
                             " | ".join(flags[learner])])


PAGE = """<!doctype html><html><head><meta charset="utf-8"><title>{title}</title><style>
body {{ font-family: sans-serif; max-width: 60em; margin: 2em auto; }} td, th {{ padding: .3em .6em;
vertical-align: top; border-bottom: 1px solid #ddd; text-align: left; }} .right {{ color: #1a7f37; }}
.wrong {{ color: #b35900; }} .errored {{ color: #c62828; }} pre {{ white-space: pre-wrap; margin: 0; }}
</style></head><body><h1>{title}</h1>{body}</body></html>
"""


def _write_learner(path: Path, learner: str, row: dict, exercises: list[str], flags: list[str]) -> None:
    right = sum(1 for key in exercises if row.get(key, Verdict(NOT_ANSWERED)).status == RIGHT)
    parts = [f"<p>{right} of {len(exercises)} exercises right.</p>"]
    if flags:
        parts.append("<h2>About the notebooks</h2><ul>" + "".join(f"<li>{html.escape(f)}</li>" for f in flags)
                     + "</ul>")
    parts.append("<table><tr><th>exercise</th><th>result</th><th>the checker's feedback</th></tr>")
    for key in exercises:
        verdict = row.get(key, Verdict(NOT_ANSWERED, "no cell of the notebooks checks this exercise"))
        parts.append(f"<tr><td>{key}</td><td class='{verdict.status.split()[0]}'>{verdict.status}</td>"
                     f"<td><pre>{html.escape(verdict.message)}</pre></td></tr>")
    parts.append("</table>")
    path.write_text(PAGE.format(title=f"Feedback for {html.escape(learner)}", body="".join(parts)),
                    encoding="utf-8")


def _write_summary(out: Path, table: dict, exercises: list[str], flags: dict) -> dict:
    rows = []
    for key in exercises:
        statuses = [row.get(key, Verdict(NOT_ANSWERED)) for row in table.values()]
        counts = Counter(v.status for v in statuses)
        slips = Counter(misconception(v.message) for v in statuses if v.status == WRONG)
        rows.append({"exercise": key, "learners": len(statuses), **{s: counts[s] for s in
                     (RIGHT, WRONG, NOT_ANSWERED, ERRORED)},
                     "success rate": counts[RIGHT] / len(statuses) if statuses else 0.0,
                     "misconceptions": slips.most_common(3)})
    with (out / "summary.csv").open("w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerow(["exercise", "learners", RIGHT, WRONG, NOT_ANSWERED, ERRORED, "success rate",
                         "most frequent misconception", "learners with it"])
        for row in rows:
            slip, count = row["misconceptions"][0] if row["misconceptions"] else ("", 0)
            writer.writerow([row["exercise"], row["learners"], row[RIGHT], row[WRONG], row[NOT_ANSWERED],
                             row[ERRORED], f"{row['success rate']:.0%}", slip, count])
    parts = [f"<p>{len(table)} learners, {len(exercises)} exercises.</p><table><tr><th>exercise</th>"
             "<th>success rate</th><th>right / wrong / not answered / errored</th>"
             "<th>misconceptions the checkers named (learners)</th></tr>"]
    for row in sorted(rows, key=lambda r: r["success rate"]):
        slips = "".join(f"<li>{html.escape(text)} ({count})</li>" for text, count in row["misconceptions"])
        parts.append(f"<tr><td>{row['exercise']}</td><td>{row['success rate']:.0%}</td><td>{row[RIGHT]} / "
                     f"{row[WRONG]} / {row[NOT_ANSWERED]} / {row[ERRORED]}</td>"
                     f"<td><ul>{slips}</ul></td></tr>")
    parts.append("</table>")
    flagged = {learner: found for learner, found in flags.items() if found}
    if flagged:
        parts.append("<h2>Notebooks to look at</h2><ul>" + "".join(
            f"<li>{html.escape(learner)}: {html.escape('; '.join(found))}</li>"
            for learner, found in flagged.items()) + "</ul>")
    page = PAGE.format(title="Class summary", body="".join(parts))
    (out / "summary.html").write_text(page, encoding="utf-8")
    return {"learners": len(table), "exercises": rows, "flags": flagged}


if __name__ == "__main__":
    _worker(sys.argv[1:])
