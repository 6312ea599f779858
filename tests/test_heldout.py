"""Run the held-out slips (tests/heldout_slips.py) through the course's checkers.

The slips were written from the notebooks alone and never tuned against the checkers, so this test
measures how the checkers meet mistakes they were not written for. It asserts only what must hold
whatever the wording of the checkers: no slip is accepted, and the set is large enough to mean
something. With ``-s`` it prints, per notebook, how many slips the checkers

- name: the verdict names a misconception among the slip's candidates;
- name wrongly: the verdict names a misconception, none of the slip's (non-empty) candidates;
- name, no candidate: the verdict names a misconception, and no catalogue id fitted the slip;
- leave generic: the verdict refuses the answer but names no misconception;
- accept: the verdict is ok.

A verdict names a misconception when the text before its hint carries that misconception's label.

    python -m pytest tests/test_heldout.py -s
"""

import ast
import sys
from collections import Counter
from pathlib import Path

import pytest

from modbus_edu.exercises import evaluate
from modbus_edu.exercises.diagnosis.catalogue import CATALOGUE

sys.path.insert(0, str(Path(__file__).parent))
from heldout_slips import HELDOUT  # noqa: E402

COLUMNS = ("named", "wrongly named", "named, no candidate", "generic", "accepted")


def _function_from_source(source: str):
    """The function a build slip defines, as a learner's cell would define it."""
    names = [node.name for node in ast.parse(source).body if isinstance(node, ast.FunctionDef)]
    namespace: dict = {}
    exec(compile(source, "<slip>", "exec"), namespace)
    return namespace[names[-1]]


def _named(message: str) -> set[str]:
    """The catalogue ids whose label the verdict's text (before its hint) carries."""
    text = message.split("\nHint:")[0].lower()
    return {key for key, entry in CATALOGUE.items() if entry.label and entry.label.lower() in text}


def _verdict(slip: dict):
    answer = slip["answer"]
    if slip["kind"] == "build":
        answer = _function_from_source(answer)
    return evaluate(slip["key"], answer)


def _outcome(slip: dict, result) -> str:
    if result.ok:
        return "accepted"
    named = _named(result.message)
    candidates = set(slip["candidates"])
    if not named:
        return "generic"
    if not candidates:
        return "named, no candidate"
    return "named" if named & candidates else "wrongly named"


@pytest.fixture
def quiet_home(tmp_path, monkeypatch):
    """Whatever a check may keep for a learner stays in a scratch folder."""
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_no_heldout_slip_is_accepted(quiet_home):
    assert len(HELDOUT) >= 300
    table: dict[str, Counter] = {}
    accepted = []
    for slip in HELDOUT:
        outcome = _outcome(slip, _verdict(slip))
        table.setdefault(slip["key"].split(".")[0], Counter())[outcome] += 1
        if outcome == "accepted":
            accepted.append((slip["key"], slip["mistake"]))

    width = max(len(c) for c in COLUMNS)

    def row(name: str, counts: Counter) -> str:
        return f"{name:>8} {sum(counts.values()):>5} " + " ".join(f"{counts[c]:>{width}}" for c in COLUMNS)

    lines = [f"{'notebook':>8} {'slips':>5} " + " ".join(f"{c:>{width}}" for c in COLUMNS)]
    total: Counter = Counter()
    for notebook in sorted(table):
        total.update(table[notebook])
        lines.append(row(notebook, table[notebook]))
    lines.append(row("all", total))
    print("\nheld-out slips through the checkers\n" + "\n".join(lines))

    assert not accepted, f"{len(accepted)} held-out slips accepted: {accepted}"
