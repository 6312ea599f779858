"""The gradebook, over a generated class of six learners: every learner gets the row their real answers
earn, whatever their notebooks do to the kernel or to ``check``."""

from __future__ import annotations

import csv
from pathlib import Path

import nbformat
import pytest

from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.exercises import EXERCISES

ROOT = Path(__file__).resolve().parents[1]
SOLUTIONS = ROOT / "notebooks" / "solutions"
NOTEBOOKS = {"01_data_model": ["01.1", "01.2"], "03_rtu_and_crc": ["03.1", "03.2", "03.5"],
             "05_tcp_and_mbap": ["05.1", "05.2"]}
KEYS = [key for keys in NOTEBOOKS.values() for key in keys]
SETUP = "import modbus_edu as mb\nfrom modbus_edu.exercises import check"
TEMPLATE = {"value": "answer = ...  # replace ... with your answer\ncheck({key!r}, answer)",
            "build": "def crc16(data: bytes) -> int:\n    ...  # your code here\n\n\ncheck({key!r}, crc16)"}
ARC = """def crc16(data: bytes) -> int:
    register = 0
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register
answer = crc16"""


def right(key: str) -> str:
    return (SOLUTIONS / f"{key.replace('.', '_')}.py").read_text()  # it ends with its own check


def wrong(key: str) -> str:
    if key == "03.5":
        return ARC + f"\ncheck({key!r}, answer)"
    return f"answer = {EXERCISES[key].wrong!r}\ncheck({key!r}, answer)"


def template(key: str) -> str:
    return TEMPLATE[EXERCISES[key].kind].format(key=key)


def write(folder: Path, name: str, cells: list[str]) -> None:
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_markdown_cell(f"# {name}"), *map(nbformat.v4.new_code_cell, cells)]
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    folder.mkdir(parents=True, exist_ok=True)
    nbformat.write(notebook, folder / f"{name}.ipynb")


def make_class(root: Path) -> dict[str, dict[str, str]]:
    """Six learners' notebooks; returns the row each one's real answers earn."""
    expected: dict[str, dict[str, str]] = {}

    def learner(name: str, answer, extra: dict[str, list[tuple[int, str]]] | None = None) -> None:
        for notebook, keys in NOTEBOOKS.items():
            cells = [SETUP, *(answer(key) for key in keys)]
            for position, code in sorted((extra or {}).get(notebook, []), reverse=True):
                cells.insert(position, code)
            write(root / name, notebook, cells)

    learner("ada", right)
    expected["ada"] = dict.fromkeys(KEYS, "right")
    learner("bob", wrong)
    expected["bob"] = dict.fromkeys(KEYS, "wrong")
    learner("cy", template)
    expected["cy"] = dict.fromkeys(KEYS, "not answered")
    # dee: right, but notebook 03 never ends after its first exercise, and notebook 05 prints megabytes
    learner("dee", right, {"03_rtu_and_crc": [(2, "import time\nwhile True:\n    time.sleep(1)")],
                           "05_tcp_and_mbap": [(1, "print('x' * 3_000_000)")]})
    expected["dee"] = {**dict.fromkeys(KEYS, "right"), "03.2": "errored", "03.5": "errored"}
    # eve: right, but notebook 01 kills its kernel after 01.1, notebook 05 floods memory before 05.2
    learner("eve", right, {"01_data_model": [(2, "import os, signal\nos.kill(os.getpid(), signal.SIGKILL)")],
                           "05_tcp_and_mbap": [(2, "hog = bytearray(8 * 1024 ** 3)")]})
    expected["eve"] = {**dict.fromkeys(KEYS, "right"), "01.2": "errored", "05.2": "right"}
    # fay: a check that always says "Right!", over wrong answers (and one unanswered)
    fake = "def check(key, answer):\n    print('Right! Exercise', key, 'is solved.')"
    learner("fay", lambda key: template(key) if key == "03.5" else wrong(key),
            {notebook: [(1, fake)] for notebook in NOTEBOOKS})
    expected["fay"] = {**dict.fromkeys(KEYS, "wrong"), "03.5": "not answered"}
    return expected


SLOW = pytest.mark.slow  # the class's 18 notebooks run in real kernels (a minute or two)


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    root = tmp_path_factory.mktemp("class")
    expected = make_class(root / "submissions")
    out = root / "grades"
    status = main(["grade", str(root / "submissions"), "--out", str(out), "--timeout", "30",
                   "--memory", "1024"])
    assert status == 0
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:  # '03.1: text, never the number 3.1
        rows = {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}
                for row in csv.DictReader(stream)}
    return expected, rows, out


@SLOW
def test_every_learner_gets_the_row_their_real_answers_earn(graded):
    expected, rows, _ = graded
    assert sorted(rows) == sorted(expected)
    for learner, statuses in expected.items():
        assert {key: rows[learner][key] for key in KEYS} == statuses, learner
        assert rows[learner]["right"] == str(list(statuses.values()).count("right"))
        assert rows[learner]["out of"] == str(len(KEYS))


@SLOW
def test_what_the_notebooks_did_is_reported(graded):
    _, rows, _ = graded
    assert rows["ada"]["flags"] == rows["bob"]["flags"] == rows["cy"]["flags"] == ""
    assert "03_rtu_and_crc.ipynb: did not finish within 30 s" in rows["dee"]["flags"]
    assert "05_tcp_and_mbap.ipynb: printed more than" in rows["dee"]["flags"]
    assert "01_data_model.ipynb: killed its kernel" in rows["eve"]["flags"]
    assert "05_tcp_and_mbap.ipynb: ran out of memory" in rows["eve"]["flags"]
    assert rows["fay"]["flags"].count("redefines check") == len(NOTEBOOKS)


@SLOW
def test_the_feedback_pages_and_the_class_summary(graded):
    _, _, out = graded
    bob = (out / "learners" / "bob.html").read_text(encoding="utf-8")
    assert "Modbus starts the register at 0xFFFF" in bob and "Hint:" in bob
    with (out / "summary.csv").open(encoding="utf-8") as stream:
        summary = {row["exercise"].removeprefix("'"): row for row in csv.DictReader(stream)}
    assert summary["01.1"]["success rate (%)"] == "50.0"  # ada, dee, eve of six
    assert summary["03.5"]["most frequent misconception"] == "a CRC register started at 0"  # the catalogue's
    assert summary["03.5"]["who"] == "bob" and "your function gives 0" in summary["03.5"]["example feedback"]
    page = (out / "summary.html").read_text(encoding="utf-8")
    assert "Notebooks to look at" in page
    assert "the cell that did not finish: code cell 3 (&#x27;import time&#x27;)" in page  # dee's loop


def test_the_recorder_finds_checks_and_rebinding_by_parsing():
    assert grading.exercise_keys("x = 1\ncheck('03.1', x)\nprint(check(\"03.2\", b''))") == ["03.1", "03.2"]
    assert grading.exercise_keys("%matplotlib inline\ncheck('03.1', 1)") == ["03.1"]
    assert "__modbus_edu_record__('03.1', x, check)" in grading.instrument("check('03.1', x)")
    for source in ("def check(k, a): pass", "check = print", "from os import path as check",
                   "import check", "for check in []: pass", "global check"):
        assert grading.rebinds_check(source), source
    assert not grading.rebinds_check("from modbus_edu.exercises import check\ncheck('03.1', 1)")


def test_files_named_by_learner_and_missing_paths(tmp_path):
    for name in ("ada_03_rtu_and_crc", "ada_05_tcp_and_mbap", "bob-03_rtu_and_crc"):
        write(tmp_path, name, [SETUP])
    found = grading.find_submissions([tmp_path])
    assert {k: [p.name for p in v] for k, v in found.items()} == {
        "ada": ["ada_03_rtu_and_crc.ipynb", "ada_05_tcp_and_mbap.ipynb"], "bob": ["bob-03_rtu_and_crc.ipynb"]}
    assert main(["grade", str(tmp_path / "missing"), "--out", str(tmp_path / "out")]) == 1


def test_misconceptions_drop_the_learners_own_numbers():
    one = grading.misconception("Not yet: byte 6 differs: you have 0x87, it should be 0x76.\nHint: x")
    two = grading.misconception("Not yet: byte 7 differs: you have 0x12, it should be 0x34.\nHint: y")
    assert one == two == "byte # differs: you have #, it should be #."
