"""A copy of the course to hand out to a class (``make release``): the notebooks without their worked
solutions, the library they run on, and the learner's pinned environment (Binder builds it as it builds
this repository), but no tests, benchmarks or tooling.

The solutions folder stays behind, and so does every sentence of the notebooks that points at it (the
``%load solutions/...`` hint of the welcome notebook): the copy must not send a learner looking for a
file that is not there.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from .._optional import load_nbformat
from .execute import course_notebooks

#: What a class repository holds, relative to the course's root: the rest (tests, bench, .ci, the
#: solutions, the instructor's guide) stays behind.
SHIPPED = ["modbus_edu", "binder", "pyproject.toml", "Makefile", "LICENSE", "LICENSE-COURSE",
           "CITATION.cff"]

SOLUTION_MENTION = re.compile(r"solutions/|%load\b")
SENTENCE_END = re.compile(r"(?<=[.!?])(\s+)")

CLASS_README = """\
# modbus_edu: learn Modbus by doing

A Jupyter course that teaches the Modbus industrial protocol by building, sending and taking apart real
frames. Everything runs without hardware.

Open `notebooks/00_welcome.ipynb` and run the notebooks in order. To run the course on your own computer
you need Python 3.10 or newer:

```bash
make lab                                             # Linux and macOS
```

```powershell
python -m venv .venv                                 # Windows (or: py -m venv .venv)
.venv\\Scripts\\python -m pip install -r binder\\requirements.txt
.venv\\Scripts\\python -m pip install --no-deps .
.venv\\Scripts\\python -m jupyter lab --notebook-dir=notebooks notebooks\\00_welcome.ipynb
```

The code is under the MIT licence (`LICENSE`); the course text and notebooks under Creative Commons
Attribution 4.0 (`LICENSE-COURSE`). The course comes from https://github.com/modbus-edu/modbus_edu.
"""


def without_solution_hints(text: str) -> str:
    """``text`` without the sentences that mention the worked solutions (``solutions/``, ``%load``)."""
    kept = []
    for paragraph in text.split("\n\n"):
        parts = SENTENCE_END.split(paragraph)
        sentences = parts[0::2]
        spaces = parts[1::2] + [""]
        if not any(SOLUTION_MENTION.search(sentence) for sentence in sentences):
            kept.append(paragraph)
            continue
        out = "".join(sentence + space for sentence, space in zip(sentences, spaces)
                      if not SOLUTION_MENTION.search(sentence)).rstrip()
        if out:
            kept.append(out)
    return "\n\n".join(kept)


def strip_notebook(path: Path) -> int:
    """Remove the solution hints from one notebook's markdown and code comments; return how many cells
    changed."""
    nbformat = load_nbformat()

    notebook = nbformat.read(path, as_version=4)
    changed = 0
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            text = without_solution_hints(cell.source)
        elif cell.cell_type == "code":
            text = "\n".join(line for line in cell.source.splitlines()
                             if not (line.lstrip().startswith(("#", "%load"))
                                     and SOLUTION_MENTION.search(line)))
        else:
            continue
        if text != cell.source:
            cell.source = text
            changed += 1
    if changed:
        nbformat.write(notebook, path)
    return changed


def release(root: Path | str, destination: Path | str) -> list[Path]:
    """Write the class copy of the course at ``root`` into ``destination`` (which must not exist or be
    empty); return the notebooks written."""
    root, destination = Path(root), Path(destination)
    if destination.exists() and any(destination.iterdir()):
        raise FileExistsError(f"{destination} is not empty: give a new folder (make release RELEASE=...)")
    destination.mkdir(parents=True, exist_ok=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".ipynb_checkpoints")
    for name in SHIPPED:
        source = root / name
        if source.is_dir():
            shutil.copytree(source, destination / name, ignore=ignore)
        elif source.exists():
            shutil.copy2(source, destination / name)
    (destination / "README.md").write_text(CLASS_README, encoding="utf-8")
    (destination / "notebooks").mkdir()
    written = []
    for notebook in course_notebooks(root / "notebooks"):
        copy = destination / "notebooks" / notebook.name
        shutil.copy2(notebook, copy)
        strip_notebook(copy)
        written.append(copy)
    return written
