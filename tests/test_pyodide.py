"""The library's browser-safe tests inside Pyodide (Python compiled to WebAssembly, as in JupyterLite),
run under Node by lite/pyodide_tests.mjs with Pyodide's core from the npm package pinned in lite/.

The library is installed from its own wheel, with the pure-Python wheels it and pytest need
(lite/wheels.py, at the project's pins); the tests and the worked solutions are mounted from this clone.
Selected: the codecs, explain, the loopback master and slave, the devices, the register maps, every
exercise's worked solution and registered wrong answer (build exercises included, and their time limit
stopping an endless loop where no thread can start), and the socket roles refusing in a browser.

Skipped, with the reason, where node or npm is missing -- unless ``CI`` is set: then it fails.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LITE = ROOT / "lite"
WHEELS = ROOT / "build" / "pyodide-wheels"
# The library's tests that need no socket, no thread, no subprocess and no file outside the clone.
BROWSER_SAFE = [
    "tests/test_crc.py", "tests/test_pdu.py", "tests/test_framing.py", "tests/test_values.py",
    "tests/test_explain.py",
    "tests/test_vectors.py", "tests/test_datamodel.py", "tests/test_registermap.py",
    "tests/test_loopback_serial.py", "tests/test_master.py", "tests/test_slave.py", "tests/test_meter.py",
    "tests/test_arduino.py", "tests/test_generators.py", "tests/test_clock.py",
    "tests/test_exercises.py", "tests/test_exercise_variants.py", "tests/test_platform.py",
    "tests/test_course.py::test_solution_passes_and_wrong_answer_fails",
    "tests/test_course.py::test_build_checkers_refuse_functions_that_raise_or_return_junk",
]
# Left out: the stack under Pyodide is the browser's, far shallower than CPython's recursion limit
# (deep_nesting builds answers 100 000 levels deep); and the check that CPython is not a browser.
NOT_IN_A_BROWSER = "deep_nesting or outside_a_browser"


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


def _require(*tools: str) -> None:
    missing = [t for t in tools if shutil.which(t) is None]
    if missing:
        reason = f"the Pyodide test run needs {' and '.join(missing)} (Node.js 18 or newer, with npm)"
        if _in_ci():
            pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
        pytest.skip(reason)


@pytest.mark.slow
def test_the_browser_safe_tests_pass_inside_pyodide():
    _require("node", "npm")
    subprocess.run(["npm", "ci", "--no-audit", "--no-fund", "--loglevel=error"], cwd=LITE, check=True,
                   timeout=600)
    subprocess.run([sys.executable, str(LITE / "wheels.py"), str(WHEELS), "--tests"], check=True, timeout=600,
                   capture_output=True)
    done = subprocess.run(
        ["node", str(LITE / "pyodide_tests.mjs"), str(WHEELS), str(ROOT / "tests"), str(ROOT / "notebooks"),
         "--", "-q", "--tb=short", "-rfE", "-k", f"not ({NOT_IN_A_BROWSER})", *BROWSER_SAFE],
        capture_output=True, text=True, timeout=1800)
    report = done.stdout + done.stderr
    assert done.returncode == 0, report[-6000:]
    assert "on emscripten: modbus_edu" in report and " passed" in report, report[-2000:]
    assert " failed" not in report and " error" not in report, report[-6000:]
