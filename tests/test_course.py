"""The course itself: notebook conventions, exercises and their checkers, and the pinned environment."""

from __future__ import annotations

import re
import runpy
from pathlib import Path

import pytest

from modbus_edu import course, exercises

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
SOLUTIONS = NOTEBOOKS / "solutions"
NOTEBOOK_FILES = course.course_notebooks(NOTEBOOKS)


def test_the_notebooks_are_numbered_in_order_without_gaps():
    numbers = [int(path.name[:2]) for path in NOTEBOOK_FILES]
    assert numbers == list(range(len(numbers))) and len(numbers) >= 14


@pytest.mark.parametrize("path", NOTEBOOK_FILES, ids=lambda p: p.name)
def test_notebook_conventions(path):
    problems = course.check_notebook(path, last=path == NOTEBOOK_FILES[-1])
    assert not problems, "\n".join(map(str, problems))


def test_no_source_shorthand_in_the_prose_of_notebooks_01_on():
    left = {path.name: course.source_shorthands(path) for path in NOTEBOOK_FILES[1:]}
    assert not any(left.values()), {name: found for name, found in left.items() if found}


def test_every_library_name_is_introduced_before_it_is_used():
    problems = course.used_before_introduced(NOTEBOOK_FILES)
    assert not problems, "\n".join(map(str, problems))


def test_the_introduction_check_finds_a_name_used_first(tmp_path):
    import nbformat

    def write(name, cells):
        notebook = nbformat.v4.new_notebook()
        notebook.cells = cells
        nbformat.write(notebook, tmp_path / name)
        return tmp_path / name

    first = write("00_a.ipynb", [nbformat.v4.new_markdown_cell("A `Master` runs transactions."),
                                 nbformat.v4.new_code_cell("master = mb.Master(link)\nmb.Slave(unit=1)")])
    second = write("01_b.ipynb", [nbformat.v4.new_code_cell(
        "from modbus_edu.widgets import TestTool  # the TestTool panel\nmb.Master\nmb.Slave")])
    messages = [str(problem) for problem in course.used_before_introduced([first, second])]
    assert messages == ["00_a.ipynb: cell 1 uses Slave before the course introduces it "
                        "(name it in the prose or a comment first)"]


def test_every_notebook_from_01_has_a_build_exercise():
    with_build = {key[:2] for key, item in exercises.EXERCISES.items() if item.kind == "build"}
    missing = [path.name for path in NOTEBOOK_FILES[1:] if path.name[:2] not in with_build]
    assert not missing, f"no build exercise in {missing}"


def test_no_committed_output_shows_a_hint_for_an_unanswered_exercise():
    import nbformat

    for path in NOTEBOOK_FILES:
        for cell in nbformat.read(path, as_version=4).cells:
            for output in cell.get("outputs", []):
                text = output.get("text", "")
                text = text if isinstance(text, str) else "".join(text)
                if "not answered yet" in text:
                    assert "Hint" not in text, f"{path.name} shows a hint before any attempt: {text!r}"


def test_course_check_reports_a_broken_notebook(tmp_path):
    import nbformat

    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_markdown_cell("Intro without a title"),
                      nbformat.v4.new_code_cell("1 + 1", execution_count=2),
                      nbformat.v4.new_markdown_cell("[gone](99_missing.ipynb)")]
    notebook.metadata["kernelspec"] = {"name": "other"}
    path = tmp_path / "00_broken.ipynb"
    nbformat.write(notebook, path)
    messages = "\n".join(str(problem) for problem in course.check_notebook(path))
    for expected in ("kernelspec", "execution counts", "title", "What you will learn", "What you need",
                     "Summary", "Exercises", "check()", "99_missing.ipynb", "next notebook"):
        assert expected in messages


def _used_keys() -> dict[str, str]:
    import nbformat

    used = {}
    for path in NOTEBOOK_FILES:
        for cell in nbformat.read(path, as_version=4).cells:
            if cell.cell_type == "code":
                for key in re.findall(r"check\(\s*[\"'](\d\d\.\d+)[\"']", cell.source):
                    used[key] = path.name
    return used


def test_every_exercise_is_used_and_every_used_exercise_exists():
    used = _used_keys()
    assert set(used) == set(exercises.EXERCISES), (
        f"registered but unused: {sorted(set(exercises.EXERCISES) - set(used))}; "
        f"used but unregistered: {sorted(set(used) - set(exercises.EXERCISES))}")


def test_every_notebook_has_two_exercises():
    per_notebook: dict[str, int] = {}
    for key in exercises.EXERCISES:
        per_notebook[key[:2]] = per_notebook.get(key[:2], 0) + 1
    assert {path.name[:2] for path in NOTEBOOK_FILES} == set(per_notebook)
    assert all(count >= 2 for count in per_notebook.values()), per_notebook


@pytest.mark.parametrize("key", sorted(exercises.EXERCISES))
def test_solution_passes_and_wrong_answer_fails(key):
    path = SOLUTIONS / f"{key.replace('.', '_')}.py"
    assert path.exists(), f"no solution file {path.name}"
    answer = runpy.run_path(str(path))["answer"]
    result = exercises.evaluate(key, answer)
    assert result.ok is True, result.message
    wrong = exercises.evaluate(key, exercises.EXERCISES[key].wrong)
    assert wrong.ok is False, f"the checker of {key} accepted a wrong answer"
    assert wrong.message.startswith("Not yet:")


def test_unanswered_exercise_says_so_without_a_hint_and_raises_nothing(capsys):
    key = sorted(exercises.EXERCISES)[0]
    result = exercises.check(key, ...)
    assert result.ok is None and not result
    out = capsys.readouterr().out
    assert "not answered yet" in out and "Hint" not in out


BUILD_KEYS = sorted(key for key, item in exercises.EXERCISES.items() if item.kind == "build")


def _raises(*args):
    raise RuntimeError("not written yet")


class _Junk:
    def __eq__(self, other):
        raise RuntimeError("junk")


@pytest.mark.parametrize("key", BUILD_KEYS)
def test_build_checkers_refuse_functions_that_raise_or_return_junk(key):
    for function in (_raises, lambda *args: _Junk(), lambda *args: "junk"):
        result = exercises.evaluate(key, function)
        assert result.ok is False and result.message.startswith("Not yet:"), result.message


def test_unknown_exercise_key_is_reported():
    assert exercises.evaluate("99.9", 1).ok is False
