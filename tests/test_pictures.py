"""A cell that draws, where matplotlib is missing (the offline site): its other statements run, and the
picture the build drew from it is shown with one line; the site's build ships those pictures."""

from __future__ import annotations

import base64
import json
import sys
import zipfile
from pathlib import Path

import pytest

import modbus_edu
from modbus_edu import pictures

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "lite"))
import build_site  # noqa: E402

CELL = """import matplotlib.pyplot as plt
import json
values = [1, 2, 3]
fig, ax = plt.subplots()
ax.plot(values)
total = sum(values)
total"""


@pytest.fixture
def no_matplotlib(monkeypatch):
    """matplotlib absent, as in the offline site (an import of it raises ModuleNotFoundError)."""
    drawing = ("matplotlib.", "modbus_edu.plot")
    for name in [n for n in sys.modules if n == "matplotlib" or n.startswith(drawing)]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.delattr(modbus_edu, "plotstyle", raising=False)  # imported by a test before: forgotten
    monkeypatch.setitem(sys.modules, "matplotlib", None)


def test_the_statements_that_do_not_draw_run_and_the_last_value_is_shown(no_matplotlib):
    namespace: dict = {}
    shown = []
    skipped = pictures.run_statements(CELL, namespace, show=shown.append)
    assert skipped == [1, 4, 5]  # the import, the figure, and the line that drew on ax
    assert namespace["values"] == [1, 2, 3] and namespace["total"] == 6 and "json" in namespace
    assert shown == [6]


def test_the_course_s_plot_style_counts_as_drawing(no_matplotlib):
    namespace: dict = {}
    cell = "from modbus_edu import plotstyle\nx = 2\nfig, ax = plotstyle.figure()\ny = x * 2"
    skipped = pictures.run_statements(cell, namespace)
    assert skipped == [1, 3] and namespace["y"] == 4


def test_a_name_a_cell_above_could_not_bind_needs_matplotlib_in_the_cells_below(no_matplotlib):
    namespace: dict = {}
    unbound: set[str] = set()
    assert pictures.run_statements("import json\nfrom modbus_edu import plotstyle", namespace,
                                   unbound=unbound) == [2]
    assert pictures.run_statements("x = 1\nfig, ax = plotstyle.figure()\nax.plot([x])\ny = 2", namespace,
                                   unbound=unbound) == [2, 3]
    assert namespace["y"] == 2 and unbound == {"plotstyle", "fig", "ax"}
    with pytest.raises(NameError):  # without what the cells above could not bind, it is a real error
        pictures.run_statements("fig, ax = plotstyle.figure()", {})


def test_any_other_error_is_raised_as_usual(no_matplotlib):
    with pytest.raises(ZeroDivisionError):
        pictures.run_statements("import matplotlib\nx = 1 / 0", {})
    with pytest.raises(NameError):
        pictures.run_statements("import matplotlib\nprint(undefined_name)", {})
    with pytest.raises(ModuleNotFoundError):
        pictures.run_statements("import no_such_module_here", {})


def test_with_matplotlib_nothing_is_skipped():
    namespace: dict = {}
    assert pictures.run_statements("import matplotlib\nx = 1", namespace) == [] and namespace["x"] == 1


def _displayed(monkeypatch, stored: dict) -> tuple[list, list]:
    images, printed = [], []
    monkeypatch.setattr(pictures, "stored_pictures", lambda: stored)
    import IPython.display  # what a kernel has loaded

    monkeypatch.setattr(IPython.display, "display", lambda *items, **kw: images.extend(items))
    monkeypatch.setattr("builtins.print", lambda *args, **kw: printed.append(" ".join(map(str, args))))
    return images, printed


PNG = base64.b64encode(b"\x89PNG\r\n\x1a\n" + b"\0" * 16).decode()


def test_the_build_s_picture_is_shown_with_one_line(no_matplotlib, monkeypatch):
    images, printed = _displayed(monkeypatch, {pictures.cell_key(CELL): [PNG]})
    pictures.run_drawing(CELL)
    assert images[0] == 6  # the cell's last value, then its picture
    assert [type(image).__name__ for image in images[1:]] == ["Image"]
    assert images[1].data == base64.b64decode(PNG)
    assert len(printed) == 1 and "drawn from this cell when the course was built" in printed[0]
    assert "Binder" in printed[0] and "published site" in printed[0]


def test_the_build_s_picture_is_shown_with_its_words(no_matplotlib, monkeypatch):
    shown = []
    images, printed = _displayed(monkeypatch, {pictures.cell_key(CELL): [{"png": PNG, "alt": "a line up"}]})
    import IPython.display

    monkeypatch.setattr(IPython.display, "display", lambda *items, **kw: shown.append((items, kw)))
    pictures.run_drawing(CELL)
    (image,), options = shown[1]
    assert image.data == base64.b64decode(PNG)
    assert options == {"metadata": {"image/png": {"alt": "a line up"}}}
    assert printed[0] == "The figure in words: a line up" == pictures.FIGURE_IN_WORDS + "a line up"
    assert "drawn from this cell when the course was built" in printed[1]


def test_an_edited_cell_says_it_has_no_picture_and_a_cell_that_drew_nothing_says_nothing(no_matplotlib,
                                                                                          monkeypatch):
    images, printed = _displayed(monkeypatch, {pictures.cell_key(CELL): [PNG],
                                               pictures.cell_key("import matplotlib\nx = 1"): []})
    pictures.run_drawing(CELL + "\nextra = 1")
    assert images == [] and len(printed) == 1 and "no picture" in printed[0]  # (its last line binds)
    printed.clear()
    pictures.run_drawing("import matplotlib\nx = 1")  # a set-up cell: it imports, it never drew
    assert images == [] and printed == []


def test_only_cells_that_draw_are_rewritten():
    assert pictures._transform(["x = 1\n"]) == ["x = 1\n"]
    assert pictures._transform(["%%time\n", "import matplotlib\n"]) == ["%%time\n", "import matplotlib\n"]
    (line,) = pictures._transform(["import matplotlib\n", "y = 2\n"])
    assert line.startswith("__import__('modbus_edu.pictures').pictures.run_drawing(")


def test_the_key_ignores_trailing_blanks_but_not_the_code():
    assert pictures.cell_key("a = 1  \nb = 2\n\n") == pictures.cell_key("a = 1\nb = 2")
    assert pictures.cell_key("a = 1\nb = 2") != pictures.cell_key("a = 1\nb = 3")


def test_the_build_ships_every_drawing_cell_s_pictures_as_a_wheel(tmp_path):
    notebooks = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
    wheel = build_site.pictures_wheel(notebooks, tmp_path)
    with zipfile.ZipFile(wheel) as archive:
        stored = json.loads(archive.read("modbus_edu_pictures/pictures.json"))
        record = archive.read("modbus_edu_pictures-1.0.dist-info/RECORD").decode()
    drew = 0
    for path in notebooks:
        for cell in json.loads(path.read_text())["cells"]:
            source = build_site._source(cell)
            if cell["cell_type"] == "code" and pictures.draws(source):
                pngs = [o["data"]["image/png"] for o in cell["outputs"] if "image/png" in o.get("data", {})]
                assert len(stored[pictures.cell_key(source)]) == len(pngs), (path.name, source[:60])
                drew += bool(pngs)
    assert drew >= 10  # 01, 03, 06, 08, 09, 10 and 16 draw
    assert all(base64.b64decode(picture["png"]).startswith(b"\x89PNG") for pictures_ in stored.values()
               for picture in pictures_)
    assert all(picture["alt"] for pictures_ in stored.values() for picture in pictures_)  # each has its words
    assert "modbus_edu_pictures/pictures.json,sha256=" in record
