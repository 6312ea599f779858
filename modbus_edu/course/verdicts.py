"""A learner's verdicts: each exercise's status and the checker's feedback, from the notebooks' runs."""

from __future__ import annotations

import re
from dataclasses import dataclass

from .runner import NotebookRun

RIGHT, WRONG, NOT_ANSWERED, ERRORED = "right", "wrong", "not answered", "errored"


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
