"""The gradebook reads hand-ins as learning platforms make them, and its reports read right.

Moodle, Canvas and nbgrader each name a class's files their own way, flat, in folders or zipped: each
gives one row per learner, named as the platform names them, and says how it read the files.  A scratch
notebook never overrides a course notebook; a success rate counts the learners who handed the notebook
in; the concept inventory's table numbers questions as the notebooks do and shows a drop; the CSV holds
numbers, never a fraction a spreadsheet takes for a date; and the export is what Moodle's and Canvas's
grade imports read.  All without a kernel, but the last test."""

from __future__ import annotations

import csv
import os
import re
import stat
import subprocess
import tempfile
import zipfile
from datetime import datetime
from pathlib import Path

import pytest
import test_grade

from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.course.reports import _write_csv, _write_summary
from modbus_edu.course.runner import NOTEBOOK_LIMIT, NotebookRun
from modbus_edu.course.submissions import collect
from modbus_edu.course.verdicts import RIGHT, WRONG, course_keys, pick_copies, verdicts
from modbus_edu.errors import ModbusError
from modbus_edu.exercises import inventory

ROOT = Path(__file__).resolve().parents[1]
EMPTY = '{"nbformat": 4, "nbformat_minor": 5, "metadata": {}, "cells": []}'
"""A notebook with no cell: what the grader reads as a notebook."""
NOTEBOOK_KEYS = {"01_data_model": ["01.1", "01.2"], "03_rtu_and_crc": ["03.1", "03.2"],
                 "05_tcp_and_mbap": ["05.1", "05.2"]}
CANVAS = {  # six learners: a LATE mark, resubmissions (-1, -2), a scratch notebook
    "lovelaceada_12345_678901_03_rtu_and_crc.ipynb": 1_000,
    "lovelaceada_LATE_12345_678950_03_rtu_and_crc-1.ipynb": 2_000,
    "lovelaceada_12345_678902_01_data_model.ipynb": 1_000,
    "hoppergrace_23456_678903_03_rtu_and_crc.ipynb": 1_000,
    "hoppergrace_23456_678904_01_data_model.ipynb": 1_000,
    "turingalan_LATE_34567_678905_03_rtu_and_crc.ipynb": 1_000,
    "turingalan_LATE_34567_678906_05_tcp_and_mbap.ipynb": 1_000,
    "babbagecharles_45678_678907_03_rtu_and_crc.ipynb": 3_000,  # the newest file, not the newest resubmission
    "babbagecharles_45678_678908_03_rtu_and_crc-1.ipynb": 1_000,
    "babbagecharles_45678_678909_03_rtu_and_crc-2.ipynb": 2_000,
    "noetheremmy_56789_678910_01_data_model.ipynb": 1_000,
    "noetheremmy_56789_678911_Untitled.ipynb": 1_000,
    "curiemarie_67890_678912_05_tcp_and_mbap.ipynb": 1_000,
}
MOODLE = {  # participant ids of 2 and 7 digits, two learners of one name, an online text
    "Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb",
    "Ada Lovelace_12_assignsubmission_file_01_data_model.ipynb",
    "Grace Hopper_1234567_assignsubmission_file_03_rtu_and_crc.ipynb",
    "Sam Lee_21_assignsubmission_file_05_tcp_and_mbap.ipynb",
    "Sam Lee_7654321_assignsubmission_file_05_tcp_and_mbap.ipynb",
}
MOODLE_NAMES = {"Ada Lovelace": "12", "Grace Hopper": "1234567", "Sam Lee (21)": "21",
                "Sam Lee (7654321)": "7654321"}


def touch(path: Path, mtime: float | None = None, text: str = EMPTY) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    if mtime is not None:
        os.utime(path, (mtime, mtime))
    return path


def canvas_class(folder: Path) -> Path:
    for name, mtime in CANVAS.items():
        touch(folder / name, 1_600_000_000 + mtime)
    return folder


def moodle_flat(folder: Path) -> Path:
    for name in MOODLE:
        touch(folder / name)
    touch(folder / "Ada Lovelace_12_assignsubmission_onlinetext_onlinetext.html", text="<p>see the files</p>")
    return folder


def moodle_folders(folder: Path) -> Path:
    """Moodle's "Download submissions in folders": one folder per learner, files under their own name."""
    for name in MOODLE:
        prefix, _, own = name.partition("_assignsubmission_file_")
        touch(folder / f"{prefix}_assignsubmission_file_" / own)
    touch(folder / "Ada Lovelace_12_assignsubmission_onlinetext_" / "onlinetext.html", text="<p>hi</p>")
    return folder


def nbgrader_course(folder: Path) -> Path:
    handed = [("s001", "ps1", "03_rtu_and_crc"), ("s001", "ps2", "05_tcp_and_mbap"),
              ("Bob", "ps1", "03_rtu_and_crc"), ("Bob", "ps1", "01_data_model")]
    for student, assignment, notebook in handed:
        touch(folder / "submitted" / student / assignment / f"{notebook}.ipynb")
        touch(folder / "autograded" / student / assignment / f"{notebook}.ipynb")
    touch(folder / "submitted" / "s001" / "ps1" / "timestamp.txt", text="2026-01-01 10:00:00")
    return folder


def zipped(folder: Path, archive: Path) -> Path:
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as out:
        for path in sorted(folder.rglob("*")):
            if path.is_file():
                out.write(path, path.relative_to(folder).as_posix())
    return archive


def rows(found) -> dict[str, list[str]]:
    table: dict[str, list[str]] = {}
    for submission in found.submissions:
        table.setdefault(submission.learner, []).append(submission.notebook)
    return {learner: sorted(set(notebooks)) for learner, notebooks in table.items()}


def right(key: str) -> dict:
    return {"key": key, "ok": True, "message": f"Right! Exercise {key} is solved."}


def wrong(key: str) -> dict:
    return {"key": key, "ok": False, "message": f"Not yet: {key} is wrong."}


def answering(submission, keys: dict[str, dict] | None = None) -> NotebookRun:
    """A run of a submitted notebook: each of its exercises answered right, unless ``keys`` says."""
    if keys is None:
        keys = {key: right(key) for key in NOTEBOOK_KEYS.get(submission.notebook, [])}
    return NotebookRun(submission.path.name, keys=list(keys), records=list(keys.values()))


def graded_table(found, runs=None):
    """What ``grade`` makes of a class once its runs are in: the columns and each learner's verdicts."""
    graded = [(s, (runs or {}).get(s.path.name) or answering(s)) for s in found.submissions]
    chosen, choices = pick_copies(graded)
    columns, kept, _ = course_keys(chosen)
    return columns, {learner: verdicts(kept.get(learner, [])) for learner in found.learners}, chosen, choices


def score(row: dict, columns: list[str]) -> tuple[int, int]:
    return sum(1 for key in columns if key in row and row[key].status == RIGHT), len(columns)


# --- Canvas --------------------------------------------------------------------------------------------

def test_a_canvas_download_is_one_row_per_learner_and_the_newest_resubmission_counts(tmp_path):
    found = collect([canvas_class(tmp_path / "canvas")])
    assert rows(found) == {
        "babbagecharles": ["03_rtu_and_crc"], "curiemarie": ["05_tcp_and_mbap"],
        "hoppergrace": ["01_data_model", "03_rtu_and_crc"],
        "lovelaceada": ["01_data_model", "03_rtu_and_crc"],
        "noetheremmy": ["01_data_model", "untitled"], "turingalan": ["03_rtu_and_crc", "05_tcp_and_mbap"]}
    assert {name: (person.platform, person.id) for name, person in found.identities.items()} == {
        "babbagecharles": ("canvas", "45678"), "curiemarie": ("canvas", "67890"),
        "hoppergrace": ("canvas", "23456"), "lovelaceada": ("canvas", "12345"),
        "noetheremmy": ("canvas", "56789"), "turingalan": ("canvas", "34567")}
    assert found.flags["turingalan"] == ["handed in late (Canvas marks it LATE): "
                                         "'turingalan_LATE_34567_678905_03_rtu_and_crc.ipynb', "
                                         "'turingalan_LATE_34567_678906_05_tcp_and_mbap.ipynb'"]
    assert "lovelaceada" in found.flags and "hoppergrace" not in found.flags
    canvas = [note for note in found.notes if note.startswith("Canvas's download")]
    assert len(canvas) == 1 and "13 file(s) of 6 learner(s)" in canvas[0]
    assert "3 file(s) marked LATE" in canvas[0] and "3 resubmission(s)" in canvas[0]

    # the newest resubmission counts, even when an older one answered more or is the newer file
    by_name = {s.path.name: s for s in found.submissions}
    blank = {"03.1": {"key": "03.1", "ok": None, "message": "not answered yet"}}
    runs = {"lovelaceada_LATE_12345_678950_03_rtu_and_crc-1.ipynb": answering(
                by_name["lovelaceada_LATE_12345_678950_03_rtu_and_crc-1.ipynb"], {"03.1": right("03.1")}),
            "lovelaceada_12345_678901_03_rtu_and_crc.ipynb": answering(
                by_name["lovelaceada_12345_678901_03_rtu_and_crc.ipynb"],
                {"03.1": wrong("03.1"), "03.2": right("03.2")}),
            "babbagecharles_45678_678907_03_rtu_and_crc.ipynb": answering(
                by_name["babbagecharles_45678_678907_03_rtu_and_crc.ipynb"]),
            "babbagecharles_45678_678909_03_rtu_and_crc-2.ipynb": answering(
                by_name["babbagecharles_45678_678909_03_rtu_and_crc-2.ipynb"], blank)}
    columns, table, chosen, choices = graded_table(found, runs)
    assert len(table) == 6
    assert [s.path.name for s, _ in chosen["lovelaceada"] if s.notebook == "03_rtu_and_crc"] == [
        "lovelaceada_LATE_12345_678950_03_rtu_and_crc-1.ipynb"]
    assert [s.path.name for s, _ in chosen["babbagecharles"]] == [
        "babbagecharles_45678_678909_03_rtu_and_crc-2.ipynb"]
    assert "the platform's newest resubmission" in choices["babbagecharles"][0]
    assert table["lovelaceada"]["03.1"].status == RIGHT and "03.2" not in table["lovelaceada"]


# --- Moodle --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("layout", [moodle_flat, moodle_folders])
def test_moodle_names_learners_by_full_name_whatever_the_length_of_their_id(tmp_path, layout):
    found = collect([layout(tmp_path / "moodle")])
    assert rows(found) == {"Ada Lovelace": ["01_data_model", "03_rtu_and_crc"],
                           "Grace Hopper": ["03_rtu_and_crc"], "Sam Lee (21)": ["05_tcp_and_mbap"],
                           "Sam Lee (7654321)": ["05_tcp_and_mbap"]}
    assert {name: (person.platform, person.id) for name, person in found.identities.items()} == {
        name: ("moodle", number) for name, number in MOODLE_NAMES.items()}
    moodle = [note for note in found.notes if note.startswith("Moodle's download")]
    assert len(moodle) == 1 and "5 file(s) of 4 learner(s)" in moodle[0]
    assert any("online text" in note and "not graded" in note for note in found.notes)
    columns, table, _, _ = graded_table(found)
    assert columns == ["01.1", "01.2", "03.1", "03.2", "05.1", "05.2"]
    assert score(table["Ada Lovelace"], columns) == (4, 6)  # a 2-digit id: graded, not 0/0
    assert score(table["Grace Hopper"], columns) == (2, 6)


def test_moodles_anonymous_participants_keep_their_number(tmp_path):
    touch(tmp_path / "Participant_4711_assignsubmission_file_03_rtu_and_crc.ipynb")
    found = collect([tmp_path])
    assert rows(found) == {"Participant 4711": ["03_rtu_and_crc"]}


# --- nbgrader ------------------------------------------------------------------------------------------

def test_an_nbgrader_tree_is_one_row_per_student_id(tmp_path):
    course = nbgrader_course(tmp_path / "course")
    for given in (course, course / "submitted"):
        found = collect([given])
        assert rows(found) == {"Bob": ["01_data_model", "03_rtu_and_crc"],
                               "s001": ["03_rtu_and_crc", "05_tcp_and_mbap"]}, given
        assert all(s.path.parts[-4] == "submitted" for s in found.submissions)
        assert any("nbgrader's tree" in note and "2 student(s)" in note for note in found.notes)
    assert any("autograded/: not read" in note for note in collect([course]).notes)
    autograded = collect([course / "autograded"])
    assert rows(autograded) == rows(found)
    assert {person.platform for person in found.identities.values()} == {"nbgrader"}


# --- zips ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("layout, expected", [
    (canvas_class, 6), (moodle_flat, 4), (moodle_folders, 4), (nbgrader_course, 2)])
def test_a_zip_of_each_layout_reads_as_the_folder_it_holds(tmp_path, layout, expected):
    folder = layout(tmp_path / "download")
    archive = zipped(folder, tmp_path / "submissions.zip")
    plain, packed = collect([folder]), collect([archive])
    try:
        assert rows(packed) == rows(plain) and len(rows(packed)) == expected
        assert packed.scratch and all(packed.scratch in s.path.parents for s in packed.submissions)
        assert any(note.startswith("submissions.zip: unpacked") for note in packed.notes)
        # dropped into the Makefile's submissions/ folder, it reads the same
        dropped = tmp_path / "submissions"
        dropped.mkdir()
        (dropped / archive.name).write_bytes(archive.read_bytes())
        again = collect([dropped])
        assert rows(again) == rows(plain)
        again.cleanup()
    finally:
        scratch = packed.scratch
        packed.cleanup()
    assert not scratch.exists()


def test_a_learners_own_zip_inside_a_download_is_theirs(tmp_path):
    inner = tmp_path / "work"
    touch(inner / "notebooks" / "05_tcp_and_mbap.ipynb")
    moodle = moodle_flat(tmp_path / "moodle")
    zipped(inner, moodle / "Ada Lovelace_12_assignsubmission_file_work.zip")
    folders = moodle_folders(tmp_path / "folders")
    zipped(inner, folders / "Grace Hopper_1234567_assignsubmission_file_" / "work.zip")
    only = tmp_path / "only"
    only.mkdir()
    zipped(inner, only / "Ada Lovelace_12_assignsubmission_file_work.zip")
    for given, learner, notebooks in [
            (moodle, "Ada Lovelace", ["01_data_model", "03_rtu_and_crc", "05_tcp_and_mbap"]),
            (folders, "Grace Hopper", ["03_rtu_and_crc", "05_tcp_and_mbap"]),
            (only, "Ada Lovelace", ["05_tcp_and_mbap"])]:
        found = collect([given])
        assert rows(found)[learner] == notebooks, given
        found.cleanup()


def test_a_hostile_zip_writes_nothing_outside_its_folder(tmp_path):
    archive = tmp_path / "class.zip"
    link = zipfile.ZipInfo("ada/03_rtu_and_crc.ipynb")
    link.external_attr = (stat.S_IFLNK | 0o777) << 16
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as out:
        out.writestr("../escaped_03_rtu_and_crc.ipynb", "{}")
        out.writestr("/tmp/absolute_03_rtu_and_crc.ipynb", "{}")
        out.writestr("bob/..\\..\\windows_03_rtu_and_crc.ipynb", "{}")
        out.writestr(link, "/etc/passwd")
        out.writestr("cy/03_rtu_and_crc.ipynb", " " * (NOTEBOOK_LIMIT + 1))  # a bomb, small in the zip
        out.writestr("__MACOSX/cy/._03_rtu_and_crc.ipynb", "junk")
        out.writestr("dee/03_rtu_and_crc.ipynb", EMPTY)
        out.writestr("dee/notes.txt", "not a notebook")
    found = collect([archive])
    try:
        assert [(s.learner, s.path.name) for s in found.submissions] == [("dee", "03_rtu_and_crc.ipynb")]
        assert not (tmp_path / "escaped_03_rtu_and_crc.ipynb").exists()
        assert not Path("/tmp/absolute_03_rtu_and_crc.ipynb").exists()
        reasons = " | ".join(reason for found_reasons in found.refused.values() for reason in found_reasons)
        assert "symbolic link" in reasons and "MB" in reasons
        assert set(found.refused) == {"ada", "cy"}  # the learners whose files were refused keep a row
        # a name that leads out of the zip names no learner: said in the notes, in no row
        assert sum("leads outside" in note and "in no row" in note for note in found.notes) == 3
        written = [p for p in found.scratch.rglob("*") if p.is_file()]
        assert [p.name for p in written] == ["03_rtu_and_crc.ipynb"]
        assert not any(p.is_symlink() for p in found.scratch.rglob("*"))
    finally:
        found.cleanup()
    broken = tmp_path / "broken.zip"
    broken.write_bytes(b"PK\x03\x04 not really a zip")
    unpacked = set(Path(tempfile.gettempdir()).glob("modbus-edu-unpacked-*"))
    with pytest.raises(ModbusError, match="cannot be read as a zip"):
        collect([broken])
    assert set(Path(tempfile.gettempdir()).glob("modbus-edu-unpacked-*")) == unpacked  # nothing left behind


# --- a scratch notebook never overrides ----------------------------------------------------------------

@pytest.mark.parametrize("scratch", ["Untitled.ipynb", "scratch.ipynb", "Untitled1-Copy1.ipynb"])
def test_a_scratch_notebook_counts_only_for_notebooks_not_handed_in(tmp_path, scratch):
    touch(tmp_path / "ada" / "03_rtu_and_crc.ipynb", 1_000)
    touch(tmp_path / "ada" / scratch, 2_000)  # newer, and sorted after the course notebook
    found = collect([tmp_path])
    runs = {"03_rtu_and_crc.ipynb": NotebookRun("03_rtu_and_crc.ipynb", keys=["03.1"],
                                                records=[right("03.1")]),
            scratch: NotebookRun(scratch, keys=["03.1", "05.1"], records=[wrong("03.1"), right("05.1")])}
    columns, table, chosen, choices = graded_table(found, runs)
    assert table["ada"]["03.1"].status == RIGHT  # the first wrong try in the scratch notebook changes nothing
    assert table["ada"]["05.1"].status == RIGHT  # notebook 05 was not handed in: the scratch answer counts
    assert choices["ada"] == [f"{scratch}: not named after a course notebook, so it never overrides one; "
                              "graded for 05.1 (no notebook 05 handed in); its checks of 03.1 not graded "
                              "(notebook 03 handed in)"]


# --- reports -------------------------------------------------------------------------------------------

def test_a_success_rate_counts_only_the_learners_who_handed_the_notebook_in(tmp_path):
    for learner in ("ada", "bob", "cy", "dee"):
        touch(tmp_path / learner / "03_rtu_and_crc.ipynb")
    touch(tmp_path / "ada" / "05_tcp_and_mbap.ipynb")
    touch(tmp_path / "bob" / "05_tcp_and_mbap.ipynb")
    touch(tmp_path / "cy" / "Untitled.ipynb")  # graded for 05, which cy did not hand in
    found = collect([tmp_path])
    runs = {("bob", "05_tcp_and_mbap.ipynb"): NotebookRun("05_tcp_and_mbap.ipynb", keys=["05.1", "05.2"],
                                                          records=[wrong("05.1"), right("05.2")]),
            ("cy", "Untitled.ipynb"): NotebookRun("Untitled.ipynb", keys=["05.1"], records=[right("05.1")]),
            ("dee", "03_rtu_and_crc.ipynb"): NotebookRun("03_rtu_and_crc.ipynb")}  # unreadable: no keys
    graded = [(s, runs.get((s.learner, s.path.name)) or answering(s)) for s in found.submissions]
    chosen, _ = pick_copies(graded)
    columns, kept, _ = course_keys(chosen)
    table = {learner: verdicts(kept.get(learner, [])) for learner in found.learners}
    from modbus_edu.course.verdicts import handed_in
    summary = _write_summary(tmp_path, table, columns, {}, handed=handed_in(chosen))
    rates = {row["exercise"]: (row["learners"], row["success rate"]) for row in summary["exercises"]}
    assert rates["05.1"] == (3, 2 / 3)  # ada and cy right, bob wrong; dee never handed 05 in
    assert rates["05.2"] == (3, 2 / 3)  # ada and bob right; cy's scratch notebook never checked it
    assert rates["03.1"] == (4, 3 / 4)  # dee handed 03 in: it counts, unanswered
    with (tmp_path / "summary.csv").open(encoding="utf-8") as stream:
        lines = {row["exercise"]: row for row in csv.DictReader(stream)}
    assert lines["'05.1"]["learners who handed it in"] == "3" and lines["'05.1"]["success rate (%)"] == "66.7"


def test_the_inventory_table_numbers_questions_as_the_notebooks_and_shows_a_drop(tmp_path):
    everyone = dict.fromkeys(inventory.BY_ID, True)
    marks = {f"l{n}": {inventory.PRE: dict(everyone), inventory.POST: dict(everyone)} for n in range(4)}
    marks["l0"][inventory.POST]["crc-order"] = False  # 100% -> 75%
    for learner in ("l0", "l1"):
        marks[learner][inventory.PRE]["mbap-length"] = False  # 50% -> 100%: g = 1
    _write_summary(tmp_path, {learner: {} for learner in marks}, [], {}, marks=marks)
    page = (tmp_path / "summary.html").read_text(encoding="utf-8")
    crc = f"{inventory.ORDER_PRE.index('crc-order') + 1} / {inventory.ORDER_POST.index('crc-order') + 1}"
    assert crc == "5 / " + str(inventory.ORDER_POST.index("crc-order") + 1)
    row = re.search(rf"<tr><td>{re.escape(crc)}</td><td>[^<]*</td><td>100%</td><td>75%</td><td>([^<]*)</td>",
                    page)
    assert row and row.group(1) == "100% → 75% (−25)"
    mbap = f"{inventory.ORDER_PRE.index('mbap-length') + 1} / {inventory.ORDER_POST.index('mbap-length') + 1}"
    assert f"<tr><td>{mbap}</td>" in page and "<td>50%</td><td>100%</td><td>1.00</td>" in page
    assert "<td>100%</td><td>100%</td><td>—</td>" in page  # all right before and after: nothing to measure
    assert "<th>question (00 / 17)</th>" in page


DATE_OR_NUMBER = re.compile(r"\s*[\d.,/:\s-]*\d[\d.,/:\s-]*%?\s*")


def test_the_csv_holds_numbers_and_no_text_a_spreadsheet_turns_into_a_date(tmp_path):
    table = {"6/12": {"03.1": grading.Verdict(RIGHT), "03.2": grading.Verdict(WRONG)},
             "ada": {"03.1": grading.Verdict(RIGHT)}, "1-2": {}, "Jan-5": {}, "10:30": {}}
    marks = {"ada": {inventory.PRE: dict.fromkeys(inventory.BY_ID, True), inventory.POST: None}}
    flags = {learner: [] for learner in table}
    _write_csv(tmp_path / "gradebook.csv", table, ["03.1", "03.2"], flags, marks)
    _write_summary(tmp_path, table, ["03.1", "03.2"], flags, marks=marks)
    with (tmp_path / "gradebook.csv").open(encoding="utf-8", newline="") as stream:
        lines = list(csv.reader(stream))
    header, body = lines[0], {line[0]: dict(zip(lines[0], line)) for line in lines[1:]}
    assert header[1:3] == ["'03.1", "'03.2"]  # text, not the numbers 3.1 and 3.2 (or dates)
    assert sorted(body) == ["'1-2", "'10:30", "'6/12", "'Jan-5", "ada"]
    assert (body["'6/12"]["right"], body["'6/12"]["out of"]) == ("1", "2")
    ada = body["ada"]
    assert (ada["inventory pre"], ada["inventory post"], ada["inventory questions"]) == ("12", "", "12")
    with (tmp_path / "summary.csv").open(encoding="utf-8", newline="") as stream:
        summary = list(csv.reader(stream))
    for name, cells in (("gradebook.csv", lines), ("summary.csv", summary)):
        for cell in (cell for line in cells for cell in line):
            if DATE_OR_NUMBER.fullmatch(cell):
                float(cell)  # a bare number it may be (a count, a rate); a date, a time or a fraction, never
            assert not cell.startswith(("=", "+", "-", "@")), (name, cell)


# --- exports -------------------------------------------------------------------------------------------

def read(path: Path) -> list[dict]:
    with path.open(encoding="utf-8", newline="") as stream:
        return list(csv.DictReader(stream))


def test_the_moodle_export_is_a_grading_worksheet_moodle_matches_by_participant(tmp_path):
    from modbus_edu.course.export import export
    found = collect([moodle_flat(tmp_path / "moodle")])
    columns, table, _, _ = graded_table(found)
    scores = {learner: score(table[learner], columns) for learner in found.learners}
    scores["ada"] = (1, 6)  # a learner gathered by hand: no participant id
    left_out = export(tmp_path / "moodle.csv", "moodle", scores, found.identities)
    assert left_out == ["ada"]
    lines = read(tmp_path / "moodle.csv")
    assert {"Identifier", "Grade", "Last modified (grade)"} <= set(lines[0])  # what Moodle's import needs
    grades = {line["Identifier"]: float(line["Grade"]) for line in lines}
    assert grades == {"Participant 12": 66.67, "Participant 21": 33.33, "Participant 1234567": 33.33,
                      "Participant 7654321": 33.33}
    assert all(line["Maximum grade"] == "100" for line in lines)
    names = sorted(line["Full name"] for line in lines)
    assert names == ["Ada Lovelace", "Grace Hopper", "Sam Lee", "Sam Lee"]
    datetime.fromisoformat(lines[0]["Last modified (grade)"])  # a time PHP's strtotime reads
    with pytest.raises(ModbusError, match="none of the learners came from a Canvas download"):
        export(tmp_path / "canvas.csv", "canvas", scores, found.identities)


def test_the_canvas_export_is_a_gradebook_import_matched_by_user_id(tmp_path, capsys, monkeypatch):
    found = collect([canvas_class(tmp_path / "canvas")])
    columns, table, _, _ = graded_table(found)
    scores = {learner: score(table[learner], columns) for learner in found.learners}
    summary = {"learners": 6, "seconds": 0.1, "exercises": [], "flags": {}, "notes": [], "scores": scores,
               "identities": found.identities}
    monkeypatch.setattr(grading, "grade", lambda *args, **kwargs: summary)
    out = tmp_path / "grades"
    out.mkdir()
    assert main(["grade", str(tmp_path / "canvas"), "--out", str(out), "-q", "--export", "canvas",
                 "--assignment", "Notebooks (4321)"]) == 0
    assert "canvas grade import:" in capsys.readouterr().out
    with (out / "canvas-import.csv").open(encoding="utf-8", newline="") as stream:
        header, possible, *body = list(csv.reader(stream))
    assert header == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Notebooks (4321)"]
    assert possible == ["    Points Possible", "", "", "", "", "100"]  # as Canvas's own export has it
    grades = {line[1]: float(line[5]) for line in body}
    assert grades == {"12345": 66.67, "23456": 66.67, "34567": 66.67, "45678": 33.33, "56789": 33.33,
                      "67890": 33.33}  # of the six exercises of notebooks 01, 03 and 05
    assert {line[0] for line in body} == set(found.identities)


# --- the repository ------------------------------------------------------------------------------------

def test_make_grades_folders_are_never_committed():
    for path in ("submissions/ada/03_rtu_and_crc.ipynb", "grades/gradebook.csv"):
        ignored = subprocess.run(["git", "check-ignore", "-q", path], cwd=ROOT, timeout=30)
        assert ignored.returncode == 0, path


# --- the same, in real kernels -------------------------------------------------------------------------

@pytest.mark.slow
def test_a_canvas_zip_graded_in_real_kernels_and_exported(tmp_path, capsys):
    """Two learners as Canvas zips them: a late resubmission, a scratch notebook with a first wrong try;
    graded in real kernels, then exported for Canvas's import."""
    room = tmp_path / "canvas"
    setup, write = test_grade.SETUP, test_grade.write
    write(room, "lovelaceada_12345_678901_03_rtu_and_crc", [setup, test_grade.wrong("03.1")])
    write(room, "lovelaceada_LATE_12345_678950_03_rtu_and_crc-1", [setup, test_grade.right("03.1")])
    write(room, "hoppergrace_23456_678903_03_rtu_and_crc", [setup, test_grade.right("03.1")])
    write(room, "hoppergrace_23456_678904_Untitled", [setup, test_grade.wrong("03.1")])
    archive = zipped(room, tmp_path / "submissions.zip")
    out = tmp_path / "grades"
    unpacked = set(Path(tempfile.gettempdir()).glob("modbus-edu-unpacked-*"))
    assert main(["grade", str(archive), "--out", str(out), "--timeout", "60", "-q", "--jobs", "2",
                 "--export", "canvas"]) == 0
    printed = capsys.readouterr().out
    assert "Canvas's download" in printed and "submissions.zip: unpacked, 4 notebook(s)" in printed
    lines = {line["learner"]: line for line in read(out / "gradebook.csv")}
    assert sorted(lines) == ["hoppergrace", "lovelaceada"]
    assert [(lines[name]["'03.1"], lines[name]["right"]) for name in sorted(lines)] == [("right", "1")] * 2
    assert "handed in late" in lines["lovelaceada"]["flags"]
    assert "never overrides" in lines["hoppergrace"]["flags"]
    assert {line["ID"]: line["Modbus notebooks"] for line in read(out / "canvas-import.csv")} == {
        "": "100", "12345": "100.0", "23456": "100.0"}  # "": the Points Possible row
    assert set(Path(tempfile.gettempdir()).glob("modbus-edu-unpacked-*")) == unpacked  # removed when done
