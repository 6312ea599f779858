"""Checkers for the course's exercises.

Two kinds of exercise end the notebooks:

* **value** exercises: the learner computes something (a frame, a CRC, a time) and passes it in::

      answer = ...          # replace ... with your answer
      check("03.1", answer)

* **build** exercises: the learner writes a function, and the checker runs it against the library on
  the edge cases and on at least 100 generated inputs, showing the first input where they differ::

      def crc16(data: bytes) -> int:
          ...               # your code here
      check("03.5", crc16)

Unanswered, ``check`` prints "not answered yet" and raises nothing, so a notebook runs from top to
bottom; a hint appears only after a wrong answer.  Worked solutions live in ``notebooks/solutions/``
(``%load solutions/03_5.py``).

Layout: :mod:`.core` holds the registry, ``evaluate`` (``verdict``, ``judge``) and the helpers checkers share;
:mod:`.build` the build-exercise runner (a trace of the learner's function, then a judgement of it).
:mod:`.checkers` holds the per-notebook checkers (``checkers/nbNN.py``: the exercises of notebook NN, found
and imported automatically); :mod:`.levels` gives the hints after the idea (the step, then a worked example
on other numbers) to the exercises whose checkers do not. :mod:`.diagnosis` names a wrong answer: one
procedure per concept (the CRC, the LRC, the MBAP header, a frame's fields, a timing, an address, a value,
a count), each able to give its answer with one named step changed (:mod:`.diagnosis.procedure`), and the
catalogue of misconceptions those steps point to (:mod:`.diagnosis.misconceptions`), so that one mistake
reads the same in every notebook.
What runs in the learner's kernel: :mod:`.submit` (``check`` itself, which under ``modbus-edu grade`` only
submits), :mod:`.plain` (answers as plain data) and :mod:`.calls` (calling a learner's function within a
time limit; the grader's clean room keeps only these two). :mod:`.inventory` is the concept inventory that
opens (00.0) and closes (17.0) the course.  To add an exercise, add it to its notebook's module with
:func:`exercise` or :func:`build_exercise`, declare beside it the answers it accepts (``accepts=``, other
spellings of the right answer) and the wrong answers it knows (``refuses=[(answer, "misconception-key" or
None), ...]``; for a build exercise, wrong functions), and write its worked solution: the test suite checks
that the solution and every accepted answer pass, and that every known wrong answer fails, named as its
misconception.  The slips a newcomer makes (test data) live in ``tests/slips.py`` and
``tests/build_slips.py``.
"""

from __future__ import annotations

# the notebooks' exercises, the concept inventory (00.0 and 17.0), then every exercise's hints after the idea
from . import checkers, inventory, levels  # noqa: F401  (levels: registered by importing it)
from .build import build_exercise
from .checkers.nb13 import lab  # the troubleshooting lab's puzzles, used by notebook 13
from .core import EXERCISES, PLACEHOLDER, AnswerError, Exercise, Result, evaluate, exercise, judge, verdict
from .submit import check

# ``from modbus_edu.exercises import nb16`` still finds a notebook's checkers
globals().update(checkers.NOTEBOOKS)

__all__ = ["EXERCISES", "PLACEHOLDER", "AnswerError", "Exercise", "Result", "build_exercise", "check",
           "evaluate", "exercise", "inventory", "judge", "lab", "verdict"]
