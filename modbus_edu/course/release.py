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
#: solutions, the instructor's guide) stays behind.  Its Makefile is :func:`class_makefile`'s.
SHIPPED = ["modbus_edu", "binder", "pyproject.toml", "LICENSE", "LICENSE-COURSE", "CITATION.cff"]

#: Files of the shipped folders that belong to the full repository only: the test tools' pins.
LEFT_BEHIND = ["requirements-test.txt"]

#: The Makefile targets that work in the class copy (the others need the tests, the benchmarks, the
#: solutions or the instructor's tools, which stay behind).
CLASS_TARGETS = ("help", "lab", "notebooks", "clean")

#: What ``make clean`` removes in a class copy: the environment ``make lab`` builds and what installing
#: the course there writes (the full repository's caches, site and release folder are not there).
CLASS_CLEAN = """\
## clean: remove the virtual environment and what installing the course wrote
clean:
	rm -rf $(VENV) .venv-* build dist *.egg-info"""

CLASS_MAKEFILE_HEADER = """\
# The course for a class: `make lab` builds its own virtual environment in .venv from the learner's pins
# (binder/requirements.txt) and opens the course in JupyterLab; a fresh clone needs only Python (3.10 or
# newer) and git. PYTHON=python3.12 picks the interpreter.
"""

CLASS_GITIGNORE = """\
.venv/
.venv-*/
__pycache__/
*.pyc
*.egg-info/
.ipynb_checkpoints/
build/
dist/
"""

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


def class_makefile(makefile: str) -> str:
    """The course's Makefile cut to the targets that work in a class copy (:data:`CLASS_TARGETS`): each
    target's block (its ``## name:`` help and its rule) kept or left out whole (``clean`` written for
    the copy: :data:`CLASS_CLEAN`), the header written for a class, and every environment built from the
    learner's pins."""
    kept = [CLASS_MAKEFILE_HEADER.rstrip("\n")]
    for block in makefile.split("\n\n")[1:]:
        target = re.search(r"^## ([\w-]+):", block, re.M)
        if target and target.group(1) not in CLASS_TARGETS:
            continue
        if target and target.group(1) == "clean":
            block = CLASS_CLEAN
        block = re.sub(r"^\.PHONY:.*$", ".PHONY: " + " ".join(CLASS_TARGETS), block, flags=re.M)
        kept.append(block.replace("$(call venv,$(TEST_PINS))", "$(call venv,$(LEARNER_PINS))"))
    text = "\n\n".join(kept).rstrip("\n") + "\n"
    unused = [name for name in re.findall(r"^([A-Z_]+)\s*[?:]?=", text, re.M) if f"$({name})" not in text]
    return re.sub(rf"^(?:{'|'.join(unused)})\s*[?:]?=.*\n", "", text, flags=re.M) if unused else text


def release(root: Path | str, destination: Path | str) -> list[Path]:
    """Write the class copy of the course at ``root`` into ``destination`` (which must not exist or be
    empty); return the notebooks written."""
    root, destination = Path(root), Path(destination)
    if destination.exists() and any(destination.iterdir()):
        raise FileExistsError(f"{destination} is not empty: give a new folder (make release RELEASE=...)")
    destination.mkdir(parents=True, exist_ok=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".ipynb_checkpoints", *LEFT_BEHIND)
    for name in SHIPPED:
        source = root / name
        if source.is_dir():
            shutil.copytree(source, destination / name, ignore=ignore)
        elif source.exists():
            shutil.copy2(source, destination / name)
    (destination / "README.md").write_text(CLASS_README, encoding="utf-8")
    (destination / ".gitignore").write_text(CLASS_GITIGNORE, encoding="utf-8")
    makefile = class_makefile((root / "Makefile").read_text(encoding="utf-8"))
    (destination / "Makefile").write_text(makefile, encoding="utf-8")
    (destination / "notebooks").mkdir()
    written = []
    for notebook in course_notebooks(root / "notebooks"):
        copy = destination / "notebooks" / notebook.name
        shutil.copy2(notebook, copy)
        strip_notebook(copy)
        written.append(copy)
    return written
