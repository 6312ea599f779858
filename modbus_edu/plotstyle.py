"""The course's plot style: one width, readable fonts, legends outside the data.

Every plot in the notebooks and panels starts from :func:`figure`, so they share a size and a font and
fit the 968 px of a notebook's output area::

    from modbus_edu.plotstyle import figure, legend_outside

    fig, ax = figure()                       # one plot, the course's width
    ax.plot([0, 1, 2], [3, 1, 2], label="register")
    legend_outside(ax)                       # beside the plot, never over the data

:func:`figure` uses matplotlib's constrained layout, which leaves room for a legend placed outside.
:func:`show` shows a figure with its text equivalent, the words a reader who cannot see it gets instead.
"""

from __future__ import annotations

import sys
from typing import Any

from .errors import require
from .pictures import FIGURE_IN_WORDS, _display, _shell  # the words' line; IPython's pieces (if any)

mpl = require("matplotlib", "modbus_edu.plotstyle")
from matplotlib.figure import Figure  # noqa: E402  (a figure of no pyplot state, for a panel's picture)

__all__ = ["FIGURE_IN_WORDS", "HEIGHT", "STYLE", "WIDTH", "Figure", "figure", "legend_outside",
           "legend_below", "show", "mpl"]

WIDTH = 9.0
"""Inches: at the notebook's 100 dpi, about 900 px, inside the 968 px output area of a 1400 px screen."""

HEIGHT = 3.2
"""Inches for one row of axes."""

STYLE: dict[str, Any] = {
    "font.size": 11,
    "axes.titlesize": 12,
    "axes.labelsize": 11,
    "xtick.labelsize": 10,
    "ytick.labelsize": 10,
    "legend.fontsize": 10,
    "legend.frameon": False,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "figure.dpi": 100,
}
"""The rcParams every course figure is drawn with."""


def figure(rows: int = 1, cols: int = 1, *, width: float = WIDTH, height: float | None = None,
           **subplots: Any):
    """A figure and its axes in the course style (``plt.subplots`` with the course's size and fonts).

    ``height`` defaults to :data:`HEIGHT` per row; further keywords (``sharex=True``, ...) go to
    ``subplots``.  Returns ``(fig, ax)`` for one axes, ``(fig, axes)`` otherwise, as ``plt.subplots``.
    """
    import matplotlib.pyplot as plt  # pyplot (a GUI backend, its state) only when a figure is made

    if height is None:
        height = HEIGHT * rows
    with mpl.rc_context(STYLE):
        return plt.subplots(rows, cols, figsize=(width, height), layout="constrained", **subplots)


def legend_outside(ax, **legend: Any):
    """Put ``ax``'s legend to the right of the plot, top-aligned, so it never covers the data."""
    options = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0,
               "frameon": False, "fontsize": STYLE["legend.fontsize"]}
    options.update(legend)
    return ax.legend(**options)


def legend_below(ax, ncols: int = 3, **legend: Any):
    """Put ``ax``'s legend under the plot in ``ncols`` columns (for wide plots with many entries)."""
    options = {"loc": "upper center", "bbox_to_anchor": (0.5, -0.18), "ncols": ncols,
               "frameon": False, "fontsize": STYLE["legend.fontsize"]}
    options.update(legend)
    return ax.legend(**options)


def show(fig, text: str) -> None:
    """Show ``fig`` with its text equivalent ``text``: what the figure shows, in words (WCAG 1.1.1).

    In a notebook the figure goes to the cell's output with ``text`` as its image's ``alt`` (the
    ``image/png`` metadata, which nbconvert writes as the ``alt`` of the ``<img>``), and ``text`` is
    printed right under it: JupyterLab draws an output image without alt text, so that line is where a
    screen reader finds the words.  Outside a notebook: pyplot's ``show``, then the words.
    """
    pyplot = sys.modules.get("matplotlib.pyplot")  # loaded by figure(), which made the figure
    if _shell() is not None:
        _display().display(fig, metadata={"image/png": {"alt": text}})
        if pyplot is not None:
            pyplot.close(fig)  # shown once: not again by the inline backend at the end of the cell
    elif pyplot is not None:
        pyplot.show()
    print(FIGURE_IN_WORDS + text)
