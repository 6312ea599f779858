"""Running one learner's notebook for the gradebook: a fresh, limited kernel, in a process of its own.

Before a cell runs, every ``check(KEY, ANSWER)`` call in it (found by parsing the cell) becomes a call of
the grader's recorder; a learner who rebinds ``check`` is flagged.  ``python -m modbus_edu.course.runner
NOTEBOOK TIMEOUT MEMORY`` is the worker :func:`run_isolated` starts.
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from .._optional import load_nbclient, load_nbformat, load_transformer_manager

RECORDER = "__modbus_edu_record__"
STARTUP_TIMEOUT = 120
"""Seconds a kernel may take to start (not counted in a notebook's time limit)."""
OUTPUT_LIMIT = 1_000_000
"""Characters of output a notebook may print before the grader reports an output flood (and keeps none)."""

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
        source = load_transformer_manager()().transform_cell(cell_source)
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
    unfinished: str = ""  # the cell that was running when the notebook was stopped or its kernel died


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
    nbformat, nbclient = load_nbformat(), load_nbclient()
    NotebookClient = nbclient.NotebookClient
    CellTimeoutError = nbclient.exceptions.CellTimeoutError
    DeadKernelError = nbclient.exceptions.DeadKernelError

    run = NotebookRun(path.name)
    start = time.monotonic()
    try:
        notebook = nbformat.read(path, as_version=4)
    except Exception as exc:
        run.problems.append(f"cannot be read as a notebook ({type(exc).__name__})")
        return run
    cell_keys: dict[int, list[str]] = {}
    cells = [c for c in notebook.cells if c.cell_type == "code"]
    first_lines = [(c.source.strip().splitlines() or [""])[0][:80] for c in cells]
    started: list[int] = [0]  # the index of the cell running (0: the grader's set-up)
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
                        resources={"metadata": {"path": str(path.parent.resolve())}},
                        on_cell_start=lambda cell, cell_index: started.append(cell_index))
        def stopped_in() -> str:  # the learner's code cell that was running, and its first line
            return f"code cell {started[-1]} ({first_lines[started[-1] - 1]!r})" if started[-1] else ""

        try:
            client.execute()
        except CellTimeoutError:
            run.problems.append(f"did not finish within {timeout:g} s (stopped)")
            run.unfinished = stopped_in()
        except DeadKernelError:
            run.problems.append("killed its kernel (the kernel died)")
            run.unfinished = stopped_in()
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
        done = subprocess.run([sys.executable, "-m", "modbus_edu.course.runner", str(path), str(timeout),
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
        cells = load_nbformat().read(path, as_version=4).cells
    except Exception:
        return []
    return [key for cell in cells if cell.cell_type == "code" for key in exercise_keys(cell.source)]


if __name__ == "__main__":
    _worker(sys.argv[1:])
