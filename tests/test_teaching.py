"""TEACHING.md quotes the checkers, never paraphrases them: its strictness rule is the one
:mod:`modbus_edu.exercises.core` states, and its table of wrong answers is what each checker says.

Both are generated from the checkers: after changing a checker's words, run
``python tests/test_teaching.py`` to write them into TEACHING.md again; this test fails until then.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from modbus_edu.exercises import EXERCISES, core, evaluate

TEACHING = Path(__file__).resolve().parent.parent / "TEACHING.md"

RULE_START = "How strict a checker is"
TABLE_HEAD = ("| exercise | what it asks | what the checker says to the classic wrong answer |\n"
              "|---|---|---|\n")
CELL = 220
"""The longest verdict a table cell quotes, in characters (then "...")."""

DESCRIBED = {
    "00.0": "the concept inventory before the course: the verdict records the answers and says nothing of "
            "which are right; notebook 17 shows them beside the post-test's.",
}
"""Exercises whose verdict on a wrong answer is no teaching sentence (the pre-test only records)."""


def strictness_rule() -> str:
    """The rule as :mod:`~modbus_edu.exercises.core`'s docstring states it, in Markdown."""
    doc = core.__doc__ or ""
    text = doc[doc.index(RULE_START):].strip()
    text = re.sub(r":func:`(\w+)`", r"`\1`", text).replace("``", "`")
    return " ".join(text.split())


def verdict_cell(key: str) -> str:
    """What the checker of ``key`` says to its registered wrong answer, without "Not yet:" and the hint."""
    if key in DESCRIBED:
        return DESCRIBED[key]
    message = evaluate(key, EXERCISES[key].wrong).message
    message = message.split("\nHint:")[0].removeprefix("Not yet: ")
    message = " ".join(message.split()).replace("|", "\\|")
    return message if len(message) <= CELL else message[:CELL].rstrip() + "..."


def table() -> str:
    """The table of wrong answers, one row per exercise, from the checkers."""
    rows = [f"| {key} | {EXERCISES[key].title} | {verdict_cell(key)} |" for key in sorted(EXERCISES)]
    return TABLE_HEAD + "\n".join(rows) + "\n"


def _table_span(text: str) -> tuple[int, int]:
    start = text.index(TABLE_HEAD)
    end = text.index("\n\n", start)
    return start, end + 1


def written(text: str) -> str:
    """TEACHING.md's text with the rule and the table generated from the checkers."""
    start, end = _table_span(text)
    text = text[:start] + table() + text[end:]
    rule = re.search(r"^> How strict a checker is.*$", text, re.M)
    assert rule is not None, "TEACHING.md has no quoted strictness rule"
    return text[:rule.start()] + "> " + strictness_rule() + text[rule.end():]


def test_teaching_quotes_the_strictness_rule_of_the_checkers():
    assert "> " + strictness_rule() in TEACHING.read_text(encoding="utf-8")


def test_teaching_table_is_what_the_checkers_say():
    text = TEACHING.read_text(encoding="utf-8")
    start, end = _table_span(text)
    assert text[start:end] == table(), "run python tests/test_teaching.py to write the table again"


if __name__ == "__main__":
    TEACHING.write_text(written(TEACHING.read_text(encoding="utf-8")), encoding="utf-8")
    sys.exit(0)
