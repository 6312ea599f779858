"""The gradebook against a hostile class: every attack on ``modbus-edu grade`` is one learner.

Each attacker must get no credit it did not earn, each honest learner exactly the grade it gets when
graded alone, and no process of the run may be left afterwards."""

from __future__ import annotations

import contextlib
import csv
import io
import os
import sys
import time
from pathlib import Path

import nbformat
import pytest
from test_grade import SETUP, right, write, wrong

from modbus_edu.cli import main
from modbus_edu.course import boundary
from modbus_edu.course.sandbox import CGROUP_V1, LIBRARY, UID_BASE, detect, processes_marked, running
from modbus_edu.exercises import EXERCISES
from modbus_edu.exercises.submit import MIME

NOTEBOOK = "03_rtu_and_crc"
KEYS = ["03.1", "03.2", "03.5"]
HONEST = {"ada": right, "bob": wrong}
XSS = "<img src=x onerror=alert(document.domain)>"
FORMULA = '=HYPERLINK("http://example.invalid","click")'
FOLDER = '=HYPERLINK("example.invalid","click")'  # a folder's name holds no slash
ESCAPE = "\x1b[31mred\x1b[0m"


def wrong_answers() -> list[str]:
    return [wrong(key) for key in KEYS]


def attacks(root: Path, out: Path) -> dict[str, list[str]]:
    """Learner -> the cells of its notebook 03 (after the setup cell)."""
    forge = {"key": "03.2", "ok": True, "message": "Right! Exercise 03.2 is solved.", "real_check": True}
    return {
        # credit for nothing: forging the recorder's log, patching the checkers, patching json
        "forger": [
            "import glob, json\n"
            "try:\n"
            "    paths = [c.cell_contents for c in __modbus_edu_record__.__closure__]\n"
            "except Exception:\n"
            "    paths = []\n"
            "paths += glob.glob('/tmp/modbus-edu-grade-*/**', recursive=True)\n"
            "for path in paths:\n"
            "    try:\n"
            f"        open(str(path), 'a').write(json.dumps({forge!r}) + '\\n')\n"
            "    except Exception:\n"
            "        pass",
            "from IPython.display import display\n"
            f"display({{{MIME!r}: json.dumps({forge!r})}}, raw=True)\n"
            f"display({{{MIME!r}: json.dumps({{'key': '03.5', 'trace': {{'name': 'f', 'calls': [], "
            f"'stopped': False}}, 'seed': ''}})}}, raw=True)",
            *wrong_answers()],
        "patcher": [
            "import dataclasses\nfrom modbus_edu.exercises import core\n"
            "for k in list(core.EXERCISES):\n"
            "    core.EXERCISES[k] = dataclasses.replace(core.EXERCISES[k], checker=lambda a: None)",
            *wrong_answers()],
        "jsonpatcher": [
            "import json\n_dumps = json.dumps\n"
            "def dumps(obj, *args, **kwargs):\n"
            "    if isinstance(obj, dict):\n"
            "        obj = dict(obj, ok=True)\n"
            "    return _dumps(obj, *args, **kwargs)\n"
            "json.dumps = dumps",
            *wrong_answers()],
        "anyequal": [
            "class Any(int):\n    def __eq__(self, other):\n        return True\n"
            "    __hash__ = int.__hash__\n"
            "class AnyBytes(bytes):\n    def __eq__(self, other):\n        return True\n"
            "    __hash__ = bytes.__hash__",
            "check('03.1', AnyBytes(b''))", "check('03.2', AnyBytes(b'\\x01'))", "check('03.4', Any(0))",
            "check('03.5', lambda data: Any(0))"],
        "library": ["check('03.5', mb.crc16)",
                    "import functools\ncheck('03.5', functools.partial(mb.crc16))"],
        # one learner against another: editing classmates' notebooks, writing verdict logs, orphans
        "editor": [
            "import glob, os\n"
            f"targets = glob.glob('../*/{NOTEBOOK}.ipynb') + glob.glob({str(root)!r} + '/*/*.ipynb')\n"
            "for path in targets:\n"
            "    try:\n"
            "        open(path, 'w').write('{}')\n"
            "    except Exception:\n"
            "        pass\n"
            "try:\n"
            f"    open({str(out)!r} + '/gradebook.csv', 'w').write('nothing')\n"
            "except Exception:\n"
            "    pass"],
        "logwriter": [
            "import glob, json\n"
            "for path in glob.glob('/tmp/modbus-edu-grade-*/*'):\n"
            "    try:\n"
            "        line = json.dumps({'key': '03.1', 'ok': False, 'message': 'x'})\n"
            "        open(path, 'a').write(line + '\\n')\n"
            "    except Exception:\n"
            "        pass"],
        "orphan": [
            "import subprocess, sys\n"
            "script = '''\nimport os, time\n"
            f"path = {str(out / 'gradebook.csv')!r}\n"
            "for _ in range(600):\n"
            "    if os.path.exists(path):\n"
            "        time.sleep(1)\n"
            "        lines = open(path).read().splitlines()\n"
            "        open(path, 'w').write('\\\\n'.join(l if not l.startswith('orphan,') else "
            "'orphan,right,right,right,3,0,0,0,3/3,' for l in lines))\n"
            "        break\n"
            "    time.sleep(0.2)\n'''\n"
            "subprocess.Popen([sys.executable, '-c', script], start_new_session=True)\n"
            "for _ in range(5):\n"
            "    subprocess.Popen(['sleep', '40'])",
            *wrong_answers()],
        # exhausting the machine
        "forkbomb": [
            "import os, time\nchildren = 0\n"
            "for _ in range(2000):\n"
            "    try:\n"
            "        pid = os.fork()\n"
            "    except OSError:\n"
            "        break\n"
            "    if pid == 0:\n"
            "        time.sleep(60)\n"
            "        os._exit(0)\n"
            "    children += 1\n"
            "print(children)",
            *wrong_answers()],
        "hog": [
            "import subprocess, sys\n"
            "hogs = [subprocess.Popen([sys.executable, '-c', 'import time; b = bytearray(500 * 2 ** 20); "
            "b[::4096] = b\"x\" * len(b[::4096]); time.sleep(20)']) for _ in range(4)]\n"
            "print([hog.wait() for hog in hogs])",
            *wrong_answers()],
        # the instructor's pages
        "xss" + XSS: [f"check({XSS!r}, 1)", *wrong_answers()],
        "formula": [f"check({FORMULA!r}, 1)", *wrong_answers()],
        FOLDER: wrong_answers(),
        "escape": [f"check({ESCAPE!r}, 1)", *wrong_answers()],
        # the grader itself
        "stdout": ["import os\nos.system('echo hi')\nos.write(1, b'x' * 64 * 1024 * 1024)",
                   *(right(key) for key in KEYS)],
        "roles": ["roles = mb.security.course_roles()\nframe = bytes([6, 0, 5, 0, 1])\n"
                  "print(roles.check(frame, 'viewer'))", *(right(key) for key in KEYS)],
    }


def build(root: Path, out: Path) -> None:
    for name, answer in HONEST.items():
        write(root / name, NOTEBOOK, [SETUP, *(answer(key) for key in KEYS)])
    for name, cells in attacks(root, out).items():
        write(root / name, NOTEBOOK, [SETUP, *cells])
    big = nbformat.v4.new_notebook()  # 6 MB of check(1, 2)
    big.cells = [nbformat.v4.new_code_cell("check(1, 2)\n" * 1000) for _ in range(350)]
    (root / "big").mkdir()
    nbformat.write(big, root / "big" / f"{NOTEBOOK}.ipynb")
    checkpoint = root / ".ipynb_checkpoints"
    write(checkpoint, f"{NOTEBOOK}-checkpoint", [SETUP, *(right(key) for key in KEYS)])
    (root / "linked").mkdir()
    (root / "linked" / f"{NOTEBOOK}.ipynb").symlink_to(root / "ada" / f"{NOTEBOOK}.ipynb")


def run_grade(root: Path, out: Path) -> tuple[dict, str, float]:
    printed = io.StringIO()
    start = time.monotonic()
    with contextlib.redirect_stdout(printed):
        status = main(["grade", str(root), "--out", str(out), "--timeout", "40", "--memory", "1024",
                       "--jobs", "2", "-q"])
    seconds = time.monotonic() - start
    assert status == 0, printed.getvalue()
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:  # '03.1: text, never the number 3.1
        rows = {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}
                for row in csv.DictReader(stream)}
    return rows, printed.getvalue(), seconds


def leftovers() -> set[int]:
    """Processes of this test's grading runs still alive: by marker, by the learners' user ids."""
    found = processes_marked(f"{os.getpid()}-")
    low = UID_BASE + 1000 * (os.getpid() % 50_000)
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                uid = entry.stat().st_uid
            except OSError:
                continue
            if low <= uid < low + 1000 and running(entry):  # a zombie, dead, waits for init to reap it
                found.add(int(entry.name))
    return found


SLOW = pytest.mark.slow  # two dozen notebooks in real kernels (minutes)
SEALED = detect().level == "sealed"


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    base = tmp_path_factory.mktemp("hostile")
    root, out = base / "class", base / "grades"
    build(root, out)
    rows, printed, seconds = run_grade(root, out)
    gradebook = (out / "gradebook.csv").read_text(encoding="utf-8")
    time.sleep(3)  # an orphan that survived would rewrite the gradebook now
    alone = base / "alone"
    for name, answer in HONEST.items():
        write(alone / name, NOTEBOOK, [SETUP, *(answer(key) for key in KEYS)])
    alone_rows, _, _ = run_grade(alone, base / "alone-grades")
    return {"rows": rows, "printed": printed, "seconds": seconds, "out": out, "gradebook": gradebook,
            "alone": alone_rows, "left": leftovers()}


@SLOW
def test_honest_learners_keep_the_grade_they_get_alone(graded):
    rows, alone = graded["rows"], graded["alone"]
    for name in HONEST:
        assert {key: rows[name][key] for key in KEYS} == {key: alone[name][key] for key in KEYS}, name
    assert [rows["ada"][key] for key in KEYS] == ["right"] * 3
    assert [rows["bob"][key] for key in KEYS] == ["wrong"] * 3
    assert "its grader failed" not in rows["ada"]["flags"] + rows["bob"]["flags"]


@SLOW
def test_no_attacker_gets_credit_it_did_not_earn(graded):
    rows = graded["rows"]
    for name in ("forger", "patcher", "jsonpatcher", "anyequal", "library", "editor", "logwriter", "orphan",
                 "forkbomb", "hog", "formula", FOLDER, "escape", "big"):
        # the formula folder's row is shown neutralised and in lower case ('=hyperlink...): found by its text
        row = rows.get(name) or next(row for learner, row in rows.items()
                                     if name.lstrip("=").casefold() in learner.casefold())
        statuses = {key: row.get(key) for key in KEYS}
        assert "right" not in statuses.values(), (name, statuses)
    assert rows["anyequal"].get("03.4") == "wrong"
    page = (graded["out"] / "learners" / "library.html").read_text(encoding="utf-8")
    assert "that is `mb.crc16`; write your own" in page


@SLOW
def test_output_and_roles_check_do_not_disturb_right_answers(graded):
    rows = graded["rows"]
    for name in ("stdout", "roles"):
        assert [rows[name][key] for key in KEYS] == ["right"] * 3, (name, rows[name])
        assert "grader failed" not in rows[name]["flags"]
    assert "printed more than" in rows["stdout"]["flags"]
    assert "redefines check" not in rows["roles"]["flags"]
    assert not any("frame" in column or "viewer" in column for column in rows["roles"])


@SLOW
def test_bounded_work_is_flagged(graded):
    rows = graded["rows"]
    assert "more than the grader reads in a notebook" in rows["big"]["flags"]
    assert graded["seconds"] < 900


@SLOW
@pytest.mark.skipif(not SEALED, reason="the per-learner limits and the private folders need the sealed level "
                                       "(root, namespaces, cgroups)")
def test_learners_are_sealed_off_and_nothing_outlives_the_run(graded):
    rows = graded["rows"]
    assert graded["left"] == set(), graded["left"]
    assert (graded["out"] / "gradebook.csv").read_text(encoding="utf-8") == graded["gradebook"]
    assert "right" not in [rows["orphan"][key] for key in KEYS]
    assert "ran out of memory" in rows["hog"]["flags"]
    leftover_groups = [p for name in ("memory", "pids") if (CGROUP_V1 / name).exists()
                       for p in (CGROUP_V1 / name).glob(f"modbus-edu-grade-{os.getpid()}-*")]
    assert leftover_groups == []


@SLOW
def test_reports_cannot_be_turned_against_the_instructor(graded):
    out, rows = graded["out"], graded["rows"]
    for page in [out / "summary.html", *(out / "learners").glob("*.html")]:
        assert "<img src=x" not in page.read_text(encoding="utf-8"), page
    for name in ("gradebook.csv", "summary.csv"):
        with (out / name).open(encoding="utf-8") as stream:
            for row in csv.reader(stream):
                assert not any(cell[:1] in ("=", "+", "-", "@") for cell in row), row
    assert "\x1b" not in graded["printed"]
    columns = set(next(iter(rows.values())))
    assert {key for key in columns if key[:2].isdigit() and "." in key} <= set(EXERCISES)


@SLOW
def test_checkpoints_and_links_are_not_learners(graded):
    rows = graded["rows"]
    assert ".ipynb_checkpoints" not in rows
    assert "right" not in [rows.get("linked", {}).get(key) for key in KEYS]


def test_the_hostile_cells_are_valid_python():
    for name, cells in attacks(Path("/class"), Path("/out")).items():
        for cell in cells:
            compile(cell, name, "exec")


def test_the_grader_judges_plain_submissions_with_its_own_checkers():
    import modbus_edu as mb
    from modbus_edu.course.runner import NotebookRun, judged
    from modbus_edu.exercises.plain import plain

    checker = EXERCISES["03.5"].checker
    honest = checker.trace(lambda data: mb.crc16(bytes(data)) ^ 0, "03.5 theirs")
    submissions = [{"key": "03.1", "answer": plain(bytes.fromhex("B2 98"))},
                   {"key": "03.2", "ok": True, "message": "Right!"},  # a forged verdict is no answer
                   {"key": "03.5", "build": True}]
    # a build exercise is judged from its clean room's trace, against the inputs the grader drew
    run = judged(NotebookRun("03_rtu_and_crc.ipynb", submissions=list(submissions)),
                 {"03.5": (honest, checker.cases("03.5 mine"))})  # outputs for other inputs than the grader's
    assert [(record["key"], record["ok"]) for record in run.records] == [
        ("03.1", True), ("03.2", False), ("03.5", False)]
    right = judged(NotebookRun("x", submissions=[{"key": "03.5", "build": True}]),
                   {"03.5": (honest, checker.cases("03.5 theirs"))})
    assert right.records[0]["ok"] is True
    unanswered = judged(NotebookRun("x", submissions=[{"key": "03.5", "build": True}]))
    assert unanswered.records == [] and "could not be traced" in unanswered.errored_cells["03.5"]


def test_only_the_librarys_own_check_is_rewritten():
    from modbus_edu.course.runner import exercise_keys, instrument

    source = "print(roles.check(frame, 'viewer'))\nexercises.check('03.1', x)\nmb.exercises.check('03.2', y)"
    rewritten = instrument(source)
    assert "roles.check(frame, 'viewer')" in rewritten
    assert "__modbus_edu_record__('03.1', x, exercises.check)" in rewritten
    assert "__modbus_edu_record__('03.2', y, mb.exercises.check)" in rewritten
    assert exercise_keys(source) == ["03.1", "03.2"]
    assert exercise_keys("roles.check('03.1', 'viewer')") == []


@SLOW
def test_the_limited_level_grades_honest_learners_alike(tmp_path, monkeypatch):
    monkeypatch.setenv("MODBUS_EDU_GRADE_ISOLATION", "limited")
    assert detect().level == "limited" and detect().note.startswith("isolation: limited")
    for name, answer in HONEST.items():
        write(tmp_path / "class" / name, NOTEBOOK, [SETUP, *(answer(key) for key in KEYS)])
    rows, _, _ = run_grade(tmp_path / "class", tmp_path / "grades")
    assert [rows["ada"][key] for key in KEYS] == ["right"] * 3
    assert [rows["bob"][key] for key in KEYS] == ["wrong"] * 3
    assert leftovers() == set()


def test_the_container_level_needs_an_engine_that_answers(tmp_path):
    image = os.environ.get("MODBUS_EDU_GRADE_IMAGE")  # an image holding Python, ipykernel and modbus_edu
    try:
        sandbox = detect(image or "python:3")
    except OSError as exc:
        assert "neither docker nor podman answers" in str(exc)
        pytest.skip(f"no container level here: {exc}")
    if not image:
        pytest.skip(f"{sandbox.engine} answers, but MODBUS_EDU_GRADE_IMAGE names no image to grade in")
    write(tmp_path / "class" / "ada", NOTEBOOK, [SETUP, *(right(key) for key in KEYS)])
    status = main(["grade", str(tmp_path / "class"), "--out", str(tmp_path / "grades"), "--container", image,
                   "-q"])
    assert status == 0
    assert "ada,right,right,right" in (tmp_path / "grades" / "gradebook.csv").read_text(encoding="utf-8")


def test_a_sealed_kernel_keeps_python_and_the_library_installed_below_tmp(monkeypatch):
    """A clone and its virtual environment under /tmp (where CI may clone) stay reachable although /tmp
    is the learner's fresh room: Python keeps its path and is bound once the room is made; the
    environment and the library are seen at /opt."""
    monkeypatch.setattr(boundary, "python_home", lambda: "/tmp/ci/python")
    monkeypatch.setattr(sys, "prefix", "/tmp/ci/.venv")
    places = boundary.resolve("kernel", "/tmp/ci/modbus_edu", sockets="/tmp/grader/run/k1")
    args = boundary.bwrap_arguments(places, {})
    pairs = list(zip(args, args[1:]))
    room = pairs.index(("--tmpfs", "/tmp"))
    assert pairs.index(("/tmp/ci/python", "/tmp/ci/python")) > room
    assert ("/tmp/ci/.venv", "/opt/environment") in pairs and ("/tmp/ci/modbus_edu",
                                                                "/opt/modbus_edu/modbus_edu") in pairs
    assert pairs.index(("/tmp/grader/run/k1", "/tmp/run")) > room
    assert (LIBRARY / "modbus_edu" / "course" / "sandbox.py").exists()
