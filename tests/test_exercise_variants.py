"""Exercises of notebooks 00-08 that ask about a variant of the example shown above them: the right
answer is the variant's, the example's own answer is refused, and the likely mistakes are named."""

from __future__ import annotations

import pytest

import modbus_edu as mb
from modbus_edu import exercises


@pytest.mark.parametrize(("key", "right", "example_answer"), [
    ("00.2", "03 00 6B 00 03", "03 00 00 00 01"),
    ("01.1", 249, 107),
    ("01.4", 60, 52),
    ("02.1", "10 00 04 00 02 04 01 F4 03 E8", "10 00 01 00 02 04 00 0A 01 02"),
    ("02.3", "84 02", "83 02"),
    ("03.1", "B2 98", "76 87"),
    ("03.4", 45, 25),
    ("04.3", 23, 17),
    ("06.4", mb.ModbusTimeoutError, mb.CrcError),
])
def test_the_variant_is_asked_not_the_example_above_it(key, right, example_answer):
    assert exercises.evaluate(key, right).ok is True
    assert exercises.evaluate(key, example_answer).ok is False


@pytest.mark.parametrize(("answer", "named"), [
    (11, "RTU frame"),
    (10, "number of bytes"),
    (21, "CR LF"),
    (22, "':'"),
    (25, "1-byte LRC"),
])
def test_the_ascii_length_exercise_names_each_miscount(answer, named):
    result = exercises.evaluate("04.3", answer)
    assert result.ok is False and named in result.message


def test_a_damaged_request_is_not_a_crc_error_at_the_master():
    result = exercises.evaluate("06.4", mb.CrcError)
    assert result.ok is False and "an answer to a damaged request" in result.message


def test_an_exception_for_the_wrong_function_is_named():
    result = exercises.evaluate("02.3", "83 02")
    assert result.ok is False and "input registers" in result.message


def test_renumbered_build_exercises_have_no_gap():
    keys = sorted(exercises.EXERCISES)
    for notebook in ("07", "08"):
        numbers = sorted(int(key[3:]) for key in keys if key.startswith(notebook + "."))
        assert numbers == list(range(1, len(numbers) + 1)), (notebook, numbers)
