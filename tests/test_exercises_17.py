"""Notebook 17's exercises: right answers in their usual spellings pass, the known mistakes are named."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

from modbus_edu import exercises
from modbus_edu.exercises.checkers.nb17 import CAPTURED_WRITE
from modbus_edu.explain import explain

SOLUTIONS = Path(__file__).resolve().parents[1] / "notebooks" / "solutions"


def _message(key, answer) -> str:
    result = exercises.evaluate(key, answer)
    assert result.ok is False, f"{key} accepted {answer!r}"
    return result.message


def test_17_1_the_captured_write_is_what_explain_shows():
    rows = {row.field: row.value for row in explain(CAPTURED_WRITE, "tcp", "request").rows}
    assert 500 in rows.values()
    assert exercises.evaluate("17.1", 500).ok and exercises.evaluate("17.1", 0x01F4).ok
    assert exercises.evaluate("17.1", "500").ok and exercises.evaluate("17.1", 500.0).ok  # spellings of 500


@pytest.mark.parametrize("answer, words", [
    (10, "address"), (0xF401, "low byte first"), (6, "function code"), (7, "transaction id"),
    ("five hundred", "whole number"), (1, "not the value"),
])
def test_17_1_mistakes_are_named(answer, words):
    assert words in _message("17.1", answer)


@pytest.mark.parametrize("answer, words", [(0, "address 100"), (2, "before the slave"), (0x90, "byte after"),
                                           (3, "not the answer")])
def test_17_2_mistakes_are_named(answer, words):
    assert exercises.evaluate("17.2", 1).ok
    assert words in _message("17.2", answer)


def _solution():
    return runpy.run_path(str(SOLUTIONS / "17_3.py"))["answer"]


def test_17_3_the_worked_solution_passes():
    assert exercises.evaluate("17.3", _solution()).ok


def test_17_3_forgetting_the_last_address_of_a_multiple_write_is_named():
    def decide(pdu, role):  # checks the first address only
        right = _solution()(pdu, role)
        if role == "operator" and pdu[0] in (15, 16) and int.from_bytes(pdu[1:3], "big") <= 99:
            return None
        return right

    assert "a multiple write judged by its first address" in _message("17.3", decide).lower()


def test_17_3_a_code_instead_of_a_pdu_and_a_wrong_exception_code_are_named():
    def code(pdu, role):
        answer = _solution()(pdu, role)
        return None if answer is None else 1

    def code_02(pdu, role):
        answer = _solution()(pdu, role)
        return None if answer is None else bytes([answer[0], 2])

    assert "whole exception PDU" in _message("17.3", code)
    assert "exception 01" in _message("17.3", code_02)


def test_17_3_letting_everyone_read_or_write_is_refused():
    def everyone(pdu, role):
        return None if pdu else bytes([pdu[0] | 0x80, 1])

    assert "may not send this request" in _message("17.3", everyone)
    assert exercises.evaluate("17.3", exercises.EXERCISES["17.3"].wrong).ok is False
