"""Calling a learner's function for a build exercise: call, catch, keep the outcome as plain data.

One implementation serves both places a build exercise's function runs: the learner's own kernel (a
``check`` in the notebook, through :meth:`~.build.BuildChecker.trace`) and the grader's clean room
(:mod:`modbus_edu.course.cleanroom`), where this module and :mod:`.plain` are all of ``exercises`` there
is.  So it imports only the standard library and :mod:`.plain`: no checker, no reference, no registry.

:func:`call_all` calls the function on each argument tuple in turn, within a time limit for all of them
together (:func:`run_within`), and records each call as plain data: ``{"out": ...}`` (what it returned),
``{"raised": name, "message": ...}``, ``{"unreadable": why}`` or ``{"fatal": name}`` (``SystemExit`` and
the like).  An exercise whose function changes its arguments (a slave storing a write) also gets the
arguments after the call (``"state"``) and the outcome of a second call that reads the state back
(``"read"``), with arguments chosen by the exercise's ``read_back``.  Where the reading back must be
planned without the exercise's code (the clean room), :func:`follow_plan` turns ``read_back`` into plain
data that names the state's items by position, and :func:`follow_from_plan` plays it back.
"""

from __future__ import annotations

import copy
import ctypes
import dis
import json
import os
import reprlib
import sys
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import ModbusError
from .plain import PlainError, plain, revive, to_json

Follow = Callable[[int, tuple, tuple], "tuple | None"]
"""``follow(index, args, state)``: the arguments of the read-back call after call ``index``, or None."""


class Stopped(BaseException):
    """Raised inside the worker thread to stop a learner's function that ran out of time."""


def run_within(work: Callable[[], None], time_limit: float, name: str = "exercise") -> bool:
    """Run ``work()``; stop it with :class:`Stopped` after ``time_limit`` seconds. True if it finished.

    ``work`` runs in a worker thread, stopped from outside when time is up.  Where no thread can start
    (Pyodide, in a browser), it runs here under a trace function that raises :class:`Stopped` inside the
    learner's code once the deadline has passed, so an endless loop is still stopped (a single call into
    C that never returns is not: only Python lines are counted).
    """
    worker = threading.Thread(target=work, name=name, daemon=True)
    try:
        if sys.platform == "emscripten":
            raise RuntimeError("a browser cannot start threads")
        worker.start()
    except RuntimeError:  # can't start new thread
        return _run_traced(work, time_limit)
    worker.join(time_limit)
    if worker.is_alive():
        stop = ctypes.py_object(Stopped)
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(worker.ident), stop)
        worker.join(0.5)
        return False
    return True


def _run_traced(work: Callable[[], None], time_limit: float) -> bool:
    """:func:`run_within` in this thread: the clock is read every 1000 Python lines and calls."""
    deadline = time.monotonic() + time_limit
    events = [0]
    late = [False]

    def tracer(frame: Any, event: str, arg: Any) -> Any:
        events[0] += 1
        if events[0] % 1000 == 0 and time.monotonic() > deadline:
            late[0] = True
            raise Stopped  # raised in the traced frame: the learner's function stops here
        return tracer

    previous = sys.gettrace()
    sys.settrace(tracer)
    try:
        work()
    finally:
        sys.settrace(previous)
    return not late[0]


def is_unwritten(function: Callable) -> bool:
    """True if ``function``'s body is only ``...`` or ``pass`` (and maybe a docstring): a template."""
    code = getattr(function, "__code__", None)
    if code is None:
        return False
    for instruction in dis.get_instructions(code):
        if instruction.opname in ("RESUME", "NOP", "RETURN_VALUE", "CACHE"):
            continue
        if instruction.opname in ("LOAD_CONST", "RETURN_CONST") and instruction.argval is None:
            continue
        return False
    return True


def safe_str(value: Any) -> str:
    """``str(value)``, or a description of it when its ``__str__`` fails."""
    try:
        return str(value)
    except Exception:
        return f"<a {type(value).__name__} that cannot be printed>"


def call_all(function: Callable, arguments: Sequence[tuple], *, time_limit: float, name: str,
             follow: Follow | None = None) -> dict:
    """The trace of ``function`` on each of ``arguments`` (see the module's docstring); never raises.

    Each call gets a deep copy of its arguments; ``follow`` (if any) chooses the read-back call after a
    call that returned.  The result: ``{"name", "calls", "stopped"}``, plain data."""
    calls: list[dict] = []

    def outcome(call_args: tuple) -> dict:
        try:
            got = function(*call_args)
        except Stopped:
            raise
        except Exception as exc:
            return {"raised": type(exc).__name__[:60], "message": safe_str(exc)[:300]}
        try:
            return {"out": plain(got)}
        except PlainError as exc:
            return {"unreadable": str(exc)}

    def work() -> None:
        try:
            for index, args in enumerate(arguments):
                state = copy.deepcopy(tuple(args))
                entry = outcome(state)
                if follow is not None and "out" in entry:
                    entry["state"] = plain(state)
                    mine = follow(index, tuple(args), state)
                    if mine is not None:
                        entry["read"] = outcome(mine)
                calls.append(entry)
        except Stopped:
            pass
        except BaseException as exc:  # SystemExit, KeyboardInterrupt raised by the learner's code
            calls.append({"fatal": type(exc).__name__[:60]})

    finished = run_within(work, time_limit, name=name)
    return {"name": str(getattr(function, "__name__", "your_function"))[:60], "calls": calls,
            "stopped": not finished}


# --- reading back without the exercise's code --------------------------------------------------------

class FollowPlanError(ModbusError):
    """An exercise's ``read_back`` that cannot be planned as plain data (it looks inside the state)."""


class _Item:
    """Stands for item ``index`` of the state while a read back is planned."""

    def __init__(self, index: int) -> None:
        self.index = index


def follow_plan(read_back: Callable[[tuple, tuple], tuple | None], args: tuple) -> list | None:
    """``read_back(args, state)`` as plain data, the state's items named by position, or None.

    Each item of the read-back arguments becomes ``{"state": i}`` (item ``i`` of the state, whatever
    the learner's function left in it) or ``{"value": plain data}``.  Raises :class:`FollowPlanError`
    when ``read_back`` looks inside the state instead of passing its items on whole."""
    items = tuple(_Item(index) for index in range(len(args)))
    try:
        chosen = read_back(args, items)
    except Exception as exc:
        raise FollowPlanError(f"read_back must pass the state's items on whole ({type(exc).__name__})"
                              ) from None
    if chosen is None:
        return None
    plan = [{"state": item.index} if isinstance(item, _Item) else {"value": plain(item)} for item in chosen]
    if '"_Item"' in json.dumps(plan):
        raise FollowPlanError("read_back must pass the state's items on whole, not inside another value")
    return plan


def follow_from_plan(plans: Sequence[list | None]) -> Follow:
    """A ``follow`` for :func:`call_all` that plays back :func:`follow_plan`'s plans, one per call."""
    def follow(index: int, args: tuple, state: tuple) -> tuple | None:
        plan = plans[index] if index < len(plans) else None
        if plan is None:
            return None
        return tuple(state[item["state"]] if "state" in item else revive(item["value"]) for item in plan)
    return follow


# --- the clean room's side ------------------------------------------------------------------------------

LOAD_LIMIT = 10.0
"""Seconds the clean room gives the learner's module to load (its imports, constants and tables)."""


def _load(source: str, name: str) -> tuple[Any, str]:
    """The learner's module run in a fresh namespace: the object ``name`` there, or why not."""
    namespace: dict[str, Any] = {"__name__": "__learner__", "__builtins__": __builtins__}
    failed: list[str] = []

    def work() -> None:
        try:
            exec(compile(source, "<your notebook>", "exec"), namespace)
        except Stopped:
            failed.append(f"loading it took more than {LOAD_LIMIT:g} s")
        except BaseException as exc:
            failed.append(f"{type(exc).__name__}: {safe_str(exc)[:300]}")

    if not run_within(work, LOAD_LIMIT, name="loading") and not failed:
        failed.append(f"loading it took more than {LOAD_LIMIT:g} s")
    if failed:
        return None, failed[0]
    if name not in namespace:
        return None, f"NameError: name {name!r} is not defined"
    return namespace[name], ""


def room_main() -> None:
    """The clean room (see :mod:`modbus_edu.course.cleanroom`): read the job from stdin, load the
    learner's module, trace its function on the job's arguments, write the trace to stdout.

    What the learner's code prints goes to stderr: stdout is kept for the trace alone."""
    out = os.dup(1)
    os.dup2(2, 1)
    job = json.loads(sys.stdin.read())
    name = str(job["name"])
    function, problem = _load(job["source"], name)
    if problem:
        trace: dict = {"name": name, "unloadable": problem}
    elif not callable(function):
        trace = {"not_callable": reprlib.repr(function)[:120]}
    elif is_unwritten(function):
        trace = {"unwritten": True}
    else:
        arguments = [tuple(args) for args in revive(job["arguments"])]
        plans = job.get("plans")
        trace = call_all(function, arguments, time_limit=float(job["time_limit"]), name=name,
                         follow=None if plans is None else follow_from_plan(plans))
    try:
        text = to_json(trace)
    except PlainError:
        text = to_json({"name": name, "unloadable": "its results are too large to send back"})
    with os.fdopen(out, "w", encoding="utf-8") as stream:
        stream.write(text)
    os._exit(0)  # threads of the learner's that never ended do not keep the room open
