"""Diagnosis from the procedure (modbus_edu.exercises.diagnosis): each concept's procedure computes the
library's answer, each perturbation changes it, and the checkers that share a procedure say the same thing
about the same slip.  Also the verdicts issue 38 found wrong: the slips accepted, the slips named wrongly,
and the generic verdicts.

``pytest tests/test_procedures.py -s -k table`` prints the perturbations each concept's procedure knows.
"""

from __future__ import annotations

import math
import random

import pytest

import modbus_edu as mb
from modbus_edu.exercises import EXERCISES, evaluate
from modbus_edu.exercises.checkers.nb06 import _slave_answer
from modbus_edu.exercises.core import compare_bytes
from modbus_edu.exercises.diagnosis.misconceptions import CATALOGUE
from modbus_edu.exercises.diagnosis.procedure import NOT_APPLICABLE, Choices, Perturbation, Procedure, say
from modbus_edu.exercises.diagnosis.procedures import (
    ANSWERED,
    CRC,
    CRC_WIRE,
    FLOAT32,
    LRC,
    MBAP,
    PROCEDURES,
    TRANSACTION_TIME,
    message_count_procedure,
    rtu_frame_procedure,
)
from modbus_edu.values import decode_value, encode_value

RNG = random.Random(38)
SAMPLES = {
    "crc": [(RNG.randbytes(n),) for n in (1, 2, 6, 40, 300)],
    "crc-wire": [(RNG.randbytes(n),) for n in (2, 6, 40, 300)],
    "lrc": [(RNG.randbytes(n),) for n in (1, 6, 40, 300)] + [(b"\x80\x80",)],
    "mbap": [(280, 1, bytes.fromhex("03 00 00 00 01")), (65535, 255, bytes(30))],
    "transaction-time": [
        (b, p, s, 8, 7) for b in (1200, 9600, 19200, 38400, 115200) for p in "NE" for s in (1, 2)
    ],
    "address": [(1,), (10,), (9999,)],
    "float32": [(list(encode_value(403.6, "float32", order)), order) for order in mb.ORDERS],
    "answered": [(2.0, 1.0, 0.02), (0.5, 1.0, 0.1), (1.0, 0.01, 0.02), (3.0, 2.0, 0.5)],
}
"""Inputs on which every perturbation of a procedure must show (each differs from the right answer once)."""


def label(key: str) -> str:
    """A misconception's label as a verdict may write it (its first letter capital or not)."""
    return CATALOGUE[key].label[1:]


@pytest.mark.parametrize("concept", sorted(PROCEDURES))
def test_every_perturbation_changes_the_answer_and_points_to_a_catalogued_misconception(concept):
    procedure = PROCEDURES[concept]
    for item in (*procedure.perturbations, *procedure.forms):
        assert item.misconception is None or item.misconception in CATALOGUE, (concept, item.key)
        assert item.also is None or item.also in CATALOGUE, (concept, item.key)
    for item in procedure.candidates():
        assert any(_changes(procedure, item, args) for args in SAMPLES[concept]), (
            f"{concept}: {item.key} gives the right answer on every sample"
        )


def _changes(procedure: Procedure, item: Perturbation, args: tuple) -> bool:
    """Whether the perturbation ``item`` gives something else than the right answer for ``args`` (for a
    change that may go several ways, one of its ways)."""
    mine, right = item.answer(*args), procedure.right(*args)
    if mine is NOT_APPLICABLE:
        return False
    return any(not procedure.same(one, right) for one in (mine if isinstance(mine, Choices) else [mine]))


def test_the_procedures_compute_what_the_library_computes():
    assert CRC.right(b"123456789") == mb.crc16(b"123456789") == 0x4B37
    assert CRC_WIRE.right(b"123456789") == b"\x37\x4b"
    assert LRC.right(bytes.fromhex("050610010200")) == 0xE2
    frame = mb.TcpFrame(transaction_id=280, unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1))
    assert MBAP.right(280, 1, frame.pdu.encode()) == frame.encode()[:7]
    assert math.isclose(TRANSACTION_TIME.right(9600, "N", 1, 8, 7), 22 * 10 / 9600)
    assert math.isclose(FLOAT32.right([0x43C9, 0xCCCD], "ABCD"), 403.6, rel_tol=1e-6)
    assert ANSWERED.right(2.0, 1.0, 0.2) == pytest.approx(0.4)


def test_the_table_of_perturbations(capsys):
    with capsys.disabled():
        print(
            "\nconcept            perturbation (the step changed)" + " " * 32 + "misconception"
        )
        for concept, procedure in sorted(PROCEDURES.items()):
            for item in (*procedure.perturbations, *procedure.forms):
                print(
                    f"{concept:<18} {item.step[:62]:<62} {item.misconception or '(none: named in words)'}"
                    + (f" + {item.also}" if item.also else "")
                )
        frame = rtu_frame_procedure(1, mb.ReadHoldingRegistersRequest(address=0, count=1))
        for item in frame.perturbations:
            print(f"{'rtu-frame':<18} {item.step[:62]:<62} {item.misconception}")
        for item in message_count_procedure(5, own_responses=2, own_requests=2).perturbations:
            print(
                f"{'message-count':<18} {item.step[:62]:<62} {item.misconception or '(none: named in words)'}"
            )
    assert sum(len(procedure.perturbations) for procedure in PROCEDURES.values()) >= 40


def test_several_changes_that_fit_name_the_candidates_not_one_misconception():
    procedure = Procedure(
        "a count",
        lambda: 5,
        (
            Perturbation("a", "one thing counted twice", "damaged-message-counted", lambda: 6),
            Perturbation("b", "another thing counted", None, lambda: 6),
            Perturbation("c", "only its own counted", "others-not-heard", lambda: 2),
        ),
    )
    both = say(procedure.reproducing([((), 6)]))
    assert "one thing counted twice" in both and "another thing counted" in both
    assert not [entry.label for entry in CATALOGUE.values() if entry.label.lower() in both.lower()]
    assert label("others-not-heard") in say(procedure.reproducing([((), 2)]))
    assert procedure.reproducing([((), 7)]) == []
    choices = Procedure(
        "an order",
        lambda: "ABCD",
        (Perturbation("x", "any order", "word-order", lambda: Choices(["CDAB", "DCBA"])),),
    )
    assert choices.reproducing([((), "DCBA")]) and not choices.reproducing([((), "BADC")])


# --- one slip, one name: the exercises that share a procedure -----------------------------------------

CRC_SLIPS = {
    "crc-initial-zero": lambda data: CRC.perturbation("initial-zero").compute(data),
    "crc-msb-first": lambda data: CRC.perturbation("unreflected").compute(data),
    "crc-swapped": lambda data: CRC.perturbation("high-first").compute(data),
}


@pytest.mark.parametrize("misconception", sorted(CRC_SLIPS))
def test_03_1_and_03_5_name_the_same_crc_slip_the_same_way(misconception):
    wrong = CRC_SLIPS[misconception]
    data = bytes.fromhex("11 04 00 08 00 01")
    as_value = evaluate("03.1", wrong(data).to_bytes(2, "little")).message
    as_function = evaluate("03.5", lambda data: wrong(data)).message
    assert label(misconception) in as_value and label(misconception) in as_function, (as_value, as_function)


def test_03_1_names_a_crc_over_the_pdu_only():
    data = bytes.fromhex("11 04 00 08 00 01")
    assert (
        label("checksum-without-address")
        in evaluate("03.1", mb.crc16(data[1:]).to_bytes(2, "little")).message
    )


# --- issue 38: the slips accepted, named wrongly, or given a generic verdict --------------------------


def test_a_right_value_in_another_form_is_told_so_not_accepted():
    for key, answer, words in (
        ("01.2", "300010", "5-digit"),
        ("04.2", ":050310000002e6\r\n", "upper-case"),
        ("06.4", mb.ModbusTimeoutError("x"), "not an instance"),
    ):
        result = evaluate(key, answer)
        assert result.ok is False and "the value is right" in result.message and words in result.message, key
    assert evaluate("01.2", "30010").ok and evaluate("04.2", ":050310000002E6\r\n").ok
    assert evaluate("06.4", mb.ModbusTimeoutError).ok


def test_03_5_tries_data_longer_than_256_bytes_and_says_so():
    result = evaluate("03.5", lambda data: mb.crc16(data[:256]))
    assert result.ok is False and "more than 256" in result.message


def test_03_5_empty_input_returning_0_is_not_told_register_started_at_0():
    message = evaluate("03.5", lambda data: mb.crc16(data) if data else 0).message
    assert label("crc-initial-zero") not in message and "empty" in message


def test_09_3_judges_the_longest_loop_without_the_reply_by_arithmetic():
    message = evaluate("09.3", 1.815).message
    assert message.startswith("Not yet:") and label("reply-time-forgotten") in message
    assert evaluate("09.3", 1.83).ok and evaluate("09.3", 1.9).ok


def test_08_4_the_fixed_silence_at_19200_is_named_as_such():
    def fixed_from_19200(baudrate, parity, stopbits, request, response):
        char = (1 + 8 + (parity != "N") + stopbits) / baudrate
        return (request + response) * char + 2 * (0.00175 if baudrate >= 19200 else 3.5 * char)

    message = evaluate("08.4", fixed_from_19200).message
    assert label("fixed-silence-at-19200") in message and label("three-characters-for-t35") not in message


def test_09_4_timeout_plus_reply_is_not_told_missed_for_answered():
    message = evaluate(
        "09.4", lambda loop, timeout, reply: min(1.0, (timeout + reply) / loop) if loop else 1.0
    )
    assert message.ok is False and label("missed-for-answered") not in message.message
    assert "added" in message.message


def test_10_4_a_constant_is_not_told_rounded_inside_the_function():
    message = evaluate("10.4", lambda registers, order: 403.6).message
    assert message.startswith("Not yet:") and label("result-rounded") not in message


def test_13_7_two_orders_with_a_tolerance_is_not_told_floats_compared_exactly():
    def two_orders(registers, value):
        return next(
            (
                order
                for order in ("ABCD", "CDAB")
                if math.isclose(decode_value(registers, "float32", order), value, rel_tol=1e-6)
            ),
            None,
        )

    message = evaluate("13.7", two_orders).message
    assert label("float-compared-exactly") not in message and "only ABCD and CDAB tried" in message


def test_14_3_names_the_candidates_when_the_count_alone_cannot_tell():
    message = evaluate("14.3", 6).message
    assert "the clear request" in message and "damaged frame" in message
    assert label("damaged-message-counted") not in message


def test_00_3_given_a_tcp_frame_says_rtu_versus_tcp():
    message = evaluate("00.3", "00 01 00 00 00 06 02 03 00 00 00 02").message
    assert label("tcp-frame-for-rtu") in message


def test_13_1_swapped_causes_say_which_trace_rules_the_cause_out():
    message = evaluate(
        "13.1", {"A": "no slave on the line", "B": "wrong unit id", "C": "wrong baud rate or parity"}
    ).message
    assert label("causes-swapped") in message and "because of a no slave" not in message


def test_06_5_names_an_off_by_one_range_and_little_endian_registers_as_02_5_does():
    def little_endian(registers, pdu):
        answer = _slave_answer(registers, pdu)
        if answer[0] != 3:
            return answer
        return answer[:2] + b"".join(bytes(reversed(answer[i : i + 2])) for i in range(2, len(answer), 2))

    def past_the_end(registers, pdu):
        address, count = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
        if (
            pdu[0] == 3
            and 1 <= count <= 125
            and address < len(registers) < address + count <= len(registers) + 1
        ):
            return bytes([3, 2 * count]) + b"".join(
                r.to_bytes(2, "big") for r in (list(registers) + [0])[address:]
            )
        return _slave_answer(registers, pdu)

    assert label("field-low-byte-first") in evaluate("06.5", little_endian).message
    message = evaluate("06.5", past_the_end).message
    assert label("invalid-input-accepted") in message and "go past the last one" in message


def test_differs_at_byte_n_names_the_field_and_what_it_should_hold():
    expected = bytes.fromhex("02 03 00 00 00 02 C4 38")
    message = compare_bytes("02 03 00 00 00 03 C4 38", expected, "your frame")
    assert "in the quantity (bytes 4-5), which should hold 00 02" in message
    tcp = compare_bytes("00 01 00 00 00 07 01 03 00 00 00 01", bytes.fromhex("000100000006010300000001"), "x")
    assert "length (bytes 4-5)" in tcp
    short = compare_bytes("02 03 00 00", expected, "your frame").lower()
    assert "what is missing starts with the quantity" in short


def test_every_build_exercise_with_a_procedure_names_its_own_perturbations():
    for key, item in EXERCISES.items():
        procedure = getattr(item.checker, "procedure", None) if item.kind == "build" else None
        if procedure is None or key == "13.7":
            continue
        for perturbation in procedure.perturbations[:6]:
            skipped = perturbation.misconception is None or perturbation.also
            if skipped or perturbation.key == "another-order":
                continue
            result = evaluate(key, lambda *args, p=perturbation: p.compute(*args))
            if result.ok is False and "raised" not in result.message:
                assert (
                    label(perturbation.misconception) in result.message or "cannot tell" in result.message
                ), (key, perturbation.key, result.message)
