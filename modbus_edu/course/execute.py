"""Re-executing the course's notebooks in place, each from a fresh ``python3`` kernel started in the
notebooks folder, so that their stored outputs are what strict nbval compares."""

from __future__ import annotations

import re
import time
from pathlib import Path

from .._optional import load_nbclient, load_nbformat

NOTEBOOK_PATTERN = re.compile(r"^\d\d_[a-z0-9_]+\.ipynb$")


def course_notebooks(folder: Path | str) -> list[Path]:
    """The course's notebooks in order: ``NN_name.ipynb`` files of ``folder``."""
    return sorted(p for p in Path(folder).iterdir() if NOTEBOOK_PATTERN.match(p.name))


def execute(path: Path | str, timeout: int = 120) -> float:
    """Execute one notebook in place from a fresh kernel; return the seconds it took."""
    nbformat, nbclient = load_nbformat(), load_nbclient()

    path = Path(path)
    notebook = nbformat.read(path, as_version=4)
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3 (ipykernel)",
                                       "language": "python"}
    start = time.perf_counter()
    client = nbclient.NotebookClient(notebook, timeout=timeout, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent.resolve())}})
    client.execute()
    elapsed = time.perf_counter() - start
    for cell in notebook.cells:
        cell.metadata.pop("execution", None)
        if cell.cell_type == "code":
            cell.outputs = coalesce_streams(cell.outputs)
    strip_widget_state(notebook)
    nbformat.write(notebook, path)
    return elapsed


def coalesce_streams(outputs: list) -> list:
    """Consecutive outputs of one stream (stdout, stderr) as one: what a cell printed is stored the same
    however a loaded machine cut it into messages."""
    merged: list = []
    for output in outputs:
        previous = merged[-1] if merged else None
        if (output.get("output_type") == "stream" and previous is not None
                and previous.get("output_type") == "stream" and previous.get("name") == output.get("name")):
            previous["text"] = "".join(previous["text"]) + "".join(output["text"])
        else:
            merged.append(output)
    return merged


WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"


def strip_widget_state(notebook) -> int:
    """Save no widget state: a panel is live only after its cell runs.

    Saved state would draw dead panels in a notebook that has not run (controls that ignore input), and
    a widget view without its state draws "Error displaying widget".  So the notebook's widget metadata
    goes, and so does each output's widget view; everything else of the output stays: a panel's
    ``text/html``, the static picture of the panel as its cell left it under "run this cell to use it"
    (what GitHub, nbviewer and JupyterLab before Run All show), and its ``text/plain``.  Returns how
    many widget views were removed.
    """
    notebook.metadata.pop("widgets", None)
    removed = 0
    for cell in notebook.cells:
        for output in cell.get("outputs", []):
            data = output.get("data")
            if data and WIDGET_VIEW in data:
                del data[WIDGET_VIEW]
                removed += 1
    return removed
