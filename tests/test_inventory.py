"""The concept inventory (00.0 before the course, 17.0 after): its questions, its two orders, its scoring,
the class's normalised gain, the pre-test's silence about which answers are right, and the gradebook's
columns and gain table built from synthetic runs (no kernel)."""

from __future__ import annotations

import csv
import json
import random
import re
import runpy
from pathlib import Path

import pytest

from modbus_edu.course.reports import _write_csv, _write_summary, gain_shown
from modbus_edu.course.runner import NotebookRun, judged
from modbus_edu.course.verdicts import course_keys, inventory_marks, verdicts
from modbus_edu.errors import ModbusError
from modbus_edu.exercises import EXERCISES, check, evaluate, inventory, verdict
from modbus_edu.exercises.misconceptions import CATALOGUE
from modbus_edu.exercises.plain import plain, revive

ROOT = Path(__file__).resolve().parents[1]
PRE, POST = inventory.PRE, inventory.POST
LETTERS = inventory.LETTERS
N = len(inventory.QUESTIONS)


def letters_for(quiz: str, right: set[str], rng: random.Random) -> str:
    """An answer to ``quiz``: the right letter for the questions in ``right``, a wrong one (or ?) else."""
    out = []
    for qid in inventory.ORDERS[quiz]:
        good = inventory.BY_ID[qid].right
        out.append(good if qid in right else rng.choice([c for c in "abcd?" if c != good]))
    return "".join(out).upper()


def generated_class(seed: int = 27, learners: int = 10) -> dict[str, tuple[str, str]]:
    """Each learner's pre and post letters: question k is known before with a chance that falls with k,
    and after with a higher one; the last question is known by everyone before (g undefined)."""
    rng = random.Random(seed)
    ids = [q.id for q in inventory.QUESTIONS]
    answers = {}
    for n in range(learners):
        before = {qid for k, qid in enumerate(ids) if k == N - 1 or rng.random() < 0.6 - 0.04 * k}
        after = before | {qid for qid in ids if rng.random() < 0.6}
        answers[f"learner{n:02}"] = (letters_for(PRE, before, rng), letters_for(POST, after, rng))
    return answers


def test_the_questions_probe_at_least_six_misconceptions_of_the_catalogue():
    probes = {q.probes for q in inventory.QUESTIONS}
    assert 10 <= N <= 12 and len(probes) >= 6 and probes <= set(CATALOGUE)
    assert len({q.id for q in inventory.QUESTIONS}) == N
    for q in inventory.QUESTIONS:
        assert len(q.choices) == 4 and len(set(q.choices)) == 4 and q.right in "abcd"
    assert len({q.right for q in inventory.QUESTIONS}) == 4  # the right answer is not always one letter


def test_both_orders_are_permutations_of_the_same_questions_in_another_order():
    assert sorted(inventory.ORDER_PRE) == sorted(inventory.ORDER_POST) == sorted(inventory.BY_ID)
    assert inventory.ORDER_PRE != inventory.ORDER_POST
    assert inventory.key_letters(PRE) != inventory.key_letters(POST)


def test_the_worked_solutions_are_the_right_letters_in_each_order():
    for quiz in (PRE, POST):
        answer = runpy.run_path(str(ROOT / "notebooks" / EXERCISES[quiz].solution))["answer"]
        assert inventory.score(inventory.read(answer, quiz)) == {q: True for q in inventory.BY_ID}


def test_reading_letters_a_dict_and_question_marks():
    letters = inventory.key_letters(PRE)
    as_dict = {n: c.lower() for n, c in enumerate(letters, 1)}
    assert inventory.read(letters, PRE) == inventory.read(as_dict, PRE) == inventory.read(
        " ".join(letters.lower()), PRE)
    unknown = inventory.read("?" * N, PRE)
    assert set(unknown.values()) == {None} and not any(inventory.score(unknown).values())
    for bad in ("ABC", "E" * N, {0: "a"}, {1: "a"}, 12, {1: 3}):
        with pytest.raises(ModbusError):
            inventory.read(bad, PRE)
        assert evaluate(PRE, bad).ok is False


@pytest.fixture(autouse=True)
def kept_answers(tmp_path, monkeypatch):
    """Each test keeps the pre-test's letters in a folder of its own, never in the real home."""
    monkeypatch.setattr(inventory, "RECORD", tmp_path / "home" / "inventory.json")
    return inventory.RECORD


def test_the_pre_test_records_the_answers_and_says_nothing_of_which_are_right():
    rng = random.Random(5)
    messages = set()
    for _ in range(30):
        right = {qid for qid in inventory.BY_ID if rng.random() < 0.5}
        result = evaluate(PRE, letters_for(PRE, right, rng))
        assert result.ok is True and result.message.startswith(f"Recorded: your {N} answers")
        assert "right" not in result.message.split("Which are right", 1)[0]
        for q in inventory.QUESTIONS:  # no label, no count of right answers
            assert CATALOGUE[q.probes].label.lower() not in result.message.lower()
        messages.add(re.sub(r"\(\d+ marked \?\)", "", result.message))
    assert len(messages) == 1  # how many are right, and which, changes nothing in what the learner reads


def test_check_keeps_the_pre_test_and_the_post_test_shows_which_were_right_before(kept_answers, capsys):
    assert not kept_answers.exists()
    missing = check(POST, inventory.key_letters(POST)).message
    assert "not kept on this computer" in missing and "00.0" in missing
    evaluate(PRE, inventory.key_letters(PRE))
    assert not kept_answers.exists()  # evaluate (and the grader) judge only; check keeps
    pre = {qid: inventory.BY_ID[qid].right for qid in ("crc-order", "mbap-length")}
    letters = "".join(pre.get(qid, "?") for qid in inventory.ORDER_PRE)
    assert check(PRE, letters).ok is True
    assert json.loads(kept_answers.read_text())[PRE] == letters
    after = check(POST, inventory._wrong_at(POST, "reference"))
    numbers = sorted(inventory.ORDER_POST.index(qid) + 1 for qid in pre)
    assert after.ok is False and after.message.endswith(
        f"Before the course (exercise 00.0) you had 2 of {N} right: questions {numbers[0]}, {numbers[1]} "
        f"(numbered as here).")
    assert "Before the course" in capsys.readouterr().out
    check(PRE, "?" * N)
    assert check(POST, inventory.key_letters(POST)).message.endswith(f"you had 0 of {N} right.")


def test_every_wrong_choice_names_the_misconception_it_stands_for():
    for q in inventory.QUESTIONS:
        assert set(q.wrong) == set(LETTERS) - {q.right} and set(q.wrong.values()) <= set(CATALOGUE), q.id
        number = inventory.ORDER_POST.index(q.id) + 1
        for letter, key in q.wrong.items():
            letters = list(inventory.key_letters(POST))
            letters[number - 1] = letter
            message = evaluate(POST, "".join(letters)).message
            assert f"question {number} ({CATALOGUE[key].label})" in message, (q.id, letter)
    frame_end = inventory.BY_ID["frame-end"]
    assert CATALOGUE[frame_end.wrong["a"]].label != CATALOGUE["one-character-for-t35"].label  # CR LF
    assert frame_end.choices[0] == "CR LF"


def test_the_notebooks_ask_the_questions_the_inventory_scores():
    import nbformat

    for quiz, notebook in ((PRE, "00_welcome.ipynb"), (POST, "17_captures_and_security.ipynb")):
        cells = nbformat.read(ROOT / "notebooks" / notebook, as_version=4).cells
        assert any(cell.source.endswith(inventory.markdown(quiz)) for cell in cells), notebook


def test_no_keyed_choice_stands_out_by_its_length():
    for q in inventory.QUESTIONS:
        lengths = sorted(len(choice) for choice in q.choices)
        keyed = len(q.choices[LETTERS.index(q.right)])
        assert keyed < lengths[-1] or lengths[-1] - lengths[-2] <= 10, q.id


@pytest.mark.parametrize("answer", [inventory.key_letters(PRE), {n: c for n, c in
                                                                  enumerate(inventory.key_letters(PRE), 1)},
                                    "?" * N])
def test_an_answer_reaches_the_grader_as_plain_data_and_is_judged_the_same(answer):
    data = plain(answer)
    assert revive(data) == answer
    assert verdict(PRE, data) == evaluate(PRE, answer)


def test_the_normalised_gain_by_hand():
    ids = [q.id for q in inventory.QUESTIONS]
    # two learners: the first question right before for one, after for both (g = (1 - .5) / (1 - .5) = 1);
    # the second right before for both (g undefined); the others never right (g = 0)
    first = {q: q in (ids[0], ids[1]) for q in ids}
    second = {q: q == ids[1] for q in ids}
    after = {q: q in (ids[0], ids[1]) for q in ids}
    rows, overall = inventory.gains({"a": (first, after), "b": (second, after), "c": (first, None)})
    assert (rows[0].pre, rows[0].post, rows[0].g) == (0.5, 1.0, 1.0)
    assert (rows[1].pre, rows[1].g, rows[1].shown) == (1.0, None, "—")
    assert rows[2].g == 0.0 and rows[2].shown == "0.00"
    assert overall.pre == pytest.approx(1.5 / N) and overall.post == pytest.approx(2 / N)
    assert overall.g == pytest.approx((2 / N - 1.5 / N) / (1 - 1.5 / N))
    assert inventory.gains({"c": (first, None)}) == ([], None)


def test_the_gain_of_a_generated_class_against_a_hand_count():
    answers = generated_class()
    marks = {name: (inventory.score(inventory.read(pre, PRE)), inventory.score(inventory.read(post, POST)))
             for name, (pre, post) in answers.items()}
    rows, overall = inventory.gains(marks)
    for row in rows:
        at_pre, at_post = inventory.ORDER_PRE.index(row.question), inventory.ORDER_POST.index(row.question)
        good = inventory.BY_ID[row.question].right.upper()
        pre = sum(p[at_pre] == good for p, _ in answers.values()) / len(answers)
        post = sum(q[at_post] == good for _, q in answers.values()) / len(answers)
        assert (row.pre, row.post) == (pytest.approx(pre), pytest.approx(post))
        assert row.g == (None if pre == 1 else pytest.approx((post - pre) / (1 - pre)))
    assert rows[-1].g is None  # everyone knew the last question before
    assert 0 < overall.g < 1


def _run(notebook: str, key: str, answer) -> NotebookRun:
    return judged(NotebookRun(notebook, keys=[key], submissions=[{"key": key, "answer": plain(answer)}]))


def test_the_gradebook_reports_each_learners_scores_and_the_class_gain_per_question(tmp_path):
    answers = generated_class()
    answers["<b>eve</b>"] = (answers["learner00"][0], None)  # no post-test: a score before, none after
    runs = {}
    for name, (pre, post) in answers.items():
        runs[name] = [_run("00_welcome.ipynb", PRE, pre)]
        if post is not None:
            runs[name].append(_run("17_captures_and_security.ipynb", POST, post))
    # a 00.0 checked in another notebook counts for nothing
    runs["learner01"].append(_run("03_rtu_and_crc.ipynb", PRE, inventory.key_letters(PRE)))
    marks = {name: inventory_marks(found) for name, found in runs.items()}
    assert marks["<b>eve</b>"][POST] is None
    assert marks["learner01"][PRE] == inventory.score(inventory.read(answers["learner01"][0], PRE))

    chosen = {name: [(type("S", (), {"notebook": run.notebook})(), run) for run in found]
              for name, found in runs.items()}
    exercises, kept, _ = course_keys(chosen)
    assert PRE not in exercises and POST not in exercises  # scored in columns of their own, not as exercises
    table = {name: verdicts(kept[name]) for name in runs}
    flags = {name: [] for name in runs}
    _write_csv(tmp_path / "gradebook.csv", table, exercises, flags, marks)
    with (tmp_path / "gradebook.csv").open(encoding="utf-8") as stream:
        rows = {row["learner"]: row for row in csv.DictReader(stream)}
    for name, (pre, post) in answers.items():
        expected_pre = sum(inventory.score(inventory.read(pre, PRE)).values())
        assert (rows[name]["inventory pre"], rows[name]["inventory questions"]) == (str(expected_pre), str(N))
        right_after = None if post is None else sum(inventory.score(inventory.read(post, POST)).values())
        expected_post = "" if post is None else str(right_after)
        assert rows[name]["inventory post"] == expected_post

    summary = _write_summary(tmp_path, table, exercises, flags, marks=marks)
    page = (tmp_path / "summary.html").read_text(encoding="utf-8")
    expected, overall = inventory.gains({name: (m[PRE], m[POST]) for name, m in marks.items()})
    assert summary["inventory"] == [*expected, overall]
    assert "10 learners answered the twelve questions" in page
    for row in expected:
        numbers = " / ".join(str(order.index(row.question) + 1)
                             for order in (inventory.ORDER_PRE, inventory.ORDER_POST))
        assert (f"<td>{numbers}</td><td>{CATALOGUE[inventory.BY_ID[row.question].probes].label}</td>"
                f"<td>{row.pre:.0%}</td><td>{row.post:.0%}</td><td>{gain_shown(row)}</td>") in page
    assert "<td>—</td>" in page and f"Overall normalised gain: g = {overall.g:.2f}." in page
    assert "<b>eve</b>" not in page


def gain_table() -> str:
    """The generated class's gain table, as text (``python tests/test_inventory.py`` prints it)."""
    answers = generated_class()
    rows, overall = inventory.gains({
        name: (inventory.score(inventory.read(pre, PRE)), inventory.score(inventory.read(post, POST)))
        for name, (pre, post) in answers.items()})
    lines = [f"{'question':16} {'what it probes':46} {'pre':>5} {'post':>5} {'g':>5}"]
    lines += [f"{row.question:16} {row.label:46} {row.pre:5.0%} {row.post:5.0%} {row.shown:>5}"
              for row in [*rows, overall]]
    return "\n".join(lines)


if __name__ == "__main__":
    print(gain_table())
