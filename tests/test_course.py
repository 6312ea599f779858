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


# --- course integrity: the map, the links, quoted frames, sources ---------------------------------------

def _notebook(folder: Path, name: str, *cells) -> Path:
    """A small notebook in ``folder``: each cell is ("md", text) or ("code", source[, printed output])."""
    import nbformat

    notebook = nbformat.v4.new_notebook()
    for kind, text, *output in cells:
        if kind == "md":
            notebook.cells.append(nbformat.v4.new_markdown_cell(text))
        else:
            cell = nbformat.v4.new_code_cell(text)
            if output:
                cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text=output[0])]
            notebook.cells.append(cell)
    nbformat.write(notebook, folder / name)
    return folder / name


WHERE = "## Where this comes from\n\nThe specification.\n\n"


@pytest.fixture
def small_course(tmp_path):
    """Three notebooks that pass every integrity check, and a README listing them."""
    folder = tmp_path / "notebooks"
    folder.mkdir()
    _notebook(folder, "00_welcome.ipynb", ("md", "# 0. Welcome: Modbus by doing"),
              ("md", "## The map\n\n| notebook |\n|---|\n| [00 Welcome](00_welcome.ipynb) |\n"
                     "| [01 Frames](01_frames.ipynb) |\n| [02 The end](02_the_end.ipynb) |"),
              ("md",
               "## Sources\n\nThe robot test-tool paper, the power-meter paper, the Arduino slave paper, "
                     "an article.\n\n**Next:** [01 Frames](01_frames.ipynb)"))
    _notebook(folder, "01_frames.ipynb", ("md", "# 1. Frames: bytes on a wire"),
              ("md",
               "The request `01 03 00 00 00 01 84 0A` reads one register; the spec's `11 03 00 6B 00 03` "
                     "reads three. A published example (the power-meter paper) is "
                     "`01 03 00 00 00 0A C5 CD`."),
              ("code", 'frame = bytes.fromhex("01 03 00 00 00 01 84 0A")\nprint(mb.explain(other))',
               "01 03 00 00 00 0A C5 CD\n"),
              ("md", WHERE + "the power-meter paper, the article, the paper, the paper.\n\n"
                     "**Next:** [02 The end](02_the_end.ipynb)"))
    _notebook(folder, "02_the_end.ipynb", ("md", "# 2. The end"),
              ("md", "This last notebook closes the course; you have reached the end of the course."),
              ("md", WHERE + "[Back to the start](00_welcome.ipynb)"))
    (tmp_path / "README.md").write_text("| # | notebook |\n|---|---|\n"
                                        "| 0 | [Welcome](notebooks/00_welcome.ipynb) |\n"
                                        "| 1 | [Frames](notebooks/01_frames.ipynb) |\n"
                                        "| 2 | [The end](notebooks/02_the_end.ipynb) |\n")
    return folder


def _messages(problems) -> str:
    return "\n".join(map(str, problems))


def test_a_course_that_follows_every_rule_passes_the_integrity_checks(small_course):
    assert course.check_integrity(small_course) == []


def test_the_map_and_the_readme_list_exactly_the_notebooks_with_their_titles(small_course):
    from modbus_edu.course import check

    _notebook(small_course, "03_more.ipynb", ("md", "# 3. More"), ("md", WHERE))
    notebooks = course.course_notebooks(small_course)
    readme = small_course.parent / "README.md"
    assert "it does not list 03_more.ipynb" in _messages(check.map_problems(notebooks))
    assert "it does not list 03_more.ipynb" in _messages(check.readme_problems(readme, notebooks))
    readme.write_text(readme.read_text().replace("[Frames]",
                                                 "[Framing]") + "| 3 | [More](notebooks/03_more.ipynb) |\n"
                      "| 4 | [Gone](notebooks/04_gone.ipynb) |\n")
    messages = _messages(check.readme_problems(readme, notebooks))
    assert "it calls 01_frames.ipynb 'Framing', but its title is 'Frames: bytes on a wire'" in messages
    assert "it lists 04_gone.ipynb, which does not exist" in messages


def test_every_next_link_names_the_next_notebook_and_only_the_last_calls_itself_the_last(small_course):
    from modbus_edu.course import check

    path = small_course / "01_frames.ipynb"
    _notebook(small_course, "01_frames.ipynb", ("md", "# 1. Frames: bytes on a wire"),
              ("md",
               "This last notebook of the course... " + WHERE + "**Next:** [02 Welcome](02_the_end.ipynb)"))
    messages = _messages(check.next_link_problems(course.course_notebooks(small_course)))
    assert "01_frames.ipynb: its 'Next' link says '02 Welcome'; the next notebook is 'The end'" in messages
    assert "01_frames.ipynb: it calls itself the last ('This last notebook')" in messages
    assert not any(line.startswith("02_the_end") for line in messages.splitlines())
    _notebook(small_course, path.name, ("md", "# 1. Frames"), ("md", "Next: [00 Welcome](00_welcome.ipynb)"))
    assert "its 'Next' link goes to 00_welcome.ipynb, not 02_the_end.ipynb" in _messages(
        check.next_link_problems(course.course_notebooks(small_course)))


def test_no_markdown_link_sits_in_a_code_cell(tmp_path):
    from modbus_edu.course import check

    path = _notebook(tmp_path, "05_x.ipynb", ("code",
                                              "# from [the paper](00_welcome.ipynb#Sources)\nx = a[0](1)"))
    assert [p.message for p in check.links_in_code(path)] == [
        "cell 0 is code but holds the markdown link '[the paper](00_welcome.ipynb#Sources)'"]


def test_every_quoted_frame_is_shown_by_a_cell_or_is_a_named_specification_example(tmp_path):
    from modbus_edu.course import check

    path = _notebook(
        tmp_path, "03_x.ipynb",
        ("md", "`01 03 00 00 00 01 84 0A` and `11 03 00 6B 00 03 76 87` (the specification's), `76 87` too; "
               "FC 16 and the orders CD AB are no frames; `01 03 04 00 03 55 71` is shown nowhere, nor is "
               ":050310000002E6; but `04 D2`, `84 0A` and `AB CD EF` are."),
        ("md", "**Exercise 03.3.** Will the slave answer `11 03 00 6B 00 03 76 86`?"),
        ("code", "print(b'\\x01\\x03\\x00\\x00\\x00\\x01\\x84\\x0a')\nvalue = 0x04D2\nword = 0xABCDEF"))
    messages = [p.message for p in check.unshown_frames(path)]
    assert messages == [
        "the prose quotes the bytes 01 03 04 00 03 55 71 but no cell shows them (or name it a specification "
        "example)", "the prose quotes the frame :050310000002E6 but no cell shows it"]


def test_the_prose_names_a_source_at_most_three_times_and_never_an_unseen_table(tmp_path):
    from modbus_edu.course import check

    path = _notebook(tmp_path, "04_x.ipynb",
                     ("md", "The Inst Tools ASCII article shows it; the paper too. CodeProject's master, an "
                            "article, and its Table 3."),
                     ("md", WHERE + "The Inst Tools ASCII article, the paper, the article, the paper."))
    assert check.source_mentions(path) == ["The Inst Tools ASCII article", "paper", "CodeProject", "article"]
    messages = [p.message for p in check.source_problems(path)]
    assert messages[0].startswith("its prose names a source 4 times (at most 3")
    assert "'its Table 3' points to a table or figure the learner cannot see" in messages[1]


def test_no_panel_picture_names_a_source_s_table(tmp_path):
    import nbformat

    from modbus_edu.course import check

    def with_picture(name: str, text: str) -> Path:
        path = _notebook(tmp_path, name, ("code", "dashboard"))
        notebook = nbformat.read(path, as_version=4)
        notebook.cells[0].outputs = [nbformat.v4.new_output(
            "execute_result", execution_count=1, data={
                "text/plain": "[panel]",
                "text/html": f'<div class="mbe-picture"><b>Power meter dashboard</b> &mdash; {text}</div>'
                             "<table><tr><td>1</td></tr></table>"})]
        nbformat.write(notebook, path)
        return path

    bad = with_picture("10_a.ipynb", "the power-meter paper's Table 5, read with function 03")
    messages = [p.message for p in check.panel_problems(bad)]
    assert messages == ["cell 0: a panel names 'Table 5', 'the power-meter paper', which the learner never "
                        "sees: say what it shows"]
    assert check.panel_problems(with_picture("10_b.ipynb", "the meter's register map, read with function "
                                                           "03")) == []


def test_every_worked_solution_ends_with_its_own_check(tmp_path):
    from modbus_edu.course import check

    right = 'from modbus_edu.exercises import check\n\nanswer = 1\ncheck("02.5", answer)\n'
    (tmp_path / "02_5.py").write_text(right)
    (tmp_path / "03_1.py").write_text("answer = 2\nprint(answer)\n")          # %load would lose the check
    (tmp_path / "03_2.py").write_text('answer = 3\ncheck("03.1", answer)\n')   # another exercise's check
    (tmp_path / "04_1.py").write_text('check("04.1", answer)\nanswer = 4\n')   # not at the end
    assert [(p.notebook, p.message) for p in check.solution_problems(tmp_path)] == [
        (f"solutions/{name}.py", f'it does not end with check("{key}", ...): %load replaces the cell, its '
                                 "check included")
        for name, key in (("03_1", "03.1"), ("03_2", "03.2"), ("04_1", "04.1"))]
    assert check.solution_problems(NOTEBOOKS / "solutions") == []


def test_every_notebook_has_a_where_this_comes_from_box_before_its_next_link(tmp_path):
    from modbus_edu.course import check

    missing = _notebook(tmp_path, "06_x.ipynb", ("md", "# 6. X\n\n**Next:** [07 Y](07_y.ipynb)"))
    late = _notebook(tmp_path, "07_y.ipynb", ("md", "**Next:** [08 Z](08_z.ipynb)"), ("md", WHERE))
    fine = _notebook(tmp_path, "08_z.ipynb",
                     ("md", "**Where this comes from**: the specification.\n\nNext: [x](09_a.ipynb)"))
    assert [p.message for p in check.where_box_problems(missing)] == [
        "it has no 'Where this comes from' section"]
    assert [p.message for p in check.where_box_problems(late)] == [
        "its 'Where this comes from' section comes after its Next link"]
    assert check.where_box_problems(fine) == []


def test_the_integrity_checks_are_part_of_the_course_check(small_course, capsys):
    from modbus_edu.course.__main__ import main

    _notebook(small_course, "01_frames.ipynb", ("md", "# 1. Frames"), ("code", "# see [x](https://example.org)"))
    assert main(["check", str(small_course)]) == 1
    assert "cell 1 is code but holds the markdown link" in capsys.readouterr().out


def test_whole_course_passes_the_integrity_checks():
    problems = course.check_integrity(NOTEBOOKS, ROOT / "README.md")
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(map(str, problems))


def test_re_execution_stores_what_a_cell_printed_as_one_output_per_stream():
    from modbus_edu.course.execute import coalesce_streams

    outputs = [{"output_type": "stream", "name": "stdout", "text": "echo:"},
               {"output_type": "stream", "name": "stdout", "text": [" A5 37\n"]},
               {"output_type": "stream", "name": "stderr", "text": "warning\n"},
               {"output_type": "display_data", "data": {"text/plain": "x"}, "metadata": {}},
               {"output_type": "stream", "name": "stdout", "text": "after\n"}]
    merged = coalesce_streams(outputs)
    assert [o.get("name") for o in merged] == ["stdout", "stderr", None, "stdout"]
    assert merged[0]["text"] == "echo: A5 37\n"
