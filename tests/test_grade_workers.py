"""One worker runs all of a learner's notebooks; a worker that stops costs only the notebook it ran."""

from __future__ import annotations

import sys
from pathlib import Path

from test_grade import SETUP, right, write

from modbus_edu.course import runner

KERNEL = [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"]


def _class(tmp_path: Path, monkeypatch) -> list[Path]:
    monkeypatch.setenv("MODBUS_EDU_SUBMIT", "1")  # what the sandbox's launcher sets in a graded kernel
    room = tmp_path / "learner" / "work"
    write(room, "01_data_model", [SETUP, right("01.1")])
    write(room, "03_rtu_and_crc", [SETUP, "import time\ntime.sleep(600)", right("03.1")])
    write(room, "05_tcp_and_mbap", [SETUP, right("05.1")])
    (tmp_path / "learner" / "run").mkdir()
    (tmp_path / "grader").mkdir()
    return [room / f"{name}.ipynb" for name in ("01_data_model", "03_rtu_and_crc", "05_tcp_and_mbap")]


def test_a_stopped_worker_costs_only_its_notebook(tmp_path, monkeypatch):
    paths = _class(tmp_path, monkeypatch)
    monkeypatch.setattr(runner, "backstop", lambda timeout: 25.0)  # the grader gives up on 03 first
    runs = runner.run_isolated(paths, 300, 1024, KERNEL, tmp_path / "grader")
    assert [run.notebook for run in runs] == [path.name for path in paths]
    assert [record["ok"] for record in runs[0].records] == [True]
    assert runs[1].records == [] and runs[1].problems == [
        "did not finish within 25 s (its grader was stopped)"]
    assert runs[1].keys == ["03.1"]  # read from the file, so 03.1 is reported errored, not missing
    assert [record["ok"] for record in runs[2].records] == [True]  # a fresh worker took the rest
    assert list((tmp_path / "grader").iterdir()) == []  # every result file and error log removed


def test_one_worker_runs_every_notebook_in_order(tmp_path, monkeypatch):
    paths = _class(tmp_path, monkeypatch)
    paths.pop(1)
    seen = []
    original = runner._one_worker

    def counted(*args):
        seen.append([path.name for path in args[0]])
        return original(*args)

    monkeypatch.setattr(runner, "_one_worker", counted)
    runs = runner.run_isolated(paths, 60, 1024, KERNEL, tmp_path / "grader")
    assert seen == [["01_data_model.ipynb", "05_tcp_and_mbap.ipynb"]]  # one worker for both
    assert [[record["key"] for record in run.records] for run in runs] == [["01.1"], ["05.1"]]
