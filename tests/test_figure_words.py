"""Every figure of the course reaches a reader who cannot see it: each picture a notebook's cell drew has
its text equivalent (WCAG 1.1.1), as the image's ``alt`` and as the line printed under it
(:func:`modbus_edu.plotstyle.show`), so a screen reader finds the words in JupyterLab, in the HTML
nbconvert writes and in the offline site (which shows the build's pictures with the words stored
beside them: tests/test_pictures.py)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from modbus_edu.pictures import FIGURE_IN_WORDS, draws

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def _cells(path: Path) -> list[tuple[int, str, list]]:
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return [(n, "".join(cell["source"]), cell.get("outputs", [])) for n, cell in enumerate(cells)
            if cell["cell_type"] == "code"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda path: path.stem[:2])
def test_every_picture_has_its_words_as_alt_and_under_it(path):
    for number, source, outputs in _cells(path):
        printed = "".join("".join(o.get("text", "")) for o in outputs if o.get("output_type") == "stream")
        for output in outputs:
            if "image/png" not in output.get("data", {}):
                continue
            alt = output.get("metadata", {}).get("image/png", {}).get("alt", "")
            assert len(alt) >= 40, f"{path.name} cell {number}: a picture without its words ({source[:60]!r})"
            assert FIGURE_IN_WORDS + alt in printed, f"{path.name} cell {number}: the words are not under it"
            assert "{" not in alt and "}" not in alt, f"{path.name} cell {number}: a placeholder in {alt!r}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda path: path.stem[:2])
def test_every_cell_that_draws_shows_its_figure_with_words(path):
    """A figure goes out through plotstyle.show, never pyplot's show, which has no place for words."""
    for number, source, _ in _cells(path):
        if draws(source):
            assert not re.search(r"\bplt\.show\(", source), f"{path.name} cell {number}: plt.show(), no words"


def test_the_figures_words_are_read_off_the_data_they_draw():
    """The words carry the figure's numbers, read off the same data (not typed in): two samples."""
    by_name = {path.stem[:2]: path for path in NOTEBOOKS}
    words = {name: [line for _, _, outputs in _cells(by_name[name]) for o in outputs
                    if o.get("output_type") == "stream" for line in "".join(o["text"]).splitlines()
                    if line.startswith(FIGURE_IN_WORDS)] for name in ("01", "08")}
    assert any("2 blocks, 149 to 174 and 199 to 224" in line for line in words["01"])
    assert any("0, 1, 0, 0, 0, 0, 0, 0, 0, 1" in line for line in words["08"])  # 0x01 in 8N1
