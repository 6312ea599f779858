"""Every checker answers an answer of the wrong type or shape with a verdict that teaches.

Hypothesis draws answers a learner may type by mistake (ints, floats, strings, bytes, None, nested
lists, tuples and dicts, huge and odd values, answers shaped almost like the right one) for every exercise:
each gets a Result whose message names no Python exception and is no internal failure of the checker.
Seeded and bounded: a few dozen answers per exercise.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st
from test_slips import python_errors

from modbus_edu import exercises

INTERNAL = "the checker cannot read your answer"
"""The words of :func:`modbus_edu.exercises.core._result` when a checker itself failed on an answer."""

odd_numbers = (st.integers(min_value=-(2**70), max_value=2**70) | st.just(10**400) | st.just(-1)
               | st.floats(allow_nan=True, allow_infinity=True) | st.just(1e308) | st.just(2**63 - 0.5))
odd_text = (st.text(max_size=30) | st.sampled_from(["", " ", "0x", ":", ":\r\n", "socket://", "socket://h:",
                                                    "socket://h:x", "30010 ", "4x0001", "0x1.8p3", "ABCD",
                                                    "1e5", "nan", "inf", "-1", "٣", "\x00", "0x" + "F" * 40]))
leaves = st.none() | st.booleans() | odd_numbers | odd_text | st.binary(max_size=30)
answers = st.recursive(
    leaves,
    lambda children: st.lists(children, max_size=6) | st.tuples(children, children)
    | st.tuples(children, children, children) | st.tuples(children, children, children, children)
    | st.dictionaries(st.text(max_size=4) | st.integers(-3, 300), children, max_size=6)
    | st.frozensets(st.integers(-3, 300), max_size=5) | st.sets(st.integers(-3, 300), max_size=5),
    max_leaves=12)


@pytest.mark.parametrize("key", sorted(exercises.EXERCISES))
def test_an_answer_of_any_type_or_shape_gets_a_verdict_that_teaches(key):
    @seed(20261128)
    @settings(max_examples=30, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
    @given(answer=answers)
    def judged(answer):
        result = exercises.evaluate(key, answer)
        assert result.ok in (True, False), (key, answer, result.message)
        assert not python_errors(result.message, answer), (key, answer, result.message)
        assert INTERNAL not in result.message, (key, answer, result.message)

    judged()


def test_a_register_map_answer_is_always_read_as_text_never_as_a_path(tmp_path):
    """A one-line answer to 16.1 is the map's text: naming a file that holds the right map is not an answer
    (the grader never reads a path a learner's answer names)."""
    from modbus_edu.exercises.checkers.nb16 import _WORKSHEET_MAP

    right = tmp_path / "map.csv"
    right.write_text(_WORKSHEET_MAP, encoding="utf-8")
    assert exercises.evaluate("16.1", _WORKSHEET_MAP).ok is True
    result = exercises.evaluate("16.1", str(right))
    assert result.ok is False and INTERNAL not in result.message


@pytest.mark.parametrize("key, answer", [("12.3", (283, 10**9)), ("13.4", (768, 10**9)),
                                         ("02.4", (1e308, float("inf"))), ("08.3", [10**400])])
def test_a_huge_number_where_bytes_or_a_list_belong_is_refused_without_building_it(key, answer):
    result = exercises.evaluate(key, answer)
    assert result.ok is False and INTERNAL not in result.message and not python_errors(result.message, answer)
