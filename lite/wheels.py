"""Collect the wheels Pyodide installs the course from: the library's own wheel and the pure-Python
wheels of what it needs, at the versions pinned in binder/requirements-test.txt (the project's one lock).

    python lite/wheels.py DIR            # the library and what the course imports in a browser
    python lite/wheels.py DIR --tests    # and what the library's tests need under Pyodide (pytest, ...)

Every wheel is ``py3-none-any``: Pyodide runs pure-Python wheels as they are.  pip downloads them from
PyPI with ``--no-deps``, so nothing but the listed pins is fetched.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PINS = ROOT / "binder" / "requirements-test.txt"
PYODIDE_PYTHON = "3.14"  # the Python of Pyodide 314

# What `import modbus_edu`, its panels and its captures need in a browser (scapy: pure Python), and the
# Web Serial panel (mb.browser_serial): anywidget and what it imports (psygnal, typing-extensions).
# cryptography is left out: compiled, and the library needs it only to speak TLS, which a browser cannot.
COURSE = ["pymodbus", "pyserial", "tqdm", "ipywidgets", "comm", "traitlets", "widgetsnbextension",
          "jupyterlab-widgets", "scapy", "anywidget", "psygnal", "typing-extensions"]
# What the library's own tests need under Pyodide: pytest and hypothesis, and IPython, which ipywidgets
# imports (a JupyterLite kernel carries it; under Node it is installed with the rest).
TESTS = ["pytest", "pluggy", "iniconfig", "packaging", "pygments", "hypothesis", "attrs", "sortedcontainers",
         "ipython", "ipython-pygments-lexers", "jedi", "parso", "matplotlib-inline", "prompt-toolkit",
         "wcwidth", "stack-data", "asttokens", "executing", "pure-eval"]
# Pinned here instead: hypothesis ships compiled wheels only since 6.156; 6.155.7 is its last pure one.
PYODIDE_PINS = {"hypothesis": "6.155.7"}


def pinned(names: list[str], pins: Path = PINS) -> list[str]:
    """``name==version`` for each name, as pinned for Pyodide's Python (3.11 or newer) in ``pins``."""
    found: dict[str, str] = {}
    for line in pins.read_text().splitlines():
        m = re.match(r"([A-Za-z0-9_.-]+)==([^\s;]+)\s*(?:;\s*([^#]*))?", line)
        if not m or (m.group(3) and "< '3.11'" in m.group(3)):
            continue
        found[m.group(1).lower().replace("_", "-")] = m.group(2)
    found.update(PYODIDE_PINS)
    missing = [n for n in names if n not in found]
    if missing:
        raise SystemExit(f"{pins} pins no version of {', '.join(missing)}")
    return [f"{n}=={found[n]}" for n in names]


def collect(out: Path, tests: bool = False) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("modbus_edu-*.whl"):
        old.unlink()  # one library wheel: the one built now
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q"]
    subprocess.run([*pip, "wheel", "--no-deps", "-w", str(out), str(ROOT)], check=True)
    names = COURSE + (TESTS if tests else [])
    # the pure-Python wheel of each pin, for Pyodide's Python, even where a compiled one exists for this one
    subprocess.run([*pip, "download", "--no-deps", "--only-binary=:all:", "--platform", "any",
                    "--python-version", PYODIDE_PYTHON, "-d", str(out), *pinned(names)], check=True)
    return sorted(out.glob("*.whl"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--tests", action="store_true", help="add the test tools (pytest, hypothesis)")
    args = parser.parse_args()
    for wheel in collect(args.out, args.tests):
        if not wheel.name.endswith("-none-any.whl"):
            raise SystemExit(f"{wheel.name} is not a pure-Python wheel: Pyodide cannot install it")
        print(wheel.name)


if __name__ == "__main__":
    main()
