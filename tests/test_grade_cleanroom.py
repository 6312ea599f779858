"""A build exercise judged from its source in a clean room: what is taken from the notebook, and what the
room lets through.  The learner's kernel no longer traces its own function, so nothing it does (patching
the grader's code, swapping modules, a startup file) reaches a verdict, and the library's own answer is
not there to call, however it is wrapped."""

from __future__ import annotations

import csv
import importlib
import inspect
import sys
import textwrap
import types
from pathlib import Path

import pytest
from test_grade import ARC, SETUP, SOLUTIONS, write

from modbus_edu.cli import main
from modbus_edu.exercises import EXERCISES

CHECK = "check('03.5', crc16)"
OWN = """def crc16(data):
    register = 0xFFFF
    for byte in data:
        register ^= byte
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
    return register"""
TABLED = ["POLY = 0xA001\nTABLE = []\nfor i in range(256):\n    c = i\n    for _ in range(8):\n"
          "        c = (c >> 1) ^ POLY if c & 1 else c >> 1\n    TABLE.append(c)\nprint(len(TABLE))",
          "def step(register, byte):\n    return (register >> 8) ^ TABLE[(register ^ byte) & 0xFF]",
          "def crc16(data):\n    register = START\n    for byte in data:\n"
          "        register = step(register, byte)\n    return register",
          "START = 0xFFFF"]


def cleanroom():
    """The module under test, imported here so that the end-to-end test also runs against a grader
    without it."""
    return importlib.import_module("modbus_edu.course.cleanroom")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("rooms")


def graded(cells: list[str], folder: Path, key: str = "03.5", seed: str = "a seed of the grader's"):
    """The verdict on exercise ``key`` of a notebook made of ``cells``, judged from its room."""
    from modbus_edu.exercises import judge

    room = cleanroom()
    taken = room.extract(cells, key)
    assert taken is not None
    trace, cases = room.room_trace(key, taken, seed, folder=folder)
    return judge(key, trace, cases=cases)


# --- what is taken ----------------------------------------------------------------------------------------

def test_helpers_tables_and_constants_are_taken_and_nothing_else():
    cells = [SETUP, "print('hello')\nimport os\nos.listdir('.')", *TABLED, "crc16(b'123')\nsteps = []",
             "import matplotlib", CHECK]
    taken = cleanroom().extract(cells, "03.5")
    assert taken.name == "crc16" and not taken.problem
    for part in ("POLY = 40961", "TABLE = []", "TABLE.append(c)", "def step(", "def crc16(", "START = 65535"):
        assert part in taken.source, part
    for part in ("print", "os.listdir", "import os", "matplotlib", "steps", "crc16(b'123')", "check("):
        assert part not in taken.source, part
    assert taken.source.index("POLY") < taken.source.index("def step") < taken.source.index("def crc16")


def test_the_last_definition_before_the_check_wins():
    first = "def crc16(data):\n    return 1"
    later = "def crc16(data):\n    return 2"
    taken = cleanroom().extract([SETUP, first, OWN, CHECK, later], "03.5")
    assert "0xFFFF" in taken.source.replace("65535", "0xFFFF") and "return 1" not in taken.source
    assert "return 2" not in taken.source
    taken = cleanroom().extract([SETUP, first, CHECK, OWN, CHECK], "03.5")  # the last check counts
    assert "return 1" not in taken.source and "register" in taken.source


def test_cells_with_magics_are_read_as_the_kernel_reads_them():
    cells = [SETUP, "%matplotlib inline\nWIDTH = 8\n!echo hi",
             "%%time\n" + OWN.replace("range(8)", "range(WIDTH)"), CHECK]
    taken = cleanroom().extract(cells, "03.5")
    assert "WIDTH = 8" in taken.source and "def crc16" in taken.source
    assert "echo" not in taken.source and "matplotlib" not in taken.source


def test_answers_that_are_no_plain_name():
    room = cleanroom()
    taken = room.extract([SETUP, "def helper(data):\n    return 0",
                          "check('03.5', lambda data: helper(data))"], "03.5")
    assert taken.name == room.ANSWER and "def helper" in taken.source and "lambda" in taken.source
    assert room.extract([SETUP, "check('03.5', mb.crc16)"], "03.5").library == "mb.crc16"
    assert room.extract([SETUP, "import functools as f\ncheck('03.5', f.partial(mb.crc16))"], "03.5"
                        ).library == "mb.crc16"
    assert room.extract(["from modbus_edu import crc16 as c\nfrom modbus_edu.exercises import check",
                         "check('03.5', c)"], "03.5").library == "mb.crc16"
    block = "if True:\n    " + OWN.replace("\n", "\n    ") + "\n    " + CHECK
    missing = room.extract([SETUP, block], "03.5")
    assert "not defined at the top level" in missing.problem
    assert room.extract([SETUP, OWN], "03.5") is None


# --- the room ---------------------------------------------------------------------------------------------

def test_an_honest_crc_is_right_and_so_is_one_built_on_a_helper_and_a_table(folder):
    assert graded([SETUP, OWN, CHECK], folder).ok is True
    result = graded([SETUP, *TABLED, CHECK], folder)
    assert result.ok is True, result.message
    assert graded([SETUP, ARC, "check('03.5', answer)"], folder).ok is False


@pytest.mark.parametrize("cells", [
    ["def crc16(d):\n    return mb.crc16(d)"],
    ["ref = mb.crc16", "def crc16(d):\n    return ref(d)"],
    ["import importlib, modbus_edu.crc",
     "def crc16(d):\n    return importlib.reload(modbus_edu.crc).crc16(d)"],
    ["import os", "def crc16(d):\n    return mb.crc16(d) if os.environ.get('MODBUS_EDU_SUBMIT') else 0"],
    ["def crc16(d):\n    return mb.crc16_bitwise(d)"],
    ["def crc16(d):\n    frame = mb.RtuFrame(unit=1, pdu=mb.ReadCoilsRequest(address=0, count=1))\n"
     "    return frame.encode()[-2:]"],
], ids=["wrapper", "captured", "reload", "environment", "another-crc", "through-a-frame"])
def test_the_librarys_own_answer_is_not_in_the_room(cells, folder, monkeypatch):
    monkeypatch.setenv("MODBUS_EDU_SUBMIT", "1")  # as a graded kernel has it
    result = graded([SETUP, *cells, CHECK], folder)
    assert result.ok is False
    assert "calls mb.crc" in result.message, result.message


def test_the_library_is_reached_nowhere_else_in_the_room(folder):
    probe = ("import sys\ndef crc16(d):\n    import modbus_edu.exercises as e\n"
             "    assert not hasattr(e, 'EXERCISES') and 'modbus_edu.course' not in sys.modules\n"
             "    try:\n        import modbus_edu.course\n    except ImportError:\n        pass\n"
             "    else:\n        raise AssertionError('course reached')\n"
             "    return mb.crc16(d)")
    result = graded([SETUP, probe, CHECK], folder)
    assert "calls mb.crc16" in result.message, result.message


def test_what_is_not_taken_does_not_run_and_a_missing_name_is_said(folder):
    cells = [SETUP, "import modbus_edu.crc\nmodbus_edu.crc.crc16 = lambda d: 0", "mb.crc16 = None",
             "def crc16(d):\n    return helper(d)", CHECK, "def helper(d):\n    return 0"]
    result = graded(cells, folder)
    assert result.ok is False and "NameError" in result.message and "helper" in result.message


def test_a_slave_handler_is_read_back_in_the_room(folder):
    solution = (SOLUTIONS / "06_5.py").read_text()
    assert graded([solution], folder, "06.5").ok is True
    forgetful = solution.replace("registers[address] = int.from_bytes(pdu[3:5], \"big\")", "pass")
    assert forgetful != solution
    result = graded([forgetful], folder, "06.5")
    assert result.ok is False and "reading it back" in result.message, result.message


@pytest.mark.slow  # two rooms per build exercise of the course (about a minute)
def test_every_worked_solution_is_right_in_its_room_and_the_reference_is_not(folder):
    """The table of what each room holds back neither refuses the worked solutions nor lets the
    checker's own reference through."""
    room = cleanroom()
    builds = [key for key, item in EXERCISES.items() if item.kind == "build"]
    assert sorted(room.BLOCKED) == sorted(builds)
    for key in builds:
        solution = (SOLUTIONS / f"{key.replace('.', '_')}.py").read_text()
        result = graded([solution], folder, key)
        assert result.ok is True, (key, result.message)
        if room.BLOCKED[key].names:
            result = graded([*reference_cells(key), f"check({key!r}, answer)"], folder, key)
            assert result.ok is False and " calls " in result.message, (key, result.message)


def reference_cells(key: str) -> list[str]:
    """Cells that answer exercise ``key`` with its checker's own reference: the reference itself when the
    library has it, else its source with the imports of the library's names it uses."""
    reference = EXERCISES[key].checker.reference
    if not reference.__module__.startswith("modbus_edu.exercises"):
        return [f"from {reference.__module__} import {reference.__name__} as reference\n"
                "def answer(*args):\n    return reference(*args)"]
    imports = []
    for name in reference.__code__.co_names:
        value = reference.__globals__.get(name)
        module = str(getattr(value, "__module__", ""))
        if isinstance(value, types.ModuleType):
            imports.append(f"import {value.__name__} as {name}")
        elif module.startswith("modbus_edu") and not module.startswith("modbus_edu.exercises"):
            imports.append(f"from {module} import {value.__name__} as {name}")
    source = textwrap.dedent(inspect.getsource(reference))
    return ["\n".join(imports), source.replace(f"def {reference.__name__}(", "def answer(", 1)]


# --- end to end: a class graded by ``modbus-edu grade`` -----------------------------------------------------

STUB = "def crc16(data):\n    return 0"
FORGE = ("import modbus_edu.exercises.submit as s\nfrom modbus_edu.exercises import EXERCISES as E\n"
         "def send_trace(key, seed):\n"
         "    s.publish({'key': key, 'trace': E[key].checker.trace(lambda d: mb.crc16(bytes(d)) ^ 0, seed), "
         "'seed': seed})\n")


SWAP = (FORGE + "import sys, types\nfake = types.ModuleType(s.__name__)\nfake.send_trace = send_trace\n"
        "sys.modules[s.__name__] = fake")
STARTUP = FORGE + "import modbus_edu as mb\ns.send_trace = send_trace\n"
PLANT = ("import os, pathlib\n"
         "startup = pathlib.Path(os.environ['IPYTHONDIR']) / 'profile_default' / 'startup'\n"
         f"startup.mkdir(parents=True, exist_ok=True)\n(startup / '00-x.py').write_text({STARTUP!r})")


def attackers() -> dict[str, dict[str, list[str]]]:
    """Learner -> notebook -> cells: each credited a stub crc16 by a grader that traces in the kernel."""
    return {
        "honest": {"03_rtu_and_crc": [SETUP, OWN, CHECK]},
        "patcher": {"03_rtu_and_crc": [SETUP, FORGE + "s.send_trace = send_trace", STUB, CHECK]},
        "swapper": {"03_rtu_and_crc": [SETUP, SWAP, STUB, CHECK]},
        "planter": {"00_welcome": [SETUP, PLANT], "03_rtu_and_crc": [SETUP, STUB, CHECK]},
        "wrapper": {"03_rtu_and_crc": [SETUP, "def crc16(data):\n    return mb.crc16(data)", CHECK]},
        "switcher": {"03_rtu_and_crc": [SETUP, "import os\ndef crc16(data):\n    if os.environ.get("
                                        "'MODBUS_EDU_SUBMIT'):\n        return mb.crc16(data)\n    return 0",
                                        CHECK]},
    }


@pytest.mark.slow  # seven notebooks in real kernels
def test_a_class_of_attackers_gets_no_credit_and_the_honest_learner_does(tmp_path):
    for learner, notebooks in attackers().items():
        for notebook, cells in notebooks.items():
            write(tmp_path / "class" / learner, notebook, cells)
    out = tmp_path / "grades"
    assert main(["grade", str(tmp_path / "class"), "--out", str(out), "--timeout", "40", "--jobs", "2",
                 "-q"]) == 0
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        rows = {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}  # '03.5: a text header
                for row in csv.DictReader(stream)}
    assert rows["honest"]["03.5"] == "right"
    for learner in ("patcher", "swapper", "planter", "wrapper", "switcher"):
        assert rows[learner]["03.5"] == "wrong", (learner, rows[learner])
    page = (out / "learners" / "wrapper.html").read_text(encoding="utf-8")
    assert "calls mb.crc16" in page
    assert sys.modules.get("modbus_edu") is not None
