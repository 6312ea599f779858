"""Keeping the course's notebooks runnable and well formed.

``python -m modbus_edu.course execute [NOTEBOOK ...]`` re-executes notebooks in place, in order, each
from a fresh ``python3`` kernel started in the notebooks folder, so their stored outputs are what strict
nbval compares.  ``python -m modbus_edu.course check`` lists what breaks the course's conventions:

* the kernelspec is ``python3`` and execution counts run 1, 2, 3, ... with no gaps;
* the first cell is a title with "What you will learn" (3 to 5 points) and "What you need";
* the notebook closes with a summary, at least two exercises (cells calling ``check(``) and a link to
  the next notebook (except the last one);
* every link to another notebook points to a file that exists;
* from notebook 01 on, the prose names the source documents by their short names ("the power-meter
  paper"), never by file number ("source 003", "003's Table 5");
* introduce before use: every library name a code cell uses (``mb.Master``, ``from modbus_edu.widgets
  import TestTool``) is introduced first, in the prose (markdown) or in a comment of that notebook or an
  earlier one;
* the course as one (``check_integrity``): notebook 00's map and the README's course table list exactly
  the notebooks that exist, with their titles; every "Next" link names the next notebook, and only the
  last notebook calls itself the last; no markdown link sits in a code cell; every hex frame of two or
  more bytes the prose quotes (outside an exercise's prompt) is shown by a code cell or an output of that
  notebook, or is a named specification example; the prose names a source at most 3 times (the closing
  "Where this comes from" box aside) and never "its Table N"; every notebook has that box before its Next
  link; no panel's picture names a source or a source's table or figure (``panel_problems``); every
  worked solution ends with its own ``check("NN.k", answer)`` (``solution_problems``).

``python -m modbus_edu.course release DIR`` (``make release``) writes a copy of the course for a class,
without the worked solutions (:mod:`.release`); ``modbus-edu grade`` grades a class's notebooks
(:mod:`.grade`).
"""

from .check import (
    Problem,
    check_course,
    check_integrity,
    check_notebook,
    source_shorthands,
    used_before_introduced,
)
from .execute import WIDGET_VIEW, course_notebooks, execute, strip_widget_state

__all__ = ["WIDGET_VIEW", "Problem", "check_course", "check_integrity", "check_notebook",
           "course_notebooks", "execute",
           "source_shorthands", "strip_widget_state", "used_before_introduced"]
