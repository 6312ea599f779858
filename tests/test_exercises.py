"""The exercise machinery: build-exercise runner, answer readers and diagnoses, and robustness of check()."""

from __future__ import annotations

import ast
import re
import threading
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import modbus_edu as mb
from modbus_edu import exercises
from modbus_edu.exercises import core
from modbus_edu.exercises.build import build_exercise
from modbus_edu.exercises.misconceptions import crc16_reflected, crc16_unreflected

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def crc_exercise():
    """A build exercise registered for one test: the learner writes crc16."""
    item = build_exercise("99.1", "a CRC function", reference=mb.crc16,
                          inputs=lambda rng: (rng.randbytes(rng.randrange(0, 40)),),
                          edge_cases=[(b"",), (b"123456789",)], hint="shift right, XOR 0xA001",
                          wrong=lambda data: 0,
                          diagnose=lambda args, expected, got: core.crc_diagnosis(args[0], got))
    yield item
    del exercises.EXERCISES["99.1"]


@pytest.fixture
def parse_exercise():
    """A build exercise whose reference refuses some inputs (a bad CRC): the learner must raise there."""

    def reference(frame: bytes) -> tuple:
        decoded = mb.RtuFrame.decode(frame)
        return decoded.unit, decoded.pdu.encode()[0]

    def inputs(rng):
        request = mb.ReadHoldingRegistersRequest(address=rng.randrange(65536 - 9), count=9)
        frame = mb.RtuFrame(unit=rng.randrange(1, 248), pdu=request).encode()
        if rng.random() < 0.3:
            frame = frame[:-1] + bytes([frame[-1] ^ 1])
        return (frame,)

    item = build_exercise("99.2", "parse a frame", reference=reference, inputs=inputs, hint="check the CRC",
                          wrong=lambda frame: (frame[0], frame[1]))
    yield item
    del exercises.EXERCISES["99.2"]


def _crc(data: bytes) -> int:
    return crc16_reflected(data)


def test_a_right_function_is_accepted(crc_exercise):
    assert crc_exercise.kind == "build"
    result = exercises.evaluate("99.1", _crc)
    assert result.ok is True, result.message


def test_a_wrong_function_shows_the_first_failing_input_and_both_values(crc_exercise):
    result = exercises.evaluate("99.1", lambda data: 0)
    assert result.ok is False
    assert '<lambda>(bytes.fromhex("")) should give 65535 (0xFFFF); your function gives 0.' in result.message
    assert "a crc register started at 0: " in result.message.lower()
    assert "Modbus starts the register at 0xFFFF" in result.message
    assert "\nHint: shift right" in result.message


@pytest.mark.parametrize("variant, words", [
    (lambda data: ((_crc(data) & 0xFF) << 8) | (_crc(data) >> 8), "swapped CRC bytes"),
    (lambda data: mb.crc16(data).to_bytes(2, "little"), "a CRC returned as bytes"),
])
def test_the_crc_checker_names_the_usual_slips(crc_exercise, variant, words):
    assert words.lower() in exercises.evaluate("99.1", variant).message.lower()


def test_the_crc_checker_recognises_crc16_arc(crc_exercise):
    def arc(data):
        return crc16_reflected(data, initial=0)

    assert "starts the register at 0xFFFF" in exercises.evaluate("99.1", arc).message
    assert "CRC-16/ARC" in core.crc_diagnosis(b"123456789", arc(b"123456789"))
    assert "unreflected CRC" in core.crc_diagnosis(b"123456789", crc16_unreflected(b"123456789"))


@pytest.mark.parametrize("function, words", [
    (lambda data: 1 / 0, "raised ZeroDivisionError"),
    (lambda data: object(), "Your function returns an object; an int is expected"),
    (lambda data: "4B37", "Your function returns a str; an int is expected"),
    (lambda: 0, "raised TypeError"),
    (42, "asks for a function"),
])
def test_a_broken_function_gets_a_message_never_an_exception(crc_exercise, function, words):
    result = exercises.evaluate("99.1", function)
    assert result.ok is False
    assert words in result.message


def test_a_function_that_never_returns_is_stopped_after_the_time_limit(crc_exercise):
    def forever(data):
        while True:
            pass

    start = time.monotonic()
    result = exercises.evaluate("99.1", forever)
    assert result.ok is False and "did not finish within 2 s" in result.message
    assert time.monotonic() - start < 3.5
    time.sleep(0.1)
    assert not any(thread.name == "exercise 99.1" for thread in threading.enumerate())


def test_an_unwritten_function_is_not_answered_yet(crc_exercise):
    def crc16(data: bytes) -> int:
        """Your code here."""
        ...

    result = exercises.evaluate("99.1", crc16)
    assert result.ok is None and "not answered yet" in result.message and "Hint" not in result.message


def test_where_the_library_refuses_the_learners_function_must_raise(parse_exercise):
    def parse(frame):
        return mb.RtuFrame.decode(frame).unit, frame[1]

    assert exercises.evaluate("99.2", parse).ok is True
    result = exercises.evaluate("99.2", lambda frame: (frame[0], frame[1]))
    assert result.ok is False and "should raise an exception" in result.message


def test_the_generated_inputs_are_the_same_every_run(crc_exercise):
    first = [args for args, _ in crc_exercise.checker.cases()]
    crc_exercise.checker._cases = None
    assert [args for args, _ in crc_exercise.checker.cases()] == first
    assert len(first) == 102


@pytest.mark.parametrize("answer, words", [
    (0.02292, "seconds for milliseconds: the question asks for milliseconds"),
    (22.9, "close: give 2 decimals"),
    (23.917, "is not"),
    (22.92, None),
])
def test_number_answers_name_units_and_near_misses(answer, words):
    message = core.number_answer(answer, 22.917, decimals=2, unit="ms", what="the time")
    assert message is None if words is None else words in message


@pytest.mark.parametrize("answer, expected, unit, label", [
    (0.6, 60, "%", "a fraction for a percentage"), (60, 0.6, "", "a percentage for a fraction"),
    (22917, 22.917, "s", "milliseconds for seconds"),
])
def test_number_answers_name_the_catalogued_unit_slips(answer, expected, unit, label):
    assert core.number_answer(answer, expected, decimals=3, unit=unit).startswith(label + ":")


def test_address_slips_are_named():
    assert core.address_diagnosis(108, 107).startswith("a 1-based address:")
    assert core.address_diagnosis(40108, 107).startswith("a reference number for an address:")
    assert core.address_diagnosis(400108, 107).startswith("a reference number for an address:")
    assert core.address_diagnosis(107, 107) is None


def test_a_whole_frame_given_for_a_pdu_is_named():
    pdu = mb.ReadHoldingRegistersRequest(address=1, count=2).encode()
    frame = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=1, count=2)).encode()
    assert "whole frame" in core.compare_pdu(frame, pdu)


def test_byte_answers_never_allocate_from_an_int():
    with pytest.raises(core.AnswerError, match="not an int"):
        core.as_bytes(10**9)
    assert exercises.evaluate("04.2", 10**9).ok is False
    assert exercises.evaluate("03.2", 0x0103 << 40000).ok is False


def test_unanswered_prints_no_hint(capsys):
    result = exercises.check("03.1", ...)
    assert result.ok is None and not result
    assert capsys.readouterr().out.strip() == "Exercise 03.1 (a CRC in wire order) is not answered yet."


json_like = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20) | st.binary(max_size=20),
    lambda children: st.lists(children, max_size=5)
    | st.dictionaries(st.text(max_size=5), children, max_size=5),
    max_leaves=20)


class Hostile:
    """An answer whose every method raises."""

    def __getattribute__(self, name):
        raise RuntimeError(name)


@settings(max_examples=300, deadline=None)
@given(key=st.sampled_from(sorted(exercises.EXERCISES)), answer=json_like)
def test_any_json_like_answer_to_any_exercise_gives_a_message(key, answer):
    result = exercises.evaluate(key, answer)
    assert result.ok in (True, False) and len(result.message) <= 1000


@pytest.mark.parametrize("key", sorted(exercises.EXERCISES))
def test_deep_nesting_hostile_objects_and_odd_keys_give_a_message(key):
    deep: list = []
    for _ in range(50_000):
        deep = [deep]
    for answer in (deep, Hostile(), 10**5000, float("nan"), {1: {2: 3}}, {1, 2}):
        assert exercises.evaluate(key, answer).ok is False
    assert exercises.evaluate({"unhashable": 1}, 1).ok is False
    assert exercises.evaluate(["03.1"], 1).ok is False


# --- the catalogue of misconceptions, and every exercise's tables of accepted and refused answers -----

from modbus_edu.exercises.misconceptions import CATALOGUE  # noqa: E402

VALUE_KEYS = sorted(key for key, item in exercises.EXERCISES.items() if item.kind == "value")
ALL_KEYS = sorted(exercises.EXERCISES)
ACCEPTED = [(key, index) for key in VALUE_KEYS for index in range(len(exercises.EXERCISES[key].accepts))]
REFUSED = [(key, index) for key in ALL_KEYS for index in range(len(exercises.EXERCISES[key].refuses))]


def test_each_misconception_has_a_key_a_label_a_detector_shape_and_one_teaching_sentence():
    assert len(CATALOGUE) >= 11
    for key, entry in CATALOGUE.items():
        assert entry.key == key and entry.label and entry.shape and callable(entry.detector)
        fields = {name: "ABCD" for name in re.findall(r"{(\w+)}", entry.sentence)}  # each a short word
        assert entry.sentence.rstrip().endswith(".") and len(entry.say(**fields)) < 320, key
    for key in ("crc-swapped", "crc-on-tcp", "lrc-ones-complement", "one-based-address", "reference-number",
                "milliseconds-for-seconds", "seconds-for-milliseconds", "fraction-for-percentage",
                "mbap-little-endian", "word-order", "frame-for-pdu", "ascii-without-crlf"):
        assert key in CATALOGUE


def test_every_misconception_is_named_by_some_exercise():
    named = {misconception for item in exercises.EXERCISES.values() for _, misconception in item.refuses}
    named.add("fraction-for-percentage")  # no exercise asks for a percentage: number_answer's test names it
    # 14.3's count alone cannot tell these from another slip that gives the same number: its verdict names
    # the candidates in words (test_14_3_names_the_mistake), and the message count's procedure keeps them
    named |= {"damaged-message-counted", "count-request-forgotten"}
    assert set(CATALOGUE) <= named, f"catalogued but never named: {sorted(set(CATALOGUE) - named)}"


@pytest.mark.parametrize("key", ALL_KEYS)
def test_every_exercise_keeps_its_tables(key):
    item = exercises.EXERCISES[key]
    assert item.refuses, f"{key} lists no known wrong answer"
    if item.kind == "value":
        assert item.accepts, f"{key} lists no accepted answer"
    else:
        assert any(misconception for _, misconception in item.refuses), f"{key} names no misconception"


@pytest.mark.parametrize("key, index", ACCEPTED, ids=[f"{k}-accepts-{i}" for k, i in ACCEPTED])
def test_each_accepted_answer_is_right(key, index):
    answer = exercises.EXERCISES[key].accepts[index]
    result = exercises.evaluate(key, answer)
    assert result.ok is True, f"{key} refuses {answer!r}: {result.message}"


@pytest.mark.parametrize("key, index", REFUSED, ids=[f"{k}-refuses-{i}" for k, i in REFUSED])
def test_each_known_wrong_answer_is_refused_and_named(key, index):
    answer, misconception = exercises.EXERCISES[key].refuses[index]
    result = exercises.evaluate(key, answer)
    assert result.ok is False, f"{key} accepts the wrong answer {answer!r}"
    assert result.message.startswith("Not yet:")
    if misconception is None:
        named = [entry.label for entry in CATALOGUE.values() if entry.label.lower() in result.message.lower()]
        assert not named, f"{key}: {answer!r} is named {named} but is no catalogued misconception"
    else:
        label = CATALOGUE[misconception].label.lower()
        assert label in result.message.lower(), f"{key}: {answer!r} should be {label!r}: {result.message}"


def test_a_build_exercise_reads_back_what_the_function_stored():
    """A function that answers right but stores nothing fails on the read that follows its write."""

    def reference(store: list, index: int, value: int | None) -> int:
        if value is not None:
            store[index] = value
        return store[index]

    item = build_exercise("99.3", "a store", reference=reference,
                          inputs=lambda rng: ([0] * 4, rng.randrange(4), rng.choice([None, 1, 2, 3])),
                          hint="store it", refuses=[(lambda store, index, value: value, None)],
                          read_back=lambda args, state: args[2] and (state[0], args[1], None))
    try:
        def stores(store, index, value):
            if value is not None:
                store[index] = value
            return store[index]

        assert exercises.evaluate("99.3", stores).ok is True
        result = exercises.evaluate("99.3", lambda store, index, value: value or store[index])
        assert result.ok is False and "reading it back with" in result.message
        assert item.wrong is item.refuses[0][0]
    finally:
        del exercises.EXERCISES["99.3"]


def test_the_fixed_checkers_judge_right():
    from modbus_edu.exercises.checkers.nb01 import _tables_by_digit
    from modbus_edu.exercises.checkers.nb06 import _echo_without_storing

    assert "frozenset" not in exercises.evaluate("13.7", lambda registers, expected: "ABCD").message
    echoed = exercises.evaluate("06.5", _echo_without_storing)
    assert "a write echoed but not stored" in echoed.message.lower()
    assert exercises.evaluate("13.2", ("CDAB", 135.5)).ok is True
    for spelling in ("Length field", "the length", "length"):
        assert exercises.evaluate("05.4", spelling).ok is True
    assert "is right in that frame" not in exercises.evaluate("05.4", "protocol identifier").message
    assert "CR LF" in exercises.evaluate("04.2", ":050310000002E6").message
    assert "a 2x table" in exercises.evaluate("01.5", _tables_by_digit).message.lower()


def test_a_refusal_table_may_only_name_catalogued_misconceptions():
    with pytest.raises(ValueError, match="not in the catalogue"):
        exercises.exercise("99.4", "x", hint="h", refuses=[(1, "no-such-slip")])(lambda answer: None)
    assert "99.4" not in exercises.EXERCISES


# --- checkers that teach, hints that do not tell ----------------------------------------------------------
def _code(text: str) -> str:
    """``text`` as code compares: no spaces, one kind of quote."""
    return re.sub(r"\s+", "", text).replace('"', "'")


def _skeleton(text: str) -> str:
    """The calls and names of ``text`` without their values (numbers, or ``...`` left to fill in): what a
    line hands out whatever its numbers."""
    return re.sub(r"[^A-Za-z_.(]", "", text.replace("...", ""))


def _expressions(line: str) -> list[str]:
    """The innermost bracketed expressions of ``line`` that compute something (an operator inside)."""
    found = [_code(inner) for inner in re.findall(r"\(([^()]*)\)", line)]
    return [inner for inner in found if len(inner) >= 8 and re.search(r"[&|^~+*/-]", inner)]


def solution_lines(key: str) -> list[str]:
    """The lines of exercise ``key``'s worked solution that do its work: the value given as the answer (a
    call or an expression, not a bare name or literal), what its functions return, and the body of a loop
    at the top of the file."""
    source = (ROOT / "notebooks" / exercises.EXERCISES[key].solution).read_text()
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "answer" for t in node.targets):
            if not isinstance(node.value, (ast.Name, ast.Constant)):
                lines.append(ast.get_source_segment(source, node.value))
        elif isinstance(node, ast.Return) and node.value is not None \
                and not isinstance(node.value, (ast.Name, ast.Constant)):
            lines.append(ast.get_source_segment(source, node.value))
        elif isinstance(node, ast.For) and node.col_offset == 0:
            lines += [ast.get_source_segment(source, statement) for statement in node.body]
    return [line for line in lines if len(_code(line)) >= 12]


def test_no_hint_level_holds_a_worked_solution_s_line():
    """Hints escalate from the idea to the step to a worked example on other numbers: no level holds an
    exercise's own line, and the idea (the first level) holds neither its call with the numbers left out
    nor the line of another exercise of the course."""
    keys = sorted(exercises.EXERCISES)
    lines = {key: solution_lines(key) for key in keys}
    assert sum(map(len, lines.values())) > 60 and lines["00.3"] and lines["09.2"] and lines["14.2"]
    for key in keys:
        idea = exercises.EXERCISES[key].hint
        levels = [idea, *core.LINES.get(key, ())]
        for other in keys:
            for line in lines[other]:
                for level in levels:
                    assert _code(line) not in _code(level), (key, other, line)
        for line in lines[key]:
            if "(" in line and len(_skeleton(line)) >= 12:
                assert _skeleton(line) not in _skeleton(idea), (key, line)
        for other in (k for k in keys if k[:2] == key[:2]):  # nor an expression of its notebook's lines
            for line in lines[other]:
                for expression in _expressions(line):
                    assert expression not in _code(idea), (key, other, expression)


def test_hints_escalate_one_level_per_wrong_try_and_start_again_when_right(capsys):
    assert {"00.3", "02.5", "04.5", "07.2", "09.2", "12.3", "14.2", "17.2"} <= set(core.LINES)
    for key, levels in core.LINES.items():
        assert levels and all(isinstance(level, str) and level for level in levels), key
        assert exercises.EXERCISES[key].hint not in levels
    key = "04.5"
    step, example = core.LINES[key]
    core.wrong_tries.pop(key, None)
    wrong = exercises.EXERCISES[key].wrong
    first = exercises.check(key, wrong)
    assert first.ok is False and "Hint:" in first.message and step not in first.message
    second = exercises.check(key, wrong)
    assert second.message.endswith(f"After 2 tries, the next step: {step}") and example not in second.message
    third = exercises.check(key, wrong)
    assert third.message.endswith(f"After 2 tries, the next step: {step}\n"
                                  f"After 3 tries, the same idea on other numbers: {example}")
    assert example in capsys.readouterr().out
    def lrc(data: bytes) -> int:  # a learner's own, right LRC (the library's own function is refused)
        return -sum(data) & 0xFF

    assert exercises.check(key, lrc).ok is True and key not in core.wrong_tries  # right: counted afresh
    assert step not in exercises.check(key, wrong).message
    assert exercises.evaluate(key, wrong).message == first.message  # evaluate counts nothing
    core.wrong_tries.pop(key, None)


def test_a_frame_built_by_hand_names_the_slip_in_the_catalogue_s_words_not_a_byte_number():
    from modbus_edu.exercises.diagnosis.frameslip import frame_slip

    messages = {key: exercises.evaluate(key, answer).message for key, answer in [
        ("02.1", "10 00 04 00 02 04 05 00 10 00"), ("03.2", "01 06 00 02 34 12 BE C7"),
        ("05.2", "00 07 00 00 00 06 01 06 00 00 12 34"), ("07.2", "17 81 02 20 55")]}
    assert all("differs at byte" not in message for message in messages.values()), messages
    assert "500 is a decimal number: in hex it is 0x01F4 (hex(500)), while 0x0500 is 1280" in messages["02.1"]
    assert "4660 (0x1234) is 12 34, and 34 12 reads as 13330 (0x3412)" in messages["03.2"]
    assert "1234 is a decimal number: in hex it is 0x04D2" in messages["05.2"]
    assert "17 is a decimal number: in hex it is 0x11 (hex(17)), while 0x17 is 23" in messages["07.2"]
    # an RTU frame's CRC follows the bytes before it: it is left out; two slips at once are not one slip
    assert frame_slip(bytes.fromhex("01 06 00 02 34 12 00 00"), bytes.fromhex("01 06 00 02 12 34 25 7D"),
                      tail=2).startswith("a 16-bit field low byte first")
    assert frame_slip(bytes.fromhex("10 00 04 00 02 04 05 00 E8 03"),
                      bytes.fromhex("10 00 04 00 02 04 01 F4 03 E8")) is None
    assert frame_slip(b"\x01", bytes.fromhex("01 02")) is None


def test_counterexamples_are_written_the_way_the_exercise_writes_its_inputs():
    import struct

    float_message = exercises.evaluate(
        "10.4", lambda registers, order: struct.unpack(">f", struct.pack(">HH", *registers))[0]).message
    assert "([0xCCCD, 0x43C9], 'CDAB')" in float_message  # registers in hex, as 10.4 writes them
    from modbus_edu.exercises.checkers.nb08 import _transaction_time

    timing = exercises.evaluate("08.4", lambda baudrate, *args:  # right, except above 19200 baud
                                _transaction_time(baudrate, *args) if baudrate <= 19200 else 0.0).message
    assert "(38400, 'N', 2, 8, 7)" in timing and "0x9600" not in timing  # a baud rate in decimal
    assert core.show(core.Written(38400)) == "38400"
    assert core.show(core.Written(0x43C9, "0x{:04X}")) == "0x43C9"
    assert str(core.Written(0x43C9, "0x{:04X}")) == "17353" and core.Written(7) + 1 == 8


def test_a_list_of_one_frame_is_one_frame():
    message = exercises.evaluate("16.2", ["01 04 00 00 00 02 71 CB"]).message
    assert "you give 1 frame;" in message


def test_the_catalogue_states_each_silence_with_its_limit_and_each_reason_for_silence_apart():
    timers = ("one-character-for-t35", "t15-forgotten", "silences-forgotten", "fixed-silence-ignored",
              "t15-for-t35")
    for key in timers:  # character times hold at 19200 baud or below; fixed times above
        assert "19200 baud" in CATALOGUE[key].sentence and "ms" in CATALOGUE[key].sentence, key
    assert "processing time" in CATALOGUE["silences-forgotten"].sentence
    refusal = CATALOGUE["illegal-function-for-address"].sentence
    assert "state" in refusal and "role" in refusal  # exception 01 is more than "not implemented"
    damaged, other = CATALOGUE["answer-to-damaged-request"], CATALOGUE["answer-to-another-unit"]
    assert "another unit" not in damaged.sentence and "CRC" not in other.sentence
    assert "another unit" in exercises.evaluate("07.3", dict.fromkeys(
        ("request for a unit nobody has", "one bit flipped in the request", "one bit flipped in the response",
         "read of an address the slave does not have", "response carries another unit id"),
        "exception")).message
