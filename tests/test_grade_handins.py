"""Hand-ins read without trusting them, and the grade the instructor assigned.

Each hole found in how the gradebook reads a class is one test here, all without a kernel: a learner's
zip that names a classmate, an entry that stops the class (a name too long, a bad encoding, a file that
is no notebook), refusals in another learner's row or in a row of their own, zip bombs, names and pages
that collide; then what counts towards the grade, which copy counts, the exports and the reports."""

from __future__ import annotations

import html
import json
import os
import stat
import struct
import time
import zipfile
from pathlib import Path

import pytest

from modbus_edu.course import archives
from modbus_edu.course.export import export
from modbus_edu.course.reports import page_name
from modbus_edu.course.submissions import collect

EMPTY = {"nbformat": 4, "nbformat_minor": 5, "metadata": {}, "cells": []}
NOTEBOOK = json.dumps(EMPTY)


def notebook(path: Path, text: str = NOTEBOOK, mtime: float | None = None) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    if mtime is not None:
        os.utime(path, (mtime, mtime))
    return path


def zipped(archive: Path, entries: dict[str, str | bytes], method: int = zipfile.ZIP_DEFLATED) -> Path:
    archive.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(archive, "w", method) as out:
        for name, data in entries.items():
            out.writestr(name, data)
    return archive


def rows(found) -> dict[str, list[str]]:
    table: dict[str, list[str]] = {}
    for submission in found.submissions:
        table.setdefault(submission.learner, []).append(submission.path.name)
    return {learner: sorted(files) for learner, files in table.items()}


def refusals(found) -> str:
    return " | ".join(f"{learner}: {reason}" for learner, reasons in found.refused.items()
                      for reason in reasons)


# --- a zip never names another learner -------------------------------------------------------------------

def test_a_learners_zip_never_names_a_classmate(tmp_path):
    """``ada.zip`` carried ``hal/03_rtu_and_crc.ipynb``: it took hal's row, and ada's own file made a row
    named ``03_rtu_and_crc``."""
    moodle_like = "Hal Jordan_9_assignsubmission_file_01_data_model.ipynb"
    zipped(tmp_path / "class" / "ada.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK,
                                            "hal/03_rtu_and_crc.ipynb": NOTEBOOK, moodle_like: NOTEBOOK})
    zipped(tmp_path / "class" / "hal.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK})
    found = collect([tmp_path / "class"])
    try:
        assert sorted(found.learners) == ["ada", "hal"]
        hal = [s for s in found.submissions if s.learner == "hal"]
        assert [s.path.relative_to(found.scratch).parts[1:] for s in hal] == [("hal", "03_rtu_and_crc.ipynb")]
        ada = sorted(s.path.relative_to(found.scratch).as_posix().split("/", 1)[1]
                     for s in found.submissions if s.learner == "ada")
        assert ada == ["ada/03_rtu_and_crc.ipynb", f"ada/{moodle_like}", "ada/hal/03_rtu_and_crc.ipynb"]
        assert not found.identities  # nothing in a learner's zip is a platform's name
        assert any("a folder of learners, one zip one learner" in note for note in found.notes)
    finally:
        found.cleanup()


def test_a_folder_of_platform_downloads_still_names_learners(tmp_path):
    zipped(tmp_path / "drop" / "moodle.zip", {
        "Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb": NOTEBOOK,
        "Hal Jordan_9_assignsubmission_file_/01_data_model.ipynb": NOTEBOOK})
    found = collect([tmp_path / "drop"])
    try:
        assert sorted(found.learners) == ["Ada Lovelace", "Hal Jordan"]
    finally:
        found.cleanup()


# --- one bad entry never stops the class -----------------------------------------------------------------

LONG = "Mal Icious_666_assignsubmission_file_" + "é" * 110 + ".ipynb"


def _bad_utf8(archive: Path, good: bytes, bad: bytes) -> Path:
    """The zip with ``good`` (part of a UTF-8 name) replaced by the invalid ``bad``, flag kept."""
    data = archive.read_bytes()
    assert data.count(good) == 2 and len(good) == len(bad)  # the local header and the directory
    archive.write_bytes(data.replace(good, bad))
    return archive


def test_an_entry_that_cannot_be_written_out_is_refused_in_its_learners_row(tmp_path):
    """A Moodle name of 263 bytes ended the run with "File name too long"; a name that is not the UTF-8
    it says it is ended it in the reader."""
    assert len(LONG.encode()) > 255
    archive = zipped(tmp_path / "moodle.zip", {
        LONG: NOTEBOOK,
        "Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb": NOTEBOOK,
        "Eve Bad_77_assignsubmission_file_03_rtu_and_crc_é.ipynb": NOTEBOOK,
        "Cy Old_88_assignsubmission_file_03_rtu_and_crc.ipynb": json.dumps({"nbformat": 3, "worksheets": []}),
        "Dee Text_99_assignsubmission_file_03_rtu_and_crc.ipynb": "print('not json')",
    })
    _bad_utf8(archive, "_é.ipynb".encode(), b"_\xff\xfe.ipynb")
    found = collect([archive])
    try:
        assert rows(found) == {"Ada Lovelace": ["Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb"]}
        assert sorted(found.learners) == ["Ada Lovelace", "Cy Old", "Dee Text", "Eve Bad", "Mal Icious"]
        assert "longer than a file name may be" in found.refused["Mal Icious"][0]
        assert "not valid UTF-8" in found.refused["Eve Bad"][0]
        assert "nbformat 3" in found.refused["Cy Old"][0]
        assert "not JSON" in found.refused["Dee Text"][0]
        assert {person.id for person in found.identities.values()} == {"12", "77", "88", "99", "666"}
    finally:
        found.cleanup()


def test_a_folder_of_unreadable_notebooks_refuses_each_in_its_own_row(tmp_path):
    root = tmp_path / "class"
    notebook(root / "ada" / "03_rtu_and_crc.ipynb")
    big = notebook(root / "bob" / "03_rtu_and_crc.ipynb")
    os.truncate(big, 500_000_000)  # sparse: 500 MB that take no disk
    notebook(root / "cy" / "03_rtu_and_crc.ipynb", "{ not json")
    notebook(root / "dee" / "03_rtu_and_crc.ipynb", json.dumps({"nbformat": 3, "worksheets": []}))
    notebook(root / "eve" / "03_rtu_and_crc.ipynb", '{"nbformat": 4, "cells": [' * 10 + "\xe9")
    (root / "fay").mkdir()
    with open(os.fsencode(root / "fay") + b"/03_rtu_and_crc_\xff.ipynb", "w") as stream:
        stream.write(NOTEBOOK)
    (root / "gus").mkdir()
    (root / "gus" / "01_data_model.ipynb").write_bytes(b"\xff\xfe not text")
    os.makedirs(os.fsencode(root) + b"/h\xffl")
    with open(os.fsencode(root) + b"/h\xffl/03_rtu_and_crc.ipynb", "w") as stream:
        stream.write(NOTEBOOK)
    start = time.monotonic()
    found = collect([root])
    assert time.monotonic() - start < 5
    assert [(s.learner, s.path.name) for s in found.submissions] == [
        ("ada", "03_rtu_and_crc.ipynb"), ("h\ufffdl", "03_rtu_and_crc.ipynb")]
    assert sorted(found.refused) == ["bob", "cy", "dee", "eve", "fay", "gus"]
    assert "500.0 MB" in found.refused["bob"][0]
    assert "not JSON" in found.refused["cy"][0] and "not JSON" in found.refused["eve"][0]
    assert "nbformat 3" in found.refused["dee"][0] and "not valid UTF-8" in found.refused["fay"][0]
    assert "not UTF-8" in found.refused["gus"][0]
    for learner, reasons in found.refused.items():  # every line can be written into the reports
        (learner + " ".join(reasons)).encode("utf-8")


# --- refusals land in their learner's row, and make no row of their own ----------------------------------

def _link(name: str) -> zipfile.ZipInfo:
    info = zipfile.ZipInfo(name)
    info.external_attr = (stat.S_IFLNK | 0o777) << 16
    return info


def test_refused_entries_make_no_rows_of_their_own(tmp_path):
    archive = tmp_path / "class.zip"
    with zipfile.ZipFile(archive, "w") as out:
        out.writestr("ada/03_rtu_and_crc.ipynb", NOTEBOOK)
        out.writestr("/abs_03_rtu_and_crc.ipynb", NOTEBOOK)
        out.writestr("c:/drive_03_rtu_and_crc.ipynb", NOTEBOOK)
        out.writestr(_link("link"), "/etc/passwd")
        out.writestr(_link("link.ipynb"), "/etc/passwd")
        out.writestr(_link(" (1).ipynb"), "/etc/passwd")
    found = collect([archive])
    try:
        assert found.learners == ["ada"]
        assert sum("in no row" in note for note in found.notes) == 4
    finally:
        found.cleanup()


def test_one_learners_refusals_land_in_their_row_only(tmp_path):
    root = tmp_path / "class"
    with zipfile.ZipFile(root.mkdir() or root / "ada.zip", "w") as out:
        out.writestr("03_rtu_and_crc.ipynb", NOTEBOOK)
        out.writestr("hal/../../escape_03_rtu_and_crc.ipynb", NOTEBOOK)
        out.writestr(_link("hal/01_data_model.ipynb"), "/etc/passwd")
    zipped(root / "hal.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK})
    found = collect([root])
    try:
        assert sorted(found.learners) == ["ada", "hal"]
        assert list(found.refused) == ["ada"] and len(found.refused["ada"]) == 2
        assert "leads outside" in refusals(found) and "symbolic link" in refusals(found)
    finally:
        found.cleanup()


def test_a_thousand_refusals_are_ten_lines_and_a_count(tmp_path):
    with zipfile.ZipFile(tmp_path / "class.zip", "w") as out:
        out.writestr("ada/03_rtu_and_crc.ipynb", NOTEBOOK)
        for number in range(1000):
            out.writestr(f"../{number}_03_rtu_and_crc.ipynb", NOTEBOOK)
            out.writestr(_link(f"ada/{number}_01_data_model.ipynb"), "/etc/passwd")
    found = collect([tmp_path / "class.zip"])
    try:
        assert len(found.refused["ada"]) == 11 and found.refused["ada"][-1] == "and 990 more entries refused"
        ownerless = [note for note in found.notes if "in no row" in note or "name no learner" in note]
        assert len(ownerless) == 11 and ownerless[-1] == "and 990 entries that name no learner refused"
    finally:
        found.cleanup()


# --- zip bombs ----------------------------------------------------------------------------------------

def _repeated(archive: Path, times: int) -> Path:
    """``archive`` (one entry) with its central directory listing that one entry ``times`` times."""
    data = archive.read_bytes()
    end = data.rindex(b"PK\x05\x06")
    signature, disk, start_disk, _, _, size, offset, comment = struct.unpack("<4s4H2LH", data[end:end + 22])
    entry = data[offset:offset + size]
    table = entry * times
    archive.write_bytes(data[:offset] + table + struct.pack("<4s4H2LH", signature, disk, start_disk, times,
                                                            times, len(table), offset, comment))
    return archive


def test_a_directory_that_lists_one_inner_zip_three_times_is_refused_before_a_byte_is_inflated(tmp_path):
    """968 KB that listed one deflated inner zip 3 times wrote 3 GB in 47 s."""
    inner = tmp_path / "inner.zip"
    zipped(inner, {"03_rtu_and_crc.ipynb": b"\0" * 4_000_000, "01_data_model.ipynb": b"\0" * 4_000_000},
           zipfile.ZIP_STORED)  # 8 MB of zeros, stored: the outer zip deflates it to kilobytes
    root = tmp_path / "class"
    bomb = _repeated(zipped(root / "bomb.zip", {"work.zip": inner.read_bytes()}), 3)
    assert bomb.stat().st_size < 100_000
    zipped(root / "ada.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK})
    spent: list[str] = []
    original = getattr(archives, "_write", None)
    if original is not None:  # every entry written out, seen
        archives._write = lambda *args: spent.append(args[1].name) or original(*args)
    start = time.monotonic()
    try:
        found = collect([root])
    finally:
        if original is not None:
            archives._write = original
    try:
        assert rows(found) == {"ada": ["03_rtu_and_crc.ipynb"]}
        assert list(found.refused) == ["bomb"] and "the same bytes as" in found.refused["bomb"][0]
        assert time.monotonic() - start < 2
        assert spent == ["03_rtu_and_crc.ipynb"]  # ada's, and nothing of the bomb inflated
    finally:
        found.cleanup()


def test_entries_that_overlap_are_refused(tmp_path):
    """An entry whose bytes lie inside another's (a second name for part of the first one's data)."""
    inner = zipped(tmp_path / "inner.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK}, zipfile.ZIP_STORED)
    inner = inner.read_bytes()
    outer = zipped(tmp_path / "class" / "x.zip", {"01_data_model.ipynb": inner}, zipfile.ZIP_STORED)
    data = outer.read_bytes()
    end = data.rindex(b"PK\x05\x06")
    signature, disk, start_disk, _, count, size, offset, comment = struct.unpack("<4s4H2LH",
                                                                                 data[end:end + 22])
    inside = data.index(inner)  # where the inner zip's local header lies in the outer zip's data
    inner_end = inner.rindex(b"PK\x05\x06")
    inner_table = inner[struct.unpack_from("<L", inner, inner_end + 16)[0]:inner_end]
    second = bytearray(inner_table)
    struct.pack_into("<L", second, 42, inside)
    table = data[offset:offset + size] + bytes(second)
    outer.write_bytes(data[:offset] + table + struct.pack("<4s4H2LH", signature, disk, start_disk, count + 1,
                                                          count + 1, len(table), offset, comment))
    assert [info.filename for info in zipfile.ZipFile(outer).infolist()] == ["01_data_model.ipynb",
                                                                             "03_rtu_and_crc.ipynb"]
    found = collect([tmp_path / "class"])
    try:
        assert not found.submissions and "bytes that overlap" in found.refused["x"][0]
    finally:
        found.cleanup()


def test_every_byte_inflated_counts_against_the_learners_and_the_classs_budget(tmp_path, monkeypatch):
    monkeypatch.setattr(archives, "LEARNER_BYTES", 12_000_000, raising=False)
    monkeypatch.setattr(archives, "CLASS_BYTES", 22_000_000, raising=False)
    inner = tmp_path / "inner.zip"
    zipped(inner, {f"0{n}_notebook.ipynb": b"\0" * 4_000_000 for n in range(5)})  # 20 MB, deflated
    root = tmp_path / "class"
    for learner in ("ada", "bob", "cy"):
        zipped(root / f"{learner}.zip", {"work.zip": inner.read_bytes(), "03_rtu_and_crc.ipynb": NOTEBOOK})
    start = time.monotonic()
    found = collect([root])
    try:
        assert time.monotonic() - start < 10
        reasons = {learner: " | ".join(lines) for learner, lines in found.refused.items()}
        assert "all the grader unpacks for one learner" in reasons["ada"]
        assert "all the grader unpacks for one learner" in reasons["bob"]
        assert "all the grader unpacks for one class" in reasons["cy"]
        inflated = sum(p.stat().st_size for p in found.scratch.rglob("*") if p.is_file())
        assert inflated <= 22_000_000
        assert all(reasons[learner].count("refused") >= 2 for learner in ("ada", "bob"))
    finally:
        found.cleanup()


# --- rows and pages keyed by the platform's id ------------------------------------------------------------

def test_a_learner_named_like_a_disambiguated_classmate_keeps_a_row_and_the_export(tmp_path):
    for name in ("Sam Lee_21", "Sam Lee_7654321", "Sam Lee (21)_555"):
        notebook(tmp_path / "moodle" / f"{name}_assignsubmission_file_05_tcp_and_mbap.ipynb")
    found = collect([tmp_path / "moodle"])
    assert len(found.learners) == 3 and len(set(found.learners)) == 3
    assert sorted(person.id for person in found.identities.values()) == ["21", "555", "7654321"]
    ids = {found.identities[learner].id: learner for learner in found.learners}
    assert ids == {"21": "Sam Lee (Moodle 21)", "555": "Sam Lee (21) (555)", "7654321": "Sam Lee (7654321)"}
    scores = {learner: (1, 2) for learner in found.learners}
    export(tmp_path / "moodle.csv", "moodle", scores, found.identities)
    exported = (tmp_path / "moodle.csv").read_text(encoding="utf-8")
    for number in ("21", "555", "7654321"):
        assert f"Participant {number}," in exported


def test_page_names_cannot_collide():
    old = page_name("Ada")
    assert page_name(old.removesuffix(".html")) != old  # "ada-99a563ab" could overwrite Ada's page
    names = ["Ada", "ada", "ADA", old.removesuffix(".html"), "ada lovelace", "ada_lovelace", "../ada", "é",
             "e", "Sam Lee (21)", "Sam Lee (21) (Moodle 555)"]
    from modbus_edu.course.reports import page_names  # the class's page names, made together

    pages = page_names(names)
    assert len(set(pages.values())) == len(names)
    assert all("/" not in page and not page.startswith(".") for page in pages.values())


# --- the grade the instructor assigned ---------------------------------------------------------------------

KEYS_03 = ["03.1", "03.2", "03.3", "03.4", "03.5"]
KEYS_05 = ["05.1", "05.2", "05.3", "05.4", "05.5"]


def cell_notebook(path: Path, cells: list[str], mtime: float | None = None) -> Path:
    book = dict(EMPTY, cells=[{"cell_type": "code", "source": source, "metadata": {}, "outputs": [],
                               "execution_count": None} for source in cells])
    return notebook(path, json.dumps(book), mtime)


def fake_grading(monkeypatch, answers: dict[str, dict[str, bool | None]]) -> list[str]:
    """Grade without kernels: the notebook ``learner/file`` checks the keys ``answers`` gives it, right
    (True), wrong (False) or blank (None); returns the notebooks run."""
    from modbus_edu.course import grade as grading
    from modbus_edu.course.runner import NotebookRun

    class Level:
        note = "isolation: none (the kernels are faked)"

    ran: list[str] = []

    def learner(sandbox, index, notebooks, *args):
        runs = []
        for path in notebooks:
            ran.append(f"{path.parent.name}/{path.name}")
            keys = answers.get(f"{path.parent.name}/{path.name}", {})
            said = {True: "Right!", False: "Not yet: no.", None: "..."}
            records = [{"key": key, "ok": ok, "message": said[ok]} for key, ok in keys.items()]
            runs.append(NotebookRun(path.name, keys=list(keys), records=records))
        return runs

    monkeypatch.setattr(grading, "detect", lambda container=None: Level())
    monkeypatch.setattr(grading, "_grade_learner", learner)
    return ran


def gradebook(out: Path) -> dict[str, dict[str, str]]:
    import csv

    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        return {row["learner"]: {key.removeprefix("'"): value for key, value in row.items()}
                for row in csv.DictReader(stream)}


def small_class(root: Path) -> None:
    """ada: 03 all right, and 02 (not assigned); bob: 03 with two right, 05 handed in blank."""
    notebook(root / "ada" / "03_rtu_and_crc.ipynb")
    notebook(root / "ada" / "02_registers.ipynb")
    notebook(root / "bob" / "03_rtu_and_crc.ipynb")
    notebook(root / "bob" / "05_tcp_and_mbap.ipynb")


SMALL = {"ada/03_rtu_and_crc.ipynb": dict.fromkeys(KEYS_03, True),
         "ada/02_registers.ipynb": {"02.1": True, "02.2": False},
         "bob/03_rtu_and_crc.ipynb": {"03.1": True, "03.2": True, "03.3": False},
         "bob/05_tcp_and_mbap.ipynb": dict.fromkeys(KEYS_05)}


def test_the_grade_is_out_of_the_notebooks_assigned_and_the_rest_is_graded_not_counted(tmp_path, monkeypatch,
                                                                                        capsys):
    from modbus_edu.cli import main

    small_class(tmp_path / "class")
    fake_grading(monkeypatch, SMALL)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "class"), "--out", str(out), "-q", "--notebooks", "03,5"]) == 0
    printed = capsys.readouterr().out
    assert "The grade is out of the 10 exercise(s) of notebook(s) 03, 05 (--notebooks)." in printed
    assert "graded but not counted (beyond the assignment): 02.1, 02.2" in printed
    rows = gradebook(out)
    assert (rows["ada"]["right"], rows["ada"]["out of"]) == ("5", "10")  # 02.1 right, not counted
    assert (rows["bob"]["right"], rows["bob"]["out of"]) == ("2", "10")
    assert rows["ada"]["02.1 (not counted)"] == "right"
    assert rows["ada"]["05.1"] == "not handed in" and rows["bob"]["05.1"] == "not answered"
    assert rows["bob"]["03.5"] == "not answered"  # 03 handed in: blank, not "not handed in"
    assert (rows["ada"]["not handed in"], rows["bob"]["not answered"]) == ("5", "7")
    summary = html.unescape((out / "summary.html").read_text(encoding="utf-8"))
    assert "Graded but not counted (handed in beyond the assignment): 02.1 (1 learner(s)), 02.2" in summary
    pages = {page.name: page.read_text(encoding="utf-8") for page in (out / "learners").iterdir()}
    ada = pages["ada.html"]
    assert ada.count("<tr><td>") == 6  # 03.1 to 03.5, and notebook 05 in one row
    assert "05.1, 05.2, 05.3, 05.4, 05.5</td><td class='not'>not handed in" in ada
    assert "<td>02.1</td>" not in ada
    assert "Also graded, not counted (not in the assignment): 02.1 right" in ada
    saved = json.loads((out / "gradebook.json").read_text(encoding="utf-8"))
    assert saved["learners"]["ada"]["right"] == 5 and saved["learners"]["ada"]["out of"] == 10


def test_without_an_assignment_one_line_says_what_the_grade_is_out_of(tmp_path, monkeypatch, capsys):
    from modbus_edu.cli import main

    small_class(tmp_path / "class")
    fake_grading(monkeypatch, SMALL)
    assert main(["grade", str(tmp_path / "class"), "--out", str(tmp_path / "grades"), "-q"]) == 0
    line = ("No assignment given (--notebooks 00,01,03, or assignment.json beside the class): the grade is "
            "out of the 12 exercise(s) that the class's notebooks check, whoever handed them in.")
    assert line in capsys.readouterr().out
    assert line in html.unescape((tmp_path / "grades" / "summary.html").read_text(encoding="utf-8"))


def test_an_assignment_file_beside_the_class_gives_the_exercises_and_the_points(tmp_path, monkeypatch,
                                                                                 capsys):
    from modbus_edu.cli import main
    from modbus_edu.course.assignment import AssignmentError, read

    root = tmp_path / "moodle"
    notebook(root / "Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb")
    notebook(root / "Hal Jordan_9_assignsubmission_file_03_rtu_and_crc.ipynb")
    (root / "assignment.json").write_text('{"exercises": ["03.1", "03.2", "03.5", "03.4"], "points": 20}')
    answers = {"moodle/Ada Lovelace_12_assignsubmission_file_03_rtu_and_crc.ipynb":
               dict.fromkeys(KEYS_03, True),
               "moodle/Hal Jordan_9_assignsubmission_file_03_rtu_and_crc.ipynb": {"03.1": True, "03.3": True}}
    fake_grading(monkeypatch, answers)
    out = tmp_path / "grades"
    assert main(["grade", str(root), "--out", str(out), "-q", "--export", "moodle"]) == 0
    assert (f"The grade is out of the 4 exercise(s) of exercise(s) 03.1, 03.2, 03.4, 03.5 "
            f"({root / 'assignment.json'}).") in capsys.readouterr().out  # which file said so
    worksheet = (out / "moodle-import.csv").read_text(encoding="utf-8").splitlines()
    assert worksheet[1].startswith("Participant 9,Hal Jordan,,5.0,20,")  # 1 of 4 counted: 03.3 is not
    assert worksheet[2].startswith("Participant 12,Ada Lovelace,,20.0,20,")
    for bad, message in [('{"notebooks": ["03", "99"]}', "notebook 99 has no exercises"),
                         ('{"exercises": ["00.0"]}', "not exercises a grade can count"),
                         ('{"notebooks": "03"}', "are a list"), ("notebooks = 03", "cannot be read as JSON"),
                         ('{"notebooks": ["03"], "points": -1}', "points must be a number above 0")]:
        (tmp_path / "bad.json").write_text(bad)
        with pytest.raises(AssignmentError, match=message):
            read(tmp_path / "bad.json")


# --- the newest of two copies -----------------------------------------------------------------------------

def test_of_two_copies_with_equal_answers_the_newest_by_the_zips_time_counts_not_the_last_unpacked(tmp_path):
    from modbus_edu.course.runner import NotebookRun
    from modbus_edu.course.verdicts import pick_copies

    archive = tmp_path / "class" / "ada.zip"
    archive.parent.mkdir()
    with zipfile.ZipFile(archive, "w") as out:  # the newer copy first, the older one last
        out.writestr(zipfile.ZipInfo("03_rtu_and_crc-Copy1.ipynb", (2026, 11, 3, 10, 22, 0)), NOTEBOOK)
        out.writestr(zipfile.ZipInfo("03_rtu_and_crc.ipynb", (2026, 11, 1, 9, 0, 0)), NOTEBOOK)
    (tmp_path / "class" / "hal").mkdir()
    for name in ("03_rtu_and_crc.ipynb", "03_rtu_and_crc (1).ipynb"):  # the same time: the (1) is later
        notebook(tmp_path / "class" / "hal" / name, mtime=1_700_000_000)
    found = collect([tmp_path / "class"])
    try:
        graded = [(s, NotebookRun(s.path.name, keys=["03.1"], records=[{"key": "03.1", "ok": True,
                                                                         "message": "Right!"}]))
                  for s in found.submissions]
        chosen, choices = pick_copies(graded)
        assert [s.path.name for s, _ in chosen["ada"]] == ["03_rtu_and_crc-Copy1.ipynb"]
        assert "as many answers, and the newest: 2026-11-03 10:22:00 by the zip's or the file's time" \
            in choices["ada"][0]
        assert [s.path.name for s, _ in chosen["hal"]] == ["03_rtu_and_crc (1).ipynb"]
        assert "the later copy by its (1) mark" in choices["hal"][0]
    finally:
        found.cleanup()


# --- exports ----------------------------------------------------------------------------------------------

def test_a_wrong_export_stops_before_anything_is_graded(tmp_path, monkeypatch, capsys):
    from modbus_edu.cli import main

    small_class(tmp_path / "class")
    ran = fake_grading(monkeypatch, SMALL)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "class"), "--out", str(out), "-q", "--export", "canvas"]) == 1
    assert ran == [] and not out.exists()
    error = capsys.readouterr().err
    assert "none of the learners came from a Canvas download (they were gathered by hand)" in error
    assert "nothing was graded" in error


def test_a_finished_gradebook_exports_again_without_grading(tmp_path, monkeypatch, capsys):
    from modbus_edu.cli import main

    root = tmp_path / "canvas"
    notebook(root / "lovelaceada_12345_678901_03_rtu_and_crc.ipynb")
    notebook(root / "hoppergrace_23456_678903_03_rtu_and_crc.ipynb")
    ran = fake_grading(monkeypatch, {"canvas/lovelaceada_12345_678901_03_rtu_and_crc.ipynb":
                                     dict.fromkeys(KEYS_03, True),
                                     "canvas/hoppergrace_23456_678903_03_rtu_and_crc.ipynb": {"03.1": True}})
    out = tmp_path / "grades"
    assert main(["grade", str(root), "--out", str(out), "-q", "--notebooks", "03"]) == 0
    assert len(ran) == 2
    capsys.readouterr()
    assert main(["grade", "--from", str(out), "--export", "canvas", "--points", "20"]) == 0
    assert "grades out of 20" in capsys.readouterr().out
    assert len(ran) == 2  # nothing graded again
    lines = (out / "canvas-import.csv").read_text(encoding="utf-8").splitlines()
    assert lines == ["Student,ID,SIS User ID,SIS Login ID,Section,Modbus notebooks",
                     "    Points Possible,,,,,20.0", "hoppergrace,23456,,,,4.0", "lovelaceada,12345,,,,20.0"]
    assert main(["grade", "--from", str(out), "--export", "canvas", "--assignment", "4321"]) == 0
    assert (out / "canvas-import.csv").read_text(encoding="utf-8").splitlines()[0].endswith(
        ",Modbus notebooks (4321)")
    assert main(["grade", "--from", str(out)]) == 2  # --from without --export: nothing to do
    assert main(["grade", "--from", str(tmp_path), "--export", "moodle"]) == 1  # no gradebook there


def test_canvas_without_an_assignment_id_says_what_its_import_will_do(tmp_path, monkeypatch, capsys):
    from modbus_edu.cli import main

    notebook(tmp_path / "canvas" / "lovelaceada_12345_678901_03_rtu_and_crc.ipynb")
    fake_grading(monkeypatch, {})
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "canvas"), "--out", str(out), "-q", "--export", "canvas",
                 "--points", "15"]) == 0
    said = capsys.readouterr()
    assert ("Canvas: no assignment id (--assignment 4321, the number in the assignment's address), so its "
            "import fills the assignment titled exactly 'Modbus notebooks' if the course has one, else makes "
            "a new assignment 'Modbus notebooks' of 15 points possible, in a new Gradebook column"
            ) in said.err
    assert "no assignment id" not in said.out  # on stderr: the output stays the gradebook's
    lines = (out / "canvas-import.csv").read_text(encoding="utf-8").splitlines()
    assert lines[1] == "    Points Possible,,,,,15.0"  # the new assignment's points, as Canvas reads them
    assert main(["grade", str(tmp_path / "canvas"), "--out", str(out), "-q", "--export", "canvas",
                 "--assignment", "Notebooks (4321)"]) == 0
    assert "no assignment id" not in capsys.readouterr().err
    assert main(["grade", "--from", str(out), "--export", "canvas"]) == 0  # an export again says it too
    assert "else makes a new assignment 'Modbus notebooks' of 100 points possible" in capsys.readouterr().err


# --- identical answers --------------------------------------------------------------------------------

def test_byte_identical_answer_cells_are_flagged_for_the_instructor_never_as_a_verdict(tmp_path, monkeypatch):
    from modbus_edu.cli import main

    built = ("def crc16(data: bytes) -> int:\n    register = 0xFFFF\n    for byte in data:\n"
             "        register ^= byte\n        for _ in range(8):\n"
             "            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1\n"
             "    return register\n\n\ncheck('03.5', crc16)")
    own = built.replace("register", "crc")
    short = "answer = 0x4B37\ncheck('03.1', answer)"
    for learner, cell in (("ada", built), ("hal", built), ("cy", own), ("dee", built.replace("0xFFFF", "0"))):
        cell_notebook(tmp_path / "class" / learner / "03_rtu_and_crc.ipynb", [short, cell])
    answered = {"03.1": True, "03.5": True}
    fake_grading(monkeypatch, {f"{learner}/03_rtu_and_crc.ipynb": answered
                               for learner in ("ada", "hal", "cy")}
                 | {"dee/03_rtu_and_crc.ipynb": {"03.1": True, "03.5": False}})
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "class"), "--out", str(out), "-q"]) == 0
    summary = html.unescape((out / "summary.html").read_text(encoding="utf-8"))
    assert "Identical answers (for you to look at; never a verdict)" in summary
    assert f"03.5: the same answer cell, byte for byte ({len(built)} characters), from 2 learners: ada, hal" \
        in summary
    assert "03.1: the same" not in summary  # a short answer: what every right answer looks like
    rows = gradebook(out)
    assert rows["ada"]["03.5"] == rows["hal"]["03.5"] == "right" and not rows["ada"]["flags"]


# --- make grade -------------------------------------------------------------------------------------------

def test_make_grade_keeps_a_name_with_spaces_whole_and_exports():
    import subprocess

    root = Path(__file__).resolve().parents[1]
    # a make of its own: run under `make test`, MAKELEVEL would make it print its directory lines
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS")}
    shown = subprocess.run(["make", "--no-print-directory", "-n", "grade",
                            "SUBMISSIONS=MOD 101-Assignment 1-12345.zip", "OUT=my grades", "EXPORT=moodle",
                            "NOTEBOOKS=00,01,03"], cwd=root, env=env,
                           capture_output=True, text=True, timeout=60, check=True).stdout
    command = [line for line in shown.splitlines() if "modbus_edu grade" in line][-1]
    assert command.endswith("grade 'MOD 101-Assignment 1-12345.zip' --out 'my grades' --notebooks '00,01,03' "
                            "--export 'moodle'")
    quoted = subprocess.run(["make", "--no-print-directory", "-n", "grade", "SUBMISSIONS=Ada's work.zip"],
                            cwd=root, env=env, capture_output=True, text=True, timeout=60,
                            check=True).stdout.splitlines()[-1]
    assert quoted.endswith("grade 'Ada'\\''s work.zip' --out 'grades'")


def test_a_damaged_zip_is_an_archive_error_never_a_crash(tmp_path):
    """Bytes flipped anywhere in a zip (its directory, headers, data, a zip inside it), or the zip cut
    short: an :class:`~modbus_edu.course.archives.ArchiveError` or a refused entry, never another error."""
    import random

    inner = zipped(tmp_path / "inner.zip", {"03_rtu_and_crc.ipynb": NOTEBOOK}).read_bytes()
    source = zipped(tmp_path / "source.zip", {"ada/03_rtu_and_crc.ipynb": NOTEBOOK, "x.zip": inner,
                                              "hal/01_data_model.ipynb": NOTEBOOK * 50}).read_bytes()
    rng = random.Random(36)
    for case in range(400):
        data = bytearray(source)
        for _ in range(rng.randint(1, 8)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        if case % 5 == 0:
            data = data[:rng.randrange(len(data))]
        damaged = tmp_path / f"{case}.zip"
        damaged.write_bytes(bytes(data))
        try:
            archives.names(damaged)
            archives.unpack(damaged, tmp_path / f"out{case}")
        except archives.ArchiveError:
            pass
