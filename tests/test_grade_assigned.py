"""The grade the instructor assigned, in points: points per exercise or per notebook from the assignment
file, the grade out of their total, and the platforms' imports as each platform reads them (Canvas's
Points Possible row, Moodle's worksheet in the language of the page it is uploaded from).  No kernel:
the grading is faked as in test_grade_handins."""

from __future__ import annotations

import csv
import html
import json

import pytest
from test_grade_handins import KEYS_03, KEYS_05, fake_grading, gradebook, notebook

from modbus_edu.course.assignment import AssignmentError, read
from modbus_edu.course.export import MOODLE_WORDS, ExportError, export
from modbus_edu.course.submissions import Identity

MOODLE = "moodle/{}_assignsubmission_file_{}.ipynb"


def moodle_class(root, answers: dict[str, dict[str, dict[str, bool | None]]]) -> dict:
    """A flat Moodle download: learner ("Ada Lovelace_12") -> notebook title -> the keys its run checks."""
    faked = {}
    for learner, books in answers.items():
        for title, keys in books.items():
            notebook(root / MOODLE.format(learner, title))
            faked[MOODLE.format(learner, title)] = keys
    return faked


def test_points_per_exercise_and_per_notebook_make_the_grade_and_every_page_says_out_of_what(
        tmp_path, monkeypatch, capsys):
    from modbus_edu.cli import main

    # 03.1 is worth 1, 03.5 is worth 4; notebook 05 is worth 10, 2 for each of its 5 exercises: 15 in all
    (tmp_path / "moodle").mkdir()
    (tmp_path / "moodle" / "assignment.json").write_text(json.dumps(
        {"exercises": {"03.1": 1, "03.5": 4}, "notebooks": {"05": 10}}))
    faked = moodle_class(tmp_path, {
        # ada: 03.5 and 05.1 right (4 + 2 = 6 of 15), 03.2 right but not assigned, 05 otherwise blank
        "Ada Lovelace_12": {"03_rtu_and_crc": {"03.1": False, "03.2": True, "03.5": True},
                            "05_tcp_and_mbap": {"05.1": True, "05.2": None}},
        # hal: 03.1 right only (1 of 15); notebook 05 not handed in
        "Hal Jordan_9": {"03_rtu_and_crc": {"03.1": True, "03.5": False}}})
    fake_grading(monkeypatch, faked)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "moodle"), "--out", str(out), "-q", "--export", "moodle"]) == 0
    printed = capsys.readouterr().out
    line = (f"The grade is out of 15 points, the points of the 7 exercise(s) of exercise(s) 03.1, 03.5, "
            f"05.1, 05.2, 05.3, 05.4, 05.5 ({tmp_path / 'moodle' / 'assignment.json'}).")
    assert line in printed
    assert "graded but not counted (beyond the assignment): 03.2" in printed
    assert "grades out of 15" in printed  # no "points" in the file: the platform's grade is the total

    rows = gradebook(out)
    ada, hal = rows["Ada Lovelace"], rows["Hal Jordan"]
    assert (ada["right"], ada["out of"], ada["points"], ada["points out of"]) == ("2", "7", "6", "15")
    assert (hal["right"], hal["out of"], hal["points"], hal["points out of"]) == ("1", "7", "1", "15")
    assert ada["03.2 (not counted)"] == "right" and hal["05.1"] == "not handed in"

    summary = html.unescape((out / "summary.html").read_text(encoding="utf-8"))
    assert line in summary
    assert "Graded but not counted (handed in beyond the assignment): 03.2 (2 learner(s))" in summary
    with (out / "summary.csv").open(encoding="utf-8", newline="") as stream:
        worth = {row["exercise"].lstrip("'"): (row["counted"], row["points"])
                 for row in csv.DictReader(stream)}
    assert worth["03.5"] == ("yes", "4") and worth["05.3"] == ("yes", "2") and worth["03.2"] == ("no", "0")

    pages = [html.unescape(page.read_text(encoding="utf-8")) for page in (out / "learners").iterdir()]
    page = next(text for text in pages if "Feedback for Ada Lovelace" in text)
    assert f"2 of 7 exercises right: 6 of 15 points. {line}" in page
    assert "<td>03.5 (4 pt)</td>" in page and "<td>05.1 (2 pt)</td>" in page
    assert "Also graded, not counted (not in the assignment): 03.2 right" in page

    with (out / "moodle-import.csv").open(encoding="utf-8", newline="") as stream:
        worksheet = {row["Identifier"]: row for row in csv.DictReader(stream)}
    ada_row = worksheet["Participant 12"]
    assert (ada_row["Grade"], ada_row["Maximum grade"]) == ("6.0", "15.0")
    assert worksheet["Participant 9"]["Grade"] == "1.0"
    assert worksheet["Participant 12"]["Feedback comments"] == \
        "2 of 7 exercises right, 6 of 15 points (modbus-edu grade)"

    # the same gradebook exported again, out of the platform's 20 points: the share of the points kept
    saved = json.loads((out / "gradebook.json").read_text(encoding="utf-8"))
    assert (saved["learners"]["Ada Lovelace"]["points"], saved["learners"]["Ada Lovelace"]["points out of"]) \
        == (6, 15)
    assert main(["grade", "--from", str(out), "--export", "moodle", "--points", "20"]) == 0
    with (out / "moodle-import.csv").open(encoding="utf-8", newline="") as stream:
        again = {row["Identifier"]: row["Grade"] for row in csv.DictReader(stream)}
    assert again == {"Participant 9": "1.33", "Participant 12": "8.0"}


def test_the_points_in_the_file_scale_the_grade_and_a_list_counts_one_point_each(tmp_path):
    path = tmp_path / "assignment.json"
    path.write_text(json.dumps({"notebooks": {"03": 10, "5": 5}, "points": 20}))
    assignment = read(path)
    assert assignment.notebooks == ("03", "05")
    assert [assignment.weight(key) for key in KEYS_03 + KEYS_05] == [2.0] * 5 + [1.0] * 5
    assert (assignment.total, assignment.maximum(), assignment.weight("02.1")) == (15.0, 20, 0.0)
    path.write_text(json.dumps({"notebooks": ["03"], "exercises": {"05.5": 3}}))
    both = read(path)
    assert both.exercises == (*KEYS_03, "05.5") and (both.total, both.maximum()) == (8.0, 8.0)
    path.write_text(json.dumps({"notebooks": ["03", "05"]}))  # a list, as before: no points per exercise
    plain = read(path)
    assert (plain.weights, plain.total, plain.maximum()) == ((), 10.0, None)
    assert plain.line() == f"The grade is out of the 10 exercise(s) of notebook(s) 03, 05 ({path})."
    for bad, message in [({"notebooks": ["03"], "exercises": {"03.5": 4}}, "03.5 counted twice"),
                         ({"exercises": {"03.5": 0}}, "03.5 is worth 0"),
                         ({"exercises": {"03.5": "4"}}, "03.5 is worth '4'"),
                         ({"notebooks": {"03": True}}, "notebook 03 is worth True"),
                         ({"notebooks": {"99": 4}}, "notebook 99 has no exercises"),
                         ({"exercises": {"00.0": 4}}, "not exercises a grade can count"),
                         ({"notebooks": {}, "exercises": []}, "no notebook and no exercise given")]:
        path.write_text(json.dumps(bad))
        with pytest.raises(AssignmentError, match=message):
            read(path)


# --- Moodle's worksheet in the language of the upload page --------------------------------------------------

PEOPLE = {"Ada Lovelace": Identity("moodle", "12", "Ada Lovelace"), "Hal Jordan": Identity("moodle", "9",
                                                                                          "Hal Jordan")}


@pytest.mark.parametrize("language, header, identifier", [
    ("en", ["Identifier", "Full name", "Email address", "Grade", "Maximum grade", "Last modified (grade)",
            "Feedback comments"], "Participant 12"),
    ("fr", ["Identifiant", "Nom complet", "Adresse de courriel", "Note", "Note maximale",
            "Dernière modification (note)", "Feedback par commentaires"], "Participant12"),
    ("de", ["ID", "Vollständiger Name", "E-Mail-Adresse", "Bewertung", "Bestwertung",
            "Zuletzt geändert (Bewertung)", "Feedback als Kommentar"], "Teilnehmer/in12"),
    ("es", ["Identificador", "Nombre completo", "Dirección de correo", "Calificación", "Calificación máxima",
            "Última modificación (calificación)", "Comentarios de retroalimentación"], "Participante12"),
])
def test_moodles_worksheet_is_written_in_the_language_its_import_matches(tmp_path, language, header,
                                                                         identifier):
    """Moodle's import finds the columns by get_string('recordid' / 'gradenoun' / 'lastmodifiedgrade') of
    the uploader's language and strips strlen(get_string('hiddenuser')) characters from each identifier:
    the strings are Moodle's English and its 4.5 language packs', the participant id must survive."""
    path = tmp_path / f"{language}.csv"
    export(path, "moodle", {"Ada Lovelace": (3, 4), "Hal Jordan": (1, 4)}, PEOPLE, points=20,
           language=language)
    with path.open(encoding="utf-8", newline="") as stream:
        written, *rows = list(csv.reader(stream))
    assert written == header
    assert [row[0] for row in rows] == [identifier.replace("12", "9"), identifier]
    hidden = MOODLE_WORDS[language][-1]
    assert [row[0][len(hidden):] for row in rows] == ["9", "12"]  # what Moodle's importer keeps: the id
    assert [row[3] for row in rows] == ["5.0", "15.0"]  # a point: every pack's unformat_float reads it


def test_the_language_is_asked_on_the_command_line_and_an_unknown_one_is_refused(tmp_path, monkeypatch,
                                                                                   capsys):
    from modbus_edu.cli import main

    faked = moodle_class(tmp_path, {"Ada Lovelace_12": {"03_rtu_and_crc": dict.fromkeys(KEYS_03, True)}})
    fake_grading(monkeypatch, faked)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "moodle"), "--out", str(out), "-q", "--export", "moodle",
                 "--language", "fr"]) == 0
    assert (out / "moodle-import.csv").read_text(encoding="utf-8").startswith("Identifiant,Nom complet,")
    assert main(["grade", "--from", str(out), "--export", "moodle", "--language", "de"]) == 0
    assert (out / "moodle-import.csv").read_text(encoding="utf-8").splitlines()[1].startswith(
        "Teilnehmer/in12,Ada Lovelace,,100.0,100,")
    assert main(["grade", "--from", str(out), "--export", "moodle", "--language", "xx"]) == 2
    assert "invalid choice: 'xx' (choose from 'en', 'fr', 'de', 'es')" in capsys.readouterr().err
    with pytest.raises(ExportError, match="no Moodle worksheet in 'xx'"):
        export(tmp_path / "x.csv", "moodle", {"Ada Lovelace": (1, 1)}, PEOPLE, language="xx")


def test_teaching_prints_the_worksheet_words_the_export_writes():
    from pathlib import Path

    guide = (Path(__file__).resolve().parents[1] / "TEACHING.md").read_text(encoding="utf-8")
    for language, words in MOODLE_WORDS.items():
        identifier, _, _, grade, _, modified, comments, participant = words
        row = (f"| `{language}` | `{identifier}` = `{participant}12345` | `{grade}` | `{modified}` | "
               f"`{comments}` |")
        assert row in guide, row


# --- rows and pages keyed by the platform's id ----------------------------------------------------------

def test_a_learner_named_like_a_disambiguated_classmate_gets_a_page_and_a_worksheet_row_of_their_own(
        tmp_path, monkeypatch):
    from modbus_edu.cli import main

    faked = moodle_class(tmp_path, {name: {"05_tcp_and_mbap": {"05.1": index == 0}}
                                    for index, name in enumerate(("Sam Lee_21", "Sam Lee_7654321",
                                                                  "Sam Lee (21)_555"))})
    fake_grading(monkeypatch, faked)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "moodle"), "--out", str(out), "-q", "--export", "moodle"]) == 0
    titles = sorted(html.unescape(page.read_text(encoding="utf-8")).split("<title>")[1].split("</title>")[0]
                    for page in (out / "learners").iterdir())
    assert titles == ["Feedback for Sam Lee (21) (555)", "Feedback for Sam Lee (7654321)",
                      "Feedback for Sam Lee (Moodle 21)"]
    assert sorted(gradebook(out)) == ["Sam Lee (21) (555)", "Sam Lee (7654321)", "Sam Lee (Moodle 21)"]
    with (out / "moodle-import.csv").open(encoding="utf-8", newline="") as stream:
        worksheet = {row["Identifier"]: row["Grade"] for row in csv.DictReader(stream)}
    assert worksheet == {"Participant 21": "100.0", "Participant 555": "0.0", "Participant 7654321": "0.0"}
