"""``check``: in a learner's notebook it answers at once; under ``modbus-edu grade`` it only submits.

A learner's notebook calls ``check("03.1", answer)`` and reads the verdict below the cell.  When the
grader runs the notebook it sets ``MODBUS_EDU_SUBMIT=1`` in the kernel's environment; ``check`` then
judges nothing: it turns the answer into plain data (:func:`.plain.plain`) and publishes it as a display
output of the course's own MIME type, :data:`MIME`, on the kernel's message channel.  The grader reads
those messages and computes every verdict in its own process, with its own checkers.  No file and no path
is involved; a learner who publishes such a message by hand has simply given an answer.

A build exercise's function cannot leave the kernel, and is not asked to: ``check`` only submits that the
exercise was checked.  The grader takes the function from the handed-in notebook and runs it in a clean
room, away from this kernel (:mod:`modbus_edu.course.cleanroom`).
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
    """Publish ``answer`` to exercise ``key`` as plain data (for a build exercise, only that it was
    checked: its function is taken from the notebook's source)."""
    name = _key(key)
    item = EXERCISES.get(name)
    payload: dict[str, Any] = {"key": name, "real_check": bool(real_check)}
    if item is not None and item.kind == "build":
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

