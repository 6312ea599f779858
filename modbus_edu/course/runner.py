"""Running one learner's notebook for the gradebook: a fresh kernel, sealed off, that only submits.

The grader never trusts the kernel to judge.  Inside the kernel ``check`` only *submits*: the answer
leaves as plain data, a display output of the MIME type :data:`~modbus_edu.exercises.submit.MIME` on the
kernel's own message channel (:mod:`modbus_edu.exercises.submit`).  The worker that drives the kernel
(``python -m modbus_edu.course.runner``, started by :func:`run_isolated`, memory- and time-limited itself)
collects those messages and hands them back through a file in the grader's own folder (never through its
stdout, which a learner's output could reach).  A build exercise's function does not leave the kernel:
once the notebook has run, the grader takes the function from the handed-in notebook file and runs it in
a clean room (:mod:`.cleanroom`), on inputs drawn from a seed the kernel never sees, once for each of the
notebook's own build exercises the learner checked (:func:`own_build_keys`).  :func:`judged` computes
every verdict in the grader's process, with the grader's own checkers.

Before a cell runs, every call of the library's own ``check`` in it (``check(KEY, ANSWER)`` or
``exercises.check(...)``, found by parsing the cell; any other ``x.check(...)`` is left alone) becomes a
call of :func:`~modbus_edu.exercises.submit.record`, so an answer is submitted even when the learner has
rebound ``check``; a learner who rebinds it is flagged.  The work is bounded: a notebook of more than
:data:`NOTEBOOK_LIMIT` bytes, a cell of more than :data:`CELL_LIMIT` characters, more than
:data:`MAX_CHECKS` checks in the source or :data:`MAX_SUBMISSIONS` submissions at run time are each
refused with a flag that says so.
"""

from __future__ import annotations

import ast
import functools
import itertools
import json
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

try:
    import resource
except ImportError:  # Windows
    resource = None

from .._optional import load_nbclient, load_nbformat, load_transformer_manager
from ..exercises import EXERCISES, judge, verdict
from ..exercises.plain import MAX_WIRE, PlainError, from_json
from ..exercises.submit import MIME
from .archives import NOTEBOOK_LIMIT
from .sandbox import kernel_spawn
from .submissions import TITLE, without_marks

RECORDER = "__modbus_edu_record__"
STARTUP_TIMEOUT = 120
"""Seconds a kernel may take to start (not counted in a notebook's time limit)."""
OUTPUT_LIMIT = 1_000_000
"""Characters of output a notebook may print before the grader reports an output flood (and keeps none)."""
CELL_LIMIT = 50_000
"""The longest code cell the grader runs, in characters."""
MAX_CHECKS = 300
"""The most ``check`` calls a notebook's source may hold."""
MAX_SUBMISSIONS = 1_000
"""The most submissions one notebook's run may send (a check in a loop counts each time)."""
WORKER_MEMORY = 2048
"""MB of address space the worker that drives a kernel may use."""
JUDGE_SECONDS = 30
"""Seconds the grader spends judging one notebook's submissions; the ones left are errored, with a flag."""

_KERNELS = itertools.count(1)
"""Numbers the kernels one worker starts (each its own connection file)."""

SETUP = f"from modbus_edu.exercises.submit import record as {RECORDER}\n"


# --- finding the exercises and rewriting the cells ------------------------------------------------------

def _python_source(cell_source: str) -> str | None:
    """A cell as plain Python (IPython magics turned into calls), or None if it does not parse."""
    try:
        TransformerManager = load_transformer_manager()
        source = TransformerManager().transform_cell(cell_source)
    except Exception:
        source = cell_source
    try:
        ast.parse(source)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return None
    return source


def _dotted(node: ast.AST) -> str:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return f"{_dotted(node.value)}.{node.attr}"
    return "?"


def _is_check(node: ast.AST) -> bool:
    """A call of the library's own check: ``check(K, A)`` or ``<...>exercises.check(K, A)``."""
    if not isinstance(node, ast.Call) or len(node.args) < 2:
        return False
    name = _dotted(node.func)
    return name == "check" or name == "exercises.check" or name.endswith(".exercises.check")


def exercise_keys(source: str) -> list[str]:
    """The exercise keys of the ``check("NN.k", ...)`` calls in a cell's source."""
    python = _python_source(source)
    if python is None:
        return re.findall(r"(?<![\w.])check\(\s*['\"](\d\d\.\d+)['\"]", source)
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
    """A cell's source with each call of the library's ``check`` submitted by the grader's recorder."""
    python = _python_source(source)
    if python is None or "check" not in python:
        return source
    tree = ast.fix_missing_locations(_Recorder().visit(ast.parse(python)))
    return ast.unparse(tree)


# --- running one notebook (in the worker) ---------------------------------------------------------------

@dataclass
class NotebookRun:
    """What running one notebook found: its submissions, each exercise's verdicts in order
    (filled in by :func:`judged`, in the grader), and what went wrong."""

    notebook: str
    keys: list[str] = field(default_factory=list)
    submissions: list[dict] = field(default_factory=list)
    records: list[dict] = field(default_factory=list)
    errored_cells: dict[str, str] = field(default_factory=dict)  # exercise key -> the error
    problems: list[str] = field(default_factory=list)
    seconds: float = 0.0
    unfinished: str = ""  # the cell that was running when the notebook was stopped or its kernel died


Builds = Callable[[NotebookRun], dict]
"""What gives a run's build-exercise traces once its kernel is done (key -> (trace, cases))."""


def _read(path: Path, run: NotebookRun, cell_keys: dict[int, list[str]]):
    """The notebook, its code cells instrumented after a setup cell, or None (with a problem) when it
    cannot or may not run; ``cell_keys`` gets each cell's exercise keys (by index, the setup cell 0)."""
    nbformat = load_nbformat()
    size = path.stat().st_size
    if size > NOTEBOOK_LIMIT:
        run.problems.append(f"is {size / 1e6:.1f} MB; the grader reads notebooks up to "
                            f"{NOTEBOOK_LIMIT / 1e6:g} MB (not run)")
        return None
    try:
        notebook = nbformat.reads(path.read_text(encoding="utf-8"), as_version=4)
    except Exception as exc:
        run.problems.append(f"cannot be read as a notebook ({type(exc).__name__})")
        return None
    cells = [cell for cell in notebook.cells if cell.cell_type == "code"]
    calls = sum(len(re.findall(r"check\s*\(", cell.source)) for cell in cells)
    if calls > MAX_CHECKS:
        run.problems.append(f"calls check {calls:,} times; the grader takes notebooks with up to "
                            f"{MAX_CHECKS} checks (not run)")
        return None
    for number, cell in enumerate(cells, start=1):
        cell.outputs = []
        if len(cell.source) > CELL_LIMIT:
            run.problems.append(f"code cell {number} has {len(cell.source):,} characters; the grader runs "
                                f"cells up to {CELL_LIMIT:,} (that cell was not run)")
            cell.source = "raise RuntimeError('this cell is too long for the grader')"
            continue
        cell_keys[number] = exercise_keys(cell.source)
        run.keys.extend(cell_keys[number])
        if rebinds_check(cell.source):
            run.problems.append("redefines check (graded by the library's own checker all the same)")
        cell.source = instrument(cell.source)
    notebook.cells = [nbformat.v4.new_code_cell(SETUP), *cells]
    return notebook


SOCKET_PATH = 100
"""The longest path a Unix socket may have here (the systems' own limits are 104 and 108 bytes)."""


class KernelSocketError(OSError):
    """A kernel's socket is not there in time, or is not a socket of the kernel's own."""


class KernelSockets:
    """One kernel's Unix sockets, reached only by descriptor.

    The kernel must be able to write the folder its sockets lie in (it binds them there), so the grader
    does no file operation by path in it: it holds the folder open from the moment it made it, opens
    each socket relative to that descriptor with ``O_PATH | O_NOFOLLOW`` once the kernel has bound it,
    checks that it is a socket of the grader's own user (the kernel's, outside its sandbox), and has
    ZeroMQ connect to ``ipc:///proc/self/fd/N``: that names the socket opened, whatever the kernel later
    puts at its path, so a link swapped in is never followed, not even when a connection is made again
    (the heartbeat's, after a kernel stopped answering).  :meth:`check` notes a socket replaced by
    something else; :meth:`close` removes the sockets by the folder's descriptor."""

    def __init__(self, folder: Path, manager) -> None:
        self.manager = manager
        self.folder = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
        self.opened: dict[str, int] = {}
        self.replaced: dict[str, str] = {}  # socket name -> what stands in for it

    def url(self, connection, channel: str) -> str:
        """The ZeroMQ address of ``connection``'s socket for ``channel`` (a descriptor of this process),
        waiting for the kernel to bind it (at most :data:`STARTUP_TIMEOUT` s, while the kernel lives)."""
        name = f"{os.path.basename(connection.ip)}-{getattr(connection, f'{channel}_port')}"
        if name not in self.opened:
            self.opened[name] = self._open(name)
        return f"ipc:///proc/self/fd/{self.opened[name]}"

    def _open(self, name: str) -> int:
        deadline = time.monotonic() + STARTUP_TIMEOUT
        while True:
            try:
                handle = os.open(name, os.O_PATH | os.O_NOFOLLOW | os.O_CLOEXEC, dir_fd=self.folder)
                break
            except FileNotFoundError:
                process = getattr(getattr(self.manager, "provisioner", None), "process", None)
                if time.monotonic() > deadline or (process is not None and process.poll() is not None):
                    raise KernelSocketError(f"the kernel did not make its socket {name}") from None
                time.sleep(0.01)
        found = os.fstat(handle)
        if stat.S_ISSOCK(found.st_mode) and found.st_uid == os.geteuid():
            return handle
        os.close(handle)
        raise KernelSocketError(f"the kernel's {name} is not a socket of its own (not followed)")

    def check(self) -> None:
        """Note each socket that something else now stands in for (a link, a file, another socket)."""
        for name, handle in self.opened.items():
            try:
                now = os.stat(name, dir_fd=self.folder, follow_symlinks=False)
            except OSError:
                continue  # gone (a kernel that ends removes its sockets)
            held = os.fstat(handle)
            if (now.st_dev, now.st_ino) != (held.st_dev, held.st_ino):
                self.replaced.setdefault(name, "a link" if stat.S_ISLNK(now.st_mode) else
                                         "another socket" if stat.S_ISSOCK(now.st_mode) else "a file")

    def problems(self) -> list[str]:
        """What the kernel did to its sockets, said for the learner's row."""
        return [f"replaced its kernel's socket {name} with {what} (the grader reaches a kernel's sockets "
                "only through what it opened when the kernel started: nothing was followed)"
                for name, what in self.replaced.items()]

    def close(self) -> None:
        """Remove the kernel's sockets (by the folder's descriptor) and close every descriptor."""
        if self.folder < 0:
            return
        self.check()
        for name, handle in self.opened.items():
            os.close(handle)
            try:
                os.unlink(name, dir_fd=self.folder)
            except OSError:
                pass
        self.opened.clear()
        os.close(self.folder)
        self.folder = -1


def connect_in(manager, runtime: Path, number: int = 1):
    """``manager`` set to reach its kernel through ``runtime``, the learner's ``run`` folder (the grader's,
    or its worker's): the kernel's five ZeroMQ sockets (where Unix sockets exist) as ``ipc://`` sockets
    ``runtime/kP-N/k-1`` ... (P: the worker's process id, N: ``number``, its Nth kernel), in a folder
    made fresh for this kernel, which its sandbox sees as ``/tmp/run``; the connection file
    ``runtime/kP-N.json`` lies beside it, where no kernel reaches.  A sealed kernel has no network but
    its own loopback and sees no other folder of the grader's, so only the grader can reach it.  The
    manager and its clients reach those sockets by descriptor only (:class:`KernelSockets`, kept as
    ``manager.kernel_sockets``)."""
    manager.connection_file = str(runtime / f"k{os.getpid()}-{number}.json")
    if os.name == "posix":
        folder = runtime / f"k{os.getpid()}-{number}"
        sockets = str(folder / "k")
        if len(sockets) + 6 > SOCKET_PATH:
            raise OSError(f"the grader's scratch folder {runtime.parent.parent} is too deep for the kernel's "
                          f"Unix sockets ({len(sockets) + 6} bytes, at most {SOCKET_PATH}): set TMPDIR to "
                          "a shorter folder")
        folder.mkdir(mode=0o700)
        manager.transport = "ipc"
        manager.ip = sockets
        if sys.platform.startswith("linux"):  # /proc/self/fd names what a descriptor holds
            held = manager.kernel_sockets = KernelSockets(folder, manager)
            manager._make_url = functools.partial(held.url, manager)
            manager.cleanup_ipc_files = held.close
            make_client = getattr(manager, "client", None)

            def client(**kwargs):
                made = make_client(**kwargs)
                made._make_url = functools.partial(held.url, made)
                return made
            if make_client is not None:
                manager.client = client
    return manager


async def _launch(launch_kernel, kernel_cmd: list[str], **kw) -> None:
    """jupyter_client's launch of a kernel (``launch_kernel``: its manager's, made for subclasses to
    change), a sealed kernel's bubblewrap started straight from this worker (:func:`.sandbox.kernel_spawn`:
    no launcher's Python between), its stdout and stderr to /dev/null."""
    spawn = kernel_spawn(kernel_cmd)
    if spawn is None:
        return await launch_kernel(kernel_cmd, **kw)
    kw.update(spawn.popen(), independent=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        return await launch_kernel(spawn.argv, **kw)
    finally:
        spawn.close()


def run_notebook(path: Path, timeout: float, argv: list[str], memory_mb: int) -> NotebookRun:
    """Run one notebook from the top in a fresh kernel started by ``argv``; its submissions.

    The kernel's connection file and sockets go beside the notebook's private copy (``../run``), where
    the kernel, sealed in that private folder, can reach them (:func:`connect_in`)."""
    nbclient = load_nbclient()
    NotebookClient, run_sync = nbclient.NotebookClient, nbclient.util.run_sync
    CellTimeoutError = nbclient.exceptions.CellTimeoutError
    DeadKernelError = nbclient.exceptions.DeadKernelError

    run = NotebookRun(path.name)
    start = time.monotonic()
    runtime = path.parent.parent / "run"
    cell_keys: dict[int, list[str]] = {}
    notebook = _read(path, run, cell_keys)
    if notebook is None:
        return run
    first_lines = [(cell.source.strip().splitlines() or [""])[0][:80] for cell in notebook.cells]
    started = [0]  # the index of the cell running (0: the grader's set-up)

    def stopped_in() -> str:  # the learner's code cell that was running, and its first line
        index = started[0]
        return f"code cell {index} ({first_lines[index]!r})" if index > 0 else ""
    counted = {"printed": 0, "submitted": 0}
    kernels: list[KernelSockets] = []  # each kernel's sockets, held by descriptor

    with tempfile.TemporaryDirectory(prefix="modbus-edu-kernelspec-") as spec_folder:
        spec = Path(spec_folder) / "kernels" / "modbus-edu-grader"
        spec.mkdir(parents=True)
        (spec / "kernel.json").write_text(json.dumps({"argv": argv, "display_name": "modbus_edu grader",
                                                      "language": "python"}))
        os.environ["JUPYTER_PATH"] = spec_folder

        def take(data: dict, cell_index: int) -> None:
            text = data.get(MIME)
            if not isinstance(text, str) or len(text) > MAX_WIRE:
                return
            try:
                payload = from_json(text)
            except PlainError:
                return
            if not isinstance(payload, dict) or not isinstance(payload.get("key"), str):
                return
            counted["submitted"] += 1
            if counted["submitted"] > MAX_SUBMISSIONS:
                if counted["submitted"] == MAX_SUBMISSIONS + 1:
                    run.problems.append(f"submitted more than {MAX_SUBMISSIONS:,} answers (the rest ignored)")
                return
            run.submissions.append({key: payload[key] for key in ("key", "answer", "build", "real_check")
                                    if key in payload})

        class Client(NotebookClient):
            def create_kernel_manager(self):
                manager = connect_in(super().create_kernel_manager(), runtime, next(_KERNELS))
                manager._async_launch_kernel = functools.partial(_launch, manager._async_launch_kernel)
                if hasattr(manager, "kernel_sockets"):
                    kernels.append(manager.kernel_sockets)
                return manager

            def output(self, outs, msg, display_id, cell_index):  # keep nothing, count what is printed
                content = msg.get("content", {})
                if msg["msg_type"] in ("display_data", "execute_result") and isinstance(content.get("data"),
                                                                                        dict):
                    take(content["data"], cell_index)
                if msg["msg_type"] == "error":
                    for key in cell_keys.get(cell_index, []):
                        error = f"{content.get('ename')}: {content.get('evalue')}"
                        run.errored_cells.setdefault(key, error[:300])
                    if content.get("ename") == "MemoryError":
                        run.problems.append(f"ran out of memory (the limit is {memory_mb} MB)")
                text = content.get("text") if isinstance(content.get("text"), str) else json.dumps(
                    content.get("data", ""))
                counted["printed"] += len(text)
                if counted["printed"] > OUTPUT_LIMIT and "flood" not in counted:
                    counted["flood"] = 1
                    run.problems.append(f"printed more than {OUTPUT_LIMIT:,} characters (output discarded)")
                return None

        deadline: list[float] = []  # the time limit counts from the first cell, once the kernel has started

        def time_left(cell) -> float:
            if not deadline:
                deadline.append(time.monotonic() + timeout)
            return max(1.0, deadline[0] - time.monotonic())

        client = Client(notebook, kernel_name="modbus-edu-grader", allow_errors=True,
                        startup_timeout=STARTUP_TIMEOUT, timeout_func=time_left,
                        resources={"metadata": {"path": str(path.parent)}})

        async def execute() -> None:
            async with client.async_setup_kernel():
                await client.async_wait_for_reply(client.kc.kernel_info())
                for index, cell in enumerate(list(client.nb.cells)):
                    started[0] = index
                    await client.async_execute_cell(cell, index, execution_count=index + 1)
                    for held in kernels:
                        held.check()

        try:
            run_sync(execute)()
        except CellTimeoutError:
            run.problems.append(f"did not finish within {timeout:g} s (stopped)")
            run.unfinished = stopped_in()
        except DeadKernelError:
            run.problems.append("killed its kernel (the kernel died)")
            run.unfinished = stopped_in()
        except Exception as exc:  # a learner's notebook must never stop the grading of the others
            run.problems.append(f"could not be run to the end ({type(exc).__name__}: {str(exc)[:200]})")
    for submission in run.submissions:
        if submission.get("real_check") is False:
            note = "redefines check (graded by the library's own checker all the same)"
            if note not in run.problems:
                run.problems.append(note)
    for held in kernels:
        held.close()
        run.problems.extend(held.problems())
    run.problems = list(dict.fromkeys(run.problems))
    run.seconds = time.monotonic() - start
    return run


def own_build_keys(notebook_title: str, keys: Iterable) -> list[str]:
    """The build exercises among ``keys`` whose function the grader judges in this notebook, each once:
    the course's build exercises only, and of those the notebook's own (its number, ``03`` in
    ``03_rtu_and_crc``) when its title or file name has one; a key a learner makes up is never judged."""
    match = TITLE.search(without_marks(str(notebook_title)))
    number = match.group()[:2] if match else None
    return [key for key in dict.fromkeys(keys) if isinstance(key, str) and key in EXERCISES
            and EXERCISES[key].kind == "build" and (number is None or key.split(".")[0] == number)]


def built(run: NotebookRun) -> list[str]:
    """The notebook's own build exercises that its run checked, once each, in order."""
    return own_build_keys(run.notebook, [s["key"] for s in run.submissions if s.get("build")])


def judged(run: NotebookRun, traces: dict[str, tuple[dict, list]] | None = None) -> NotebookRun:
    """``run`` with its records: each submission judged here, in the grader's process, by its checkers.

    A build exercise is judged from ``traces`` (key -> the trace of the function taken from the notebook
    and run in the clean room, and the cases it is judged against: :func:`.cleanroom.room_trace`); its
    submission in the kernel only said that it was checked.  One checked but never traced is errored.
    A submission the checker fails on (it raises) is that exercise errored, with a flag naming the
    failure; a notebook's submissions not judged within :data:`JUDGE_SECONDS` are errored too: one
    learner's answers never stop the grading."""
    run.records = []
    failed: set[str] = set()
    deadline = time.monotonic() + JUDGE_SECONDS
    traces = traces or {}
    work = [(s.get("key"), s) for s in run.submissions if not s.get("build")]
    work += [(key, {"key": key, "build": True, "trace": pair}) for key, pair in traces.items()]
    for position, (key, submission) in enumerate(work):
        if time.monotonic() > deadline:
            _not_judged(run, [item for _, item in work[position:]])
            break
        try:
            if "trace" in submission:
                trace, cases = submission["trace"]
                result = judge(key, trace, cases=cases, raising=True)
            else:
                result = verdict(key, submission.get("answer"), raising=True)
        except Exception as exc:  # the checker failed on this answer: this exercise errors, the rest goes on
            run.records = [record for record in run.records if record["key"] != key]
            run.errored_cells[key] = "the grader could not judge this answer (your instructor is told why)"
            if key not in failed:
                failed.add(key)
                reason = " ".join(f"{type(exc).__name__}: {exc}".split())[:200]
                run.problems.append(f"{key}: the grader could not judge the answer ({reason})")
            continue
        run.records.append({"key": result.key, "ok": result.ok, "message": result.message})
    for key in built(run):
        if key not in traces:
            run.errored_cells.setdefault(key, "its function could not be traced: " + (
                "; ".join(run.problems) or "the grader found no check of it in the notebook"))
    return run


def _not_judged(run: NotebookRun, left: list[dict]) -> None:
    """Error the exercises of the submissions ``left`` unjudged once the judging time is spent."""
    keys = [s["key"] for s in left]
    for key in keys:
        run.errored_cells.setdefault(key, f"not judged: the notebook's answers took more than "
                                          f"{JUDGE_SECONDS} s to judge")
    run.problems.append(f"its answers took more than {JUDGE_SECONDS} s to judge: {len(keys):,} of them not "
                        "judged")


def _worker(argv: list[str]) -> None:
    """Run a learner's notebooks one after the other; each one's run goes to ``RESULTS/N.json`` as soon as
    it is done (written whole, then renamed, so the grader never reads half a result)."""
    # nbformat's validator loads jsonschema's format checkers, and the IRI checker's grammar takes a second
    # to build in every worker; a notebook's schema has no IRI field, so that checker is left out
    sys.modules.setdefault("rfc3987_syntax", None)
    results, timeout, memory = Path(argv[0]), float(argv[1]), int(argv[2])
    kernel, paths = json.loads(argv[3]), [Path(path) for path in argv[4:]]
    if resource is not None:  # no resource module (Windows): no limits on the worker
        limit = WORKER_MEMORY * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        cpu = int(len(paths) * (2 * timeout + 2 * STARTUP_TIMEOUT))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 5))
        resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024 * 1024, 64 * 1024 * 1024))
    for number, path in enumerate(paths):
        run = run_notebook(path, timeout, kernel, memory)
        partial = results / f"{number}.part"
        partial.write_text(json.dumps(run.__dict__), encoding="utf-8")
        os.replace(partial, results / f"{number}.json")


def backstop(timeout: float) -> float:
    """Seconds the grader waits for one notebook's run before it stops the worker running it."""
    return 2 * timeout + 2 * STARTUP_TIMEOUT


def run_isolated(paths: list[Path], timeout: float, memory_mb: int, kernel_argv: list[str], folder: Path, *,
                 builds: list[Builds] | None = None, user: int | None = None,
                 worker: Callable[[list[str]], list[str]] | None = None) -> list[NotebookRun]:
    """:func:`run_notebook` for each of one learner's notebooks, in order, in a worker process; the runs,
    judged here.

    One worker runs the notebooks one after the other (its start, a second of imports, is paid once per
    learner, not per notebook).  Each notebook has a backstop deadline (:func:`backstop`) counted from the
    end of the one before; a worker that dies or passes it costs only the notebook it was running, which is
    reported, and a fresh worker takes the rest.  ``folder`` is the grader's own (no kernel reaches it):
    the worker writes its results there.  ``builds[N](run)``, once notebook N's kernel is done, gives the
    traces of its build exercises, each run in its clean room (:func:`.cleanroom.trace_built`), while
    the worker goes on with the next notebook.  The worker runs as ``user`` when one is given: by the
    command line ``worker`` makes of its own (:meth:`.sandbox.Seal.worker_argv`), else by switching user
    as it starts."""
    runs: list[NotebookRun] = []
    while len(runs) < len(paths):
        rest = (builds or [None] * len(paths))[len(runs):]
        runs.extend(_one_worker(paths[len(runs):], timeout, memory_mb, kernel_argv, folder, rest, user,
                                worker))
    return runs


def results_folder(folder: Path, user: int | None) -> Path:
    """A new folder in ``folder`` (mode 0700) where a worker writes its runs: the grader's, or given to the
    learner's worker (``user``) by its descriptor."""
    results = Path(tempfile.mkdtemp(prefix="runs-", dir=folder))
    if user is not None:
        handle = os.open(results, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
        try:
            os.fchown(handle, user, user)
        finally:
            os.close(handle)
    return results


def _one_worker(paths: list[Path], timeout: float, memory_mb: int, kernel_argv: list[str], folder: Path,
                builds: list[Builds | None], user: int | None = None,
                worker_argv: Callable[[list[str]], list[str]] | None = None) -> list[NotebookRun]:
    """The runs of ``paths`` by one worker, up to and including the first it could not finish; the
    worker runs as ``user`` when one is given (the grader, as root, never drives a learner's kernel)."""
    results = results_folder(folder, user)
    dropped = {}
    if user is not None:
        dropped = {"env": dict(os.environ, HOME=str(paths[0].parent.parent / "run"))}
        if worker_argv is None:
            dropped.update(user=user, group=user, extra_groups=[])
    argv = [sys.executable, "-m", "modbus_edu.course.runner", str(results), str(timeout), str(memory_mb),
            json.dumps(kernel_argv), *map(str, paths)]
    if user is not None and worker_argv is not None:
        argv = worker_argv(argv)
    errors = results / "worker.err"
    runs: list[NotebookRun] = []
    try:
        with errors.open("wb") as stream:
            worker = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                      stderr=stream, **dropped)
        try:
            for number, path in enumerate(paths):
                run = _await(worker, results / f"{number}.json", backstop(timeout), errors)
                if isinstance(run, str):
                    runs.append(NotebookRun(path.name, keys=_keys_of(path), problems=[run]))
                    break
                runs.append(judged(run, _traces(run, builds[number])))
        finally:
            _end(worker, finished=len(runs) == len(paths) and isinstance(runs[-1], NotebookRun))
    finally:
        shutil.rmtree(results, ignore_errors=True)
    return runs


def _end(worker: subprocess.Popen, finished: bool) -> None:
    """The worker ended: one that finished its notebooks is given a few seconds to exit by itself; then
    its children are killed before it (a worker run through a view is the child of the bubblewrap that
    shows it Python: killed first, it is reaped by that parent, never left to the system's init), then
    it is killed and reaped."""
    if finished:
        try:
            worker.wait(10)
            return
        except subprocess.TimeoutExpired:
            pass
    try:
        children = Path(f"/proc/{worker.pid}/task/{worker.pid}/children").read_text().split()
    except OSError:
        children = []
    for child in children:
        try:
            os.kill(int(child), 9)
        except OSError:
            pass
    worker.kill()
    worker.wait()


def _traces(run: NotebookRun, builds: Builds | None) -> dict[str, tuple[dict, list]] | None:
    """The clean-room traces of ``run``'s build exercises (none where ``builds`` is None); a room that
    fails costs only those exercises, which are then errored with the reason."""
    if builds is None:
        return None
    try:
        return builds(run)
    except Exception as exc:  # the grader's own failure: these build exercises error, the rest goes on
        reason = " ".join(f"{type(exc).__name__}: {exc}".split())[:200]
        run.problems.append(f"its functions could not be run in the clean room ({reason})")
        return {}


def _await(worker: subprocess.Popen, result: Path, seconds: float, errors: Path) -> NotebookRun | str:
    """The run the worker writes to ``result`` within ``seconds``, or why there is none."""
    deadline = time.monotonic() + seconds
    while not result.exists():
        if worker.poll() is not None and not result.exists():
            with errors.open("rb") as stream:
                stream.seek(max(0, errors.stat().st_size - 2000))
                said = stream.read().decode("utf-8", "replace").strip()[-300:]
            return "its grader failed: " + (said or f"the worker ended with status {worker.returncode}")
        if time.monotonic() > deadline:
            return f"did not finish within {seconds:g} s (its grader was stopped)"
        try:
            worker.wait(0.05)
        except subprocess.TimeoutExpired:
            pass
    try:
        return NotebookRun(**json.loads(result.read_text(encoding="utf-8")))
    except (OSError, ValueError, TypeError) as exc:
        return f"its grader failed: its result could not be read ({type(exc).__name__})"


def _keys_of(path: Path) -> list[str]:
    """The exercise keys a notebook checks, read from the file (for a notebook whose grader failed)."""
    try:
        nbformat = load_nbformat()
        if path.stat().st_size > NOTEBOOK_LIMIT:
            return []
        cells = nbformat.read(path, as_version=4).cells
    except Exception:
        return []
    return [key for cell in cells if cell.cell_type == "code" and len(cell.source) <= CELL_LIMIT
            for key in exercise_keys(cell.source)]


if __name__ == "__main__":
    _worker(sys.argv[1:])
