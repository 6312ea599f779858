"""No single learner's answer stops or stalls the gradebook for the class.

Each hole found in the grader is one test here: an answer a checker fails on, a class named after the
command line's module, a forged bank of many runs, made-up build exercises, copies of a notebook that
never ends.  Most are judged directly (:func:`~modbus_edu.course.runner.judged`, ``revive``,
``verdict``); one real class run proves them together, an honest learner beside the attackers."""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import io
import json
import os
import sys
import time
from pathlib import Path

import pytest
from test_grade import SETUP, right, write

from modbus_edu import CrcError, DataBank
from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.course import runner
from modbus_edu.course.runner import NotebookRun, judged, own_build_keys
from modbus_edu.course.verdicts import ERRORED, RIGHT, WRONG, inventory_marks, verdicts
from modbus_edu.exercises import EXERCISES, inventory, verdict
from modbus_edu.exercises.plain import MAX_RUNS, PlainError, plain, revive
from modbus_edu.exercises.submit import MIME

NOTEBOOK = "03_rtu_and_crc"
KEYS = ["03.1", "03.2", "03.5"]
HONEST = ["03.1", "03.2"]
SUPERSCRIPT = {"²": "a"}


def right_answer(key: str):
    """A right answer to value exercise ``key``, read from its worked solution's ``answer = ...`` line."""
    space: dict = {}
    source = right(key).rsplit("check(", 1)[0]
    exec(compile("import modbus_edu as mb\n" + source, key, "exec"), space)  # the course's own solution
    return space["answer"]


def submitted(*keys: str) -> list[dict]:
    return [{"key": key, "answer": plain(right_answer(key)), "real_check": True} for key in keys]


def databank(runs: list[list[int]]) -> dict:
    return {"$databank": {"sparse": True, "tables": {"holding_registers": runs}}}


# --- an answer the checker fails on --------------------------------------------------------------------

def test_an_inventory_answer_numbered_with_a_superscript_is_a_verdict_not_a_crash():
    """``check("00.0", {"²": "a"})``: ``"²".isdigit()`` yet ``int("²")`` fails; it stopped the grader."""
    run = judged(NotebookRun("00_welcome.ipynb", keys=["00.0"], submissions=[
        {"key": "00.0", "answer": plain(SUPERSCRIPT), "real_check": True}]))
    assert inventory_marks([run]) == {inventory.PRE: None, inventory.POST: None}
    found = verdicts([run])["00.0"]
    assert found.status == WRONG and "numbered 1 to 12" in found.message
    assert "ValueError" not in found.message


def test_a_checker_that_fails_errors_its_exercise_only_and_says_so_in_one_line(monkeypatch):
    def broken(answer):
        raise RuntimeError("the checker's own\nbug")

    monkeypatch.setitem(EXERCISES, "03.1", dataclasses.replace(EXERCISES["03.1"], checker=broken))
    run = judged(NotebookRun(f"{NOTEBOOK}.ipynb", keys=HONEST, submissions=submitted(*HONEST)))
    found = verdicts([run])
    assert found["03.1"].status == ERRORED and found["03.2"].status == RIGHT
    assert "RuntimeError" not in found["03.1"].message  # the learner's page names no Python exception
    flags = [problem for problem in run.problems if problem.startswith("03.1:")]
    assert flags == ["03.1: the grader could not judge the answer (RuntimeError: the checker's own bug)"]
    assert verdict("03.1", plain(b"\x01")).ok is False  # in a notebook, check still answers and never raises


def test_a_later_answer_the_checker_fails_on_counts_as_the_last(monkeypatch):
    original = EXERCISES["03.2"].checker

    def fails_on_none(answer):
        if answer is None:
            raise KeyError("none")
        return original(answer)

    monkeypatch.setitem(EXERCISES, "03.2", dataclasses.replace(EXERCISES["03.2"], checker=fails_on_none))
    first, then = submitted("03.2")[0], {"key": "03.2", "answer": None, "real_check": True}
    assert verdicts([judged(NotebookRun("x", submissions=[first, then]))])["03.2"].status == ERRORED
    assert verdicts([judged(NotebookRun("x", submissions=[then, first]))])["03.2"].status == RIGHT


def test_judging_a_notebook_has_a_time_budget(monkeypatch):
    monkeypatch.setattr(runner, "JUDGE_SECONDS", 0.2)
    original = EXERCISES["03.1"].checker

    def slow(answer):
        time.sleep(0.05)
        return original(answer)

    monkeypatch.setitem(EXERCISES, "03.1", dataclasses.replace(EXERCISES["03.1"], checker=slow))
    start = time.monotonic()
    run = judged(NotebookRun("x", submissions=submitted("03.1") * 1000 + submitted("03.2")))
    assert time.monotonic() - start < 2
    assert verdicts([run])["03.2"].status == ERRORED
    assert any("to judge" in problem and "not judged" in problem for problem in run.problems)


# --- reviving never imports ----------------------------------------------------------------------------

def test_a_class_named_after_the_command_lines_module_is_looked_up_never_imported(monkeypatch):
    """``modbus_edu.__main__`` runs the command line when imported by name: reviving must not import it."""
    monkeypatch.delitem(sys.modules, "modbus_edu.__main__", raising=False)
    monkeypatch.setattr(sys, "argv", ["modbus-edu", "--version"])
    inert = revive({"$class": "modbus_edu.__main__:Slave"})
    error = revive({"$exception": "modbus_edu.__main__:CrcError", "args": ["x"]})
    assert "modbus_edu.__main__" not in sys.modules
    assert inert.__name__ == "Slave" and inert.__module__ == "learner"
    assert type(error).__name__ == "CrcError" and not isinstance(error, CrcError)
    assert revive(plain(CrcError)) is CrcError and revive(plain(ValueError)) is ValueError
    assert revive(plain(DataBank)) is DataBank


def test_the_command_lines_module_runs_only_as_a_script(monkeypatch, capsys):
    import importlib

    monkeypatch.delitem(sys.modules, "modbus_edu.__main__", raising=False)
    monkeypatch.setattr(sys, "argv", ["modbus-edu", "--version"])
    importlib.import_module("modbus_edu.__main__")  # the library's own name, not a learner's
    assert capsys.readouterr().out == ""


# --- reviving is bounded -------------------------------------------------------------------------------

def test_a_bank_of_ten_thousand_runs_is_refused_at_once():
    forged = databank([[2 * index, 1] for index in range(10_000)])
    start = time.process_time()
    with pytest.raises(PlainError, match="10,000 runs"):
        revive(forged)
    assert time.process_time() - start < 2  # measured: well under 0.01 s


def test_a_forged_bank_declaring_one_table_over_and_over_costs_no_time():
    """120 KB of ``[0, 65536]`` runs took 42 s of the grader's time to revive."""
    forged = databank([[0, 65_536]] * 12_000)
    assert len(json.dumps(forged)) > 120_000
    start = time.process_time()
    result = verdict("09.2", forged)
    assert time.process_time() - start < 2  # measured: well under 0.01 s
    assert result.ok is False and "runs of addresses" in result.message
    with pytest.raises(PlainError, match="65,536 addresses"):
        revive(databank([[0, 65_536]] * MAX_RUNS))
    start = time.process_time()
    with pytest.raises(PlainError, match="8 banks"):
        revive([databank([[0, 65_536]])] * 200)
    assert time.process_time() - start < 2


def test_a_bank_of_too_many_runs_is_told_in_the_notebook():
    bank = DataBank(sparse=True)
    for index in range(MAX_RUNS + 1):
        bank.holding_registers.declare(2 * index)
    with pytest.raises(PlainError, match="separate runs"):
        plain(bank)
    small = DataBank(sparse=True)
    small.holding_registers.declare(150, 26)
    small.holding_registers.declare(200, 26)
    assert revive(plain(small)).holding_registers.addresses() == small.holding_registers.addresses()


# --- traces only for the notebook's own build exercises ------------------------------------------------

def test_only_the_notebooks_own_build_exercises_are_traced_each_once():
    made_up = [f"03.{number}" for number in range(6, 105)]
    keys = [*made_up, "03.5", "03.5", "05.5", "03.1", "99.9"]
    assert own_build_keys(f"{NOTEBOOK}.ipynb", keys) == ["03.5"]
    assert own_build_keys(f"ada_{NOTEBOOK}-Copy1.ipynb", keys) == ["03.5"]
    assert own_build_keys("ada.ipynb", keys) == ["03.5", "05.5"]  # no number: the course's build exercises
    run = judged(NotebookRun(f"{NOTEBOOK}.ipynb", submissions=[{"key": key, "build": True} for key in keys]))
    assert set(run.errored_cells) == {"03.5"}  # untraced made-up keys are no exercise to error


# --- copies -------------------------------------------------------------------------------------------

def fake_runs(monkeypatch, answered: dict[str, list[dict]]) -> list[str]:
    """Grade without kernels: each notebook's run submits ``answered[notebook's file name]`` (or nothing),
    judged for real; returns the names of the notebooks run, in order."""
    ran: list[str] = []

    def run_isolated(paths, timeout, memory_mb, argv, folder, builds=None, user=None, worker=None):
        ran.extend(path.name for path in paths)
        return [judged(NotebookRun(path.name, keys=HONEST, submissions=answered.get(path.name, [])))
                for path in paths]

    monkeypatch.setattr(grading, "run_isolated", run_isolated)
    return ran


def read_gradebook(out: Path) -> dict[str, dict[str, str]]:
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        return {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}  # '03.1: a text header
                for row in csv.DictReader(stream)}


def test_of_many_copies_only_the_newest_run_and_a_flag_says_so(tmp_path, monkeypatch):
    ran = fake_runs(monkeypatch, {})
    for number in range(5):
        name = NOTEBOOK if number == 0 else f"{NOTEBOOK}-Copy{number}"
        write(tmp_path / "class" / "hal", name, [SETUP, "while True:\n    pass"])
        os.utime(tmp_path / "class" / "hal" / f"{name}.ipynb", (1e9 + number, 1e9 + number))
    grading.grade([tmp_path / "class"], tmp_path / "grades", timeout=5, progress=False)
    assert sorted(ran) == [f"{NOTEBOOK}-Copy3.ipynb", f"{NOTEBOOK}-Copy4.ipynb"]
    flags = read_gradebook(tmp_path / "grades")["hal"]["flags"]
    assert f"{NOTEBOOK}: 5 copies handed in, the newest {grading.MAX_COPIES} graded; not run:" in flags


def test_a_checker_failure_leaves_every_row_of_the_gradebook(tmp_path, monkeypatch):
    def broken(answer):
        raise ValueError("no")

    monkeypatch.setitem(EXERCISES, "03.2", dataclasses.replace(EXERCISES["03.2"], checker=broken))
    fake_runs(monkeypatch, {f"{NOTEBOOK}.ipynb": submitted(*HONEST)})
    for learner in ("ada", "bob", "cy"):
        write(tmp_path / "class" / learner, NOTEBOOK, [SETUP])
    grading.grade([tmp_path / "class"], tmp_path / "grades", timeout=5, progress=False)
    rows = read_gradebook(tmp_path / "grades")
    assert sorted(rows) == ["ada", "bob", "cy"]
    for row in rows.values():
        assert (row["03.1"], row["03.2"]) == (RIGHT, ERRORED)
        assert "03.2: the grader could not judge the answer (ValueError: no)" in row["flags"]


# --- one real class --------------------------------------------------------------------------------------

def publish(payload: str, loop: str = "") -> str:
    """A cell that sends the submission ``payload`` (a Python expression) as ``check`` does, in ``loop``."""
    return (f"import json\nfrom IPython.display import display\n{loop}"
            f"display({{{MIME!r}: json.dumps({payload})}}, raw=True)")


@pytest.mark.slow
def test_a_class_of_attackers_is_graded_in_bounded_time_and_the_honest_learner_keeps_every_verdict(tmp_path):
    root, out = tmp_path / "class", tmp_path / "grades"
    write(root / "ada", NOTEBOOK, [SETUP, *(right(key) for key in KEYS)])
    write(root / "sup", "00_welcome", [SETUP, f"check('00.0', {SUPERSCRIPT!r})"])
    write(root / "main", NOTEBOOK, [SETUP, "X = type('Slave', (), {'__module__': 'modbus_edu.__main__'})\n"
                                           "check('03.1', X)", right("03.2")])
    forged = "{'key': '03.1', 'answer': {'$databank': {'sparse': True, 'tables': {'holding_registers': " \
             "[[0, 65536]] * 12000}}}}"
    write(root / "bank", NOTEBOOK, [SETUP, publish(forged), right("03.2")])
    made_up = publish("{'key': f'03.{number}', 'build': True}", loop="for number in range(6, 105):\n    ")
    write(root / "builder", NOTEBOOK, [SETUP, made_up, right("03.2")])
    for number in range(5):
        name = NOTEBOOK if number == 0 else f"{NOTEBOOK}-Copy{number}"
        write(root / "loop", name, [SETUP, right("03.1"), "while True:\n    pass"])
    printed = io.StringIO()
    start = time.monotonic()
    with contextlib.redirect_stdout(printed):
        status = main(["grade", str(root), "--out", str(out), "--timeout", "5", "--jobs", "2", "-q"])
    seconds = time.monotonic() - start
    assert status == 0, printed.getvalue()
    rows = read_gradebook(out)
    assert sorted(rows) == ["ada", "bank", "builder", "loop", "main", "sup"]
    assert [rows["ada"][key] for key in KEYS] == [RIGHT] * 3
    assert rows["main"]["03.1"] == WRONG and rows["main"]["03.2"] == RIGHT
    assert rows["bank"]["03.1"] == WRONG and rows["bank"]["03.2"] == RIGHT
    assert rows["builder"]["03.2"] == RIGHT
    assert rows["loop"]["03.1"] == RIGHT
    assert f"5 copies handed in, the newest {grading.MAX_COPIES} graded" in rows["loop"]["flags"]
    assert "did not finish within 5 s" in rows["loop"]["flags"]
    assert seconds < 120, seconds  # measured: 25 s on 2 shared cores
