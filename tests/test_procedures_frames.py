"""Diagnosis from the procedure, round two: the frame procedure every frame exercise shares (each field
written wrong, the envelope changed, and one of each), timing seen through the transaction's procedure in
every unit, the gateway of 15.2 whose CRC check is the CRC's procedure, and the address procedure.

``pytest tests/test_procedures_frames.py -s -k table`` prints the perturbations of these procedures.
"""

from __future__ import annotations

import pytest

import modbus_edu as mb
from modbus_edu.crc import crc_bytes
from modbus_edu.exercises import evaluate
from modbus_edu.exercises.checkers.nb04 import compare_characters
from modbus_edu.exercises.diagnosis.frames import frame_procedure, frame_verdict
from modbus_edu.exercises.diagnosis.gateway import GATEWAY
from modbus_edu.exercises.diagnosis.misconceptions import CATALOGUE, crc16_reflected
from modbus_edu.exercises.diagnosis.procedure import Perturbation, Procedure
from modbus_edu.exercises.diagnosis.procedures import ADDRESS
from modbus_edu.exercises.diagnosis.timing import RATE, T35, TRANSACTION_MS


def rtu(text: str, swapped: bool = False) -> str:
    data = bytes.fromhex(text)
    crc = crc_bytes(data)
    return (data + (crc[::-1] if swapped else crc)).hex(" ").upper()


def labels(message: str) -> set[str]:
    return {key for key, entry in CATALOGUE.items() if entry.label.lower() in message.lower()}


def test_a_frame_with_two_slips_is_named_for_both_in_every_frame_exercise():
    for key, text in (("00.3", "02 03 00 01 00 02"), ("03.2", "01 06 00 03 12 34")):
        message = evaluate(key, rtu(text, swapped=True)).message
        assert {"crc-swapped", "one-based-address"} <= labels(message), message


@pytest.mark.parametrize("key, answer, misconception", [
    ("00.3", rtu("02 03 00 00 02"), "field-in-one-byte"),            # the address in one byte
    ("00.3", rtu("02 03 00 00 00 02")[:-3], "crc-one-byte"),
    ("02.1", "10 00 04 02 04 01 F4 03 E8", "field-in-one-byte"),     # the quantity in one byte
    ("02.3", "01 84 02", "unit-in-pdu"),
    ("00.2", "01 03 00 6B 00 03", "unit-in-pdu"),
    ("11.2", "00 07 00 00 00 05 03 00 00 00 03", "unit-missing"),    # the length recounted without it
    ("04.2", ":0503100000021A\r\n", "lrc-plain-sum"),
    ("04.2", "050310000002E6\r\n", "ascii-colon-forgotten"),
    ("04.2", ":0503AC410002" + f"{-sum(bytes.fromhex('0503AC410002')) & 0xFF:02X}" + "\r\n",
     "reference-number"),
])
def test_frame_slips_the_frame_procedure_names(key, answer, misconception):
    message = evaluate(key, answer).message
    assert message.startswith("Not yet:") and misconception in labels(message), message


def test_the_frame_procedure_knows_every_mode_and_tells_the_field_and_the_envelope_apart():
    frame = mb.RtuFrame(unit=2, pdu=mb.ReadHoldingRegistersRequest(address=0, count=2)).encode()
    assert len(frame_procedure(frame, "rtu").perturbations) >= 60
    tcp = bytes.fromhex("00 07 00 00 00 06 01 06 00 00 04 D2")
    # a length that counts the PDU alone: one slip, not also "the length low byte first" that it overwrites
    words = frame_verdict(bytes.fromhex("00 07 00 00 00 05 01 06 00 00 04 D2"), tcp, "tcp")
    assert "mbap-length" in labels(words) and "or what" not in words, words
    ascii_frame = b":050310000002E6\r\n"
    assert "spaces" in frame_verdict(b":05 03 10 00 00 02 E6\r\n", ascii_frame, "ascii")
    assert "LF alone" in frame_verdict(b":050310000002E6\n", ascii_frame, "ascii")
    assert frame_procedure(b"\x01", "rtu") is None and frame_procedure(frame, "nope") is None


def test_an_ascii_character_is_named_by_its_field():
    message = compare_characters(b":050410000002E5\r\n", b":050310000002E6\r\n", "your frame")
    assert "the function code (characters 3-4), which should hold '03'" in message, message


def test_a_change_that_gives_the_right_answer_is_no_slip_and_one_slip_goes_before_two():
    procedure = Procedure("n", lambda: 5, (
        Perturbation("same", "nothing changed", "damaged-message-counted", lambda: 5),
        Perturbation("one", "one more", "damaged-message-counted", lambda: 6),
        Perturbation("two", "one more, twice over", "own-frames-counted", lambda: 6,
                     also="damaged-message-counted"),
    ))
    assert procedure.reproducing([((), 5)]) == []
    assert [item.key for item in procedure.reproducing([((), 6)])] == ["one"]


def test_timing_slips_read_the_same_in_every_unit():
    # 10 bits a character with even parity: 15.1 in ms, and the rate and the time at 19200 8E1
    assert "parity-bit-forgotten" in labels(evaluate("15.1", 12.5).message)
    assert "parity-bit-forgotten" in labels(RATE.explain([((19200, "E", 1, 8, 9), 1 / (24 * 10 / 19200))]))
    assert "parity-bit-forgotten" in labels(TRANSACTION_MS.explain([((19200, "E", 1, 8, 9), 12.5)]))
    assert "t15-for-t35" in labels(evaluate("08.1", 0.00344).message)
    assert "time-for-rate" in labels(evaluate("06.3", 0.01146).message)
    # a time in seconds where ms are asked, and the silence rounded by the learner
    assert "seconds-for-milliseconds" in labels(evaluate("06.1", 0.04167).message)
    # 23 characters: 3 characters for t3.5, or a frame counted one byte short: both named, neither chosen
    message = evaluate("15.1", 23 * 11 / 19200 * 1000).message
    assert "silences of 3 characters" in message and "one byte short" in message and not labels(message)
    assert T35.explain([((4800, "E", 1), 0.00175)]).startswith("your answer is what the fixed 1.75 ms")


def _gateway(check, order="little"):
    def gateway(frame, tid):
        if not check(frame[:-2]) == int.from_bytes(frame[-2:], order):
            raise mb.ModbusError("bad CRC")
        body = frame[:-2]
        return tid.to_bytes(2, "big") + bytes(2) + len(body).to_bytes(2, "big") + body
    return gateway


@pytest.mark.parametrize("function, misconception", [
    (_gateway(lambda data: crc16_reflected(data, initial=0)), "crc-initial-zero"),
    (_gateway(mb.crc16, "big"), "crc-swapped"),
    (_gateway(lambda data: mb.crc16(data[1:])), "checksum-without-address"),
])
def test_15_2_names_the_crc_slip_of_a_gateway_s_check_from_the_frames_it_refuses(function, misconception):
    message = evaluate("15.2", function).message
    assert labels(message) == {misconception}, message


def test_15_2_a_gateway_with_two_slips_is_named_for_both():
    def gateway(frame, tid):
        body = frame[:-2]
        return tid.to_bytes(2, "little") + bytes(2) + len(body).to_bytes(2, "big") + body
    message = evaluate("15.2", gateway).message
    assert {"mbap-little-endian", "invalid-input-accepted"} <= labels(message), message


@pytest.mark.parametrize("got", [400249, 300249, 40250, 40249, 30250])
def test_the_address_procedure_knows_every_form_of_a_reference_number(got):
    assert "reference-number" in labels(ADDRESS.explain([((250,), got)]))


def test_the_table_of_perturbations_of_the_shared_procedures(capsys):
    frame = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
    with capsys.disabled():
        for concept, procedure in (("frame (rtu)", frame_procedure(frame, "rtu")), ("t3.5", T35),
                                   ("gateway", GATEWAY), ("address", ADDRESS)):
            for item in (*procedure.perturbations, *procedure.forms):
                if "+" not in item.key:
                    print(f"{concept:<12} {item.step[:66]:<66} {item.misconception or '(in words)'}"
                          + (f" + {item.also}" if item.also else ""))
    assert len(GATEWAY.perturbations) >= 20
