"""``check``: in a learner's notebook it answers at once; under ``modbus-edu grade`` it only submits.

A learner's notebook calls ``check("03.1", answer)`` and reads the verdict below the cell.  When the
grader runs the notebook it sets ``MODBUS_EDU_SUBMIT=1`` in the kernel's environment; ``check`` then
judges nothing: it turns the answer into plain data (:func:`.plain.plain`) and publishes it as a display
output of the course's own MIME type, :data:`MIME`, on the kernel's message channel.  The grader reads
those messages and computes every verdict in its own process, with its own checkers.  No file and no path
is involved; a learner who publishes such a message by hand has simply given an answer.

A build exercise's function cannot leave the kernel: ``check`` keeps it (the last one given for each
exercise, in :data:`FUNCTIONS`), and once the notebook has run, the grader asks for its trace on inputs
drawn from a seed of its own (:func:`send_trace`), then judges the trace.
"""

from __future__ import annotations

import os
from typing import Any

from .core import AFTER_CHECK, EXERCISES, Result, clip, count_try, evaluate, show
from .plain import PlainError, plain, to_json

MIME = "application/vnd.modbus-edu.submission+json"
"""The MIME type of a submission on the kernel's message channel."""
SUBMIT = "MODBUS_EDU_SUBMIT"
"""The environment variable that tells ``check`` to submit instead of judging (set by the grader)."""
MAX_KEY = 100
"""The longest exercise key a submission carries, in characters."""

FUNCTIONS: dict[str, Any] = {}
"""The function last given to each build exercise in this kernel, traced when the grader asks."""


def grading() -> bool:
    """True when this kernel runs under ``modbus-edu grade``."""
    return os.environ.get(SUBMIT) == "1"


def check(key: str, answer: Any) -> Result:
    """Check an answer, print the verdict, and return it (falsy unless right); under the grader, submit it."""
    if grading():
        return submit(key, answer)
    result = count_try(evaluate(key, answer))
    if isinstance(key, str) and key in AFTER_CHECK:
        result = AFTER_CHECK[key](answer, result)
    print(result.message)
    return result


def _key(key: Any) -> str:
    return clip(str.__str__(key) if issubclass(type(key), str) else show(key), MAX_KEY)


def publish(payload: dict) -> None:
    """Send ``payload`` (plain data) to the grader as a display output of type :data:`MIME`."""
    from IPython.display import display  # only a grading kernel publishes: IPython is there

    display({MIME: to_json(payload), "text/plain": f"(submitted for grading: {payload.get('key')})"},
            raw=True)


def submit(key: Any, answer: Any, *, real_check: bool = True) -> Result:
    """Publish ``answer`` to exercise ``key`` as plain data; a build exercise's function is kept here."""
    name = _key(key)
    item = EXERCISES.get(name)
    payload: dict[str, Any] = {"key": name, "real_check": bool(real_check)}
    if item is not None and item.kind == "build":
        FUNCTIONS[name] = answer
        payload["build"] = True
    else:
        try:
            payload["answer"] = plain(answer)
            to_json(payload)
        except PlainError as exc:
            payload["answer"] = {"$error": str(exc)}
    publish(payload)
    return Result(name, None, f"Exercise {name}: submitted for grading.")


def record(key: Any, answer: Any, current: Any) -> Any:
    """What a graded notebook's ``check(KEY, ANSWER)`` becomes: the answer is submitted whatever ``check``
    names; a ``check`` that is not the library's own is then called as the notebook wrote it."""
    if current is check:
        return check(key, answer)
    submit(key, answer, real_check=False)
    return current(key, answer)


def send_trace(key: str, seed: str) -> None:
    """Trace the function last given to build exercise ``key`` on the inputs of ``seed``; publish it."""
    item = EXERCISES[key]
    trace = item.checker.trace(FUNCTIONS.get(key), seed)
    try:
        to_json(trace)
    except PlainError:
        trace = {"name": trace.get("name", "your_function"), "calls": [], "stopped": False}
    publish({"key": key, "trace": trace, "seed": seed})
