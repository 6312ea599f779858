"""Diagnosis from the procedure, round three: what was asked, not how it was computed.

- a right value in another form (an int where the reference number's text is asked, lowercase hex in an
  ASCII frame, an instance or a name where the class is asked, 6 digits where 5) is "the right value in
  another form", and the verdict says what the usual form is;
- a part of the asked bytes is "part of the answer", with the fields it holds; the answer to another
  question (the whole frame for its CRC, an RTU frame where Modbus/TCP is asked) is named as such;
- the CRC of a frame built by hand goes through the CRC procedure's steps (:mod:`.diagnosis.crcsteps`), so
  a frame whose CRC register started at 0 is named so in every frame exercise;
- build exercises 16.4 and 17.3 are tried on the inputs that separate their last two accepted slips.
"""

from __future__ import annotations

import pytest

import modbus_edu as mb
from modbus_edu.exercises import evaluate
from modbus_edu.exercises.build import _fits_every_answer
from modbus_edu.exercises.checkers.nb16 import _every_echo
from modbus_edu.exercises.checkers.nb17 import _common_only, _reference
from modbus_edu.exercises.core import bytes_diagnosis, compare_bytes, part_diagnosis
from modbus_edu.exercises.diagnosis.crcsteps import CRC_STEPS, REGISTER_SLIPS
from modbus_edu.exercises.diagnosis.frames import frame_procedure, frame_verdict
from modbus_edu.exercises.diagnosis.misconceptions import CATALOGUE, crc16_reflected, crc16_unreflected
from modbus_edu.exercises.plain import plain


def labels(message: str) -> set[str]:
    return {key for key, entry in CATALOGUE.items() if entry.label.lower() in message.lower()}


@pytest.mark.parametrize("key, answer, usual", [
    ("01.2", 30010, "'30010'"),
    ("01.2", 30010.0, "'30010'"),
    ("01.2", "300010", "5-digit"),
    ("03.1", 0x98B2, "low byte first"),
    ("04.2", ":050310000002e6\r\n", "upper-case"),
    ("06.4", mb.ModbusTimeoutError("no answer"), "the class itself"),
    ("06.4", "ModbusTimeoutError", "not its name as text"),
    ("06.4", "mb.ModbusTimeoutError", "not its name as text"),
    ("12.1", "150", "0x and four hex digits"),
])
def test_a_right_value_in_another_form_is_told_so_with_the_usual_form(key, answer, usual):
    result = evaluate(key, answer)
    assert result.ok is False and labels(result.message) == {"another-form"}, result.message
    assert usual in result.message


def test_a_wrong_value_in_another_form_is_never_called_right():
    for key, answer in (("01.2", 30011), ("01.2", "300011"), ("06.4", "ModbusError")):
        message = evaluate(key, answer).message
        assert "another-form" not in labels(message) and "value is right" not in message, (key, message)


def _frame(data: str, register: int) -> bytes:
    body = bytes.fromhex(data)
    return body + register.to_bytes(2, "little")


@pytest.mark.parametrize("key, body", [
    ("00.3", "02 03 00 00 00 02"), ("03.2", "01 06 00 02 12 34"), ("07.2", "11 81 02"),
    ("13.5", "01 03 00 00 00 01"),
])
def test_a_crc_slip_in_a_frame_built_by_hand_is_named_from_the_crc_procedure(key, body):
    data = bytes.fromhex(body)
    for compute, misconception in ((lambda d: crc16_reflected(d, initial=0), "crc-initial-zero"),
                                   (crc16_unreflected, "crc-msb-first")):
        message = evaluate(key, _frame(body, compute(data))).message
        assert labels(message) == {misconception}, (key, message)
        assert "faulty tool" not in message  # 13.5's note belongs to the swapped CRC alone
    final_xor = evaluate(key, _frame(body, mb.crc16(data) ^ 0xFFFF)).message
    assert "final XOR with 0xFFFF" in final_xor and "differs at byte" not in final_xor


def test_the_frame_procedure_takes_every_register_slip_of_the_crc_procedure():
    frame = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
    keys = {item.key for item in frame_procedure(frame, "rtu").perturbations}
    register_slips = [key for key, *_ in CRC_STEPS if key in REGISTER_SLIPS]
    assert len(register_slips) == len(REGISTER_SLIPS) >= 4
    assert {f"crc-{key}" for key in register_slips} <= keys


def test_part_of_the_asked_bytes_is_named_with_the_fields_it_holds():
    message = evaluate("13.5", "84 0A").message
    assert labels(message) == {"part-of-answer"}
    assert "the CRC (bytes 6-7)" in message and "all 8 bytes" in message
    prefix = compare_bytes("02 03 00 00", bytes.fromhex("02 03 00 00 00 02 C4 38"), "your frame")
    assert "part of the answer" in prefix and "what is missing starts with the quantity" in prefix.lower()
    middle = part_diagnosis(bytes.fromhex("00 6B"), bytes.fromhex("03 00 6B 00 03"), "pdu")
    assert "starting address (bytes 1-2)" in middle and "missing" not in middle
    assert part_diagnosis(bytes.fromhex("00 6C"), bytes.fromhex("03 00 6B 00 03")) is None  # not in it
    assert part_diagnosis(bytes.fromhex("03 00 6B 00 03"), bytes.fromhex("03 00 6B 00 03")) is None


def test_the_answer_to_another_question_is_named_as_such():
    assert labels(evaluate("03.1", "11 04 00 08 00 01 B2 98").message) == {"another-question"}
    tcp = bytes.fromhex("00 07 00 00 00 06 03 03 00 00 00 03")
    rtu = mb.RtuFrame(unit=3, pdu=mb.ReadHoldingRegistersRequest(address=0, count=3)).encode()
    assert labels(frame_verdict(rtu, tcp, "tcp")) == {"another-question"}
    assert labels(evaluate("11.2", rtu).message) == {"another-question"}
    assert labels(frame_verdict(tcp[7:], tcp, "tcp")) == {"part-of-answer"}


def test_16_4_separates_a_strip_echo_that_takes_every_copy_off():
    message = evaluate("16.4", _every_echo).message
    assert message.startswith("Not yet:") and "01 06 00 01 00 03 98 0B" in message
    assert "every copy of the request" in message


def test_17_3_separates_a_decide_that_refuses_an_engineer_the_functions_above_24():
    assert _reference(bytes.fromhex("41 00 00"), "engineer") is None
    message = evaluate("17.3", _common_only).message
    assert message.startswith("Not yet:") and "'engineer'" in message


# --- the CRC's own loop, a field's value, bytes from a build exercise ----------------------------------

def _crc_source(shifts: int = 8, after: bool = False, limit: str = "") -> object:
    step = ("r >>= 1\n            r = r ^ 0xA001 if r & 1 else r" if after
            else "r = (r >> 1) ^ 0xA001 if r & 1 else r >> 1")
    source = (f"def crc16(data):\n    r = 0xFFFF\n    for b in data{limit}:\n        r ^= b\n"
              f"        for _ in range({shifts}):\n            {step}\n    return r\n")
    namespace: dict = {}
    exec(source, namespace)
    return namespace["crc16"]


@pytest.mark.parametrize("function, misconception", [
    (_crc_source(shifts=7), "crc-bit-loop"), (_crc_source(after=True), "crc-bit-loop"),
    (_crc_source(limit="[:255]"), "crc-not-every-byte"), (_crc_source(limit="[:-1]"), "crc-not-every-byte"),
])
def test_03_5_names_a_changed_bit_loop_and_bytes_left_out_from_the_crc_procedure(function, misconception):
    message = evaluate("03.5", function).message
    assert labels(message) == {misconception}, message


def test_a_hand_built_frame_with_a_changed_bit_loop_is_named_so():
    body = bytes.fromhex("01 06 00 02 12 34")
    from modbus_edu.exercises.diagnosis.misconceptions import crc_bit_loop
    message = evaluate("03.2", _frame(body.hex(), crc_bit_loop(body, shifts=7))).message
    assert labels(message) == {"crc-bit-loop"}, message


def test_a_field_value_read_from_a_frame_names_its_slips_and_both_candidates_when_they_agree():
    assert labels(evaluate("17.1", 0xF401).message) == {"field-low-byte-first"}
    assert labels(evaluate("17.1", 0xF4).message) == {"register-one-byte"}
    assert labels(evaluate("17.1", 10).message) == {"another-field"}
    both = evaluate("17.1", 1).message  # the value's high byte, and the unit identifier: 1 both
    assert "high byte alone" in both and "unit identifier" in both and "cannot tell" in both
    assert not labels(both)
    assert labels(evaluate("11.1", (42, 6, 16, 1)).message) == {"register-one-byte"}


def test_06_5_tells_a_byte_count_written_as_the_quantity_from_a_register_of_one_byte():
    def counts_registers(registers, pdu):
        address, count = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
        if pdu[0] != 3:
            return _right_06_5(registers, pdu)
        if address + count > len(registers):
            return bytes([0x83, 2])
        return bytes([3, count]) + b"".join(r.to_bytes(2, "big") for r in registers[address:address + count])

    assert labels(evaluate("06.5", counts_registers).message) == {"byte-count-for-quantity"}


def _right_06_5(registers, pdu):
    from modbus_edu.exercises.checkers.nb06 import _slave_answer
    return _slave_answer(registers, pdu)


def test_a_build_exercise_s_bytes_are_named_by_the_frame_procedure_where_every_wrong_answer_agrees():
    def low_byte_tid(tid, unit, address, count):
        return mb.TcpFrame(transaction_id=tid & 0xFF, unit=unit,
                           pdu=mb.ReadHoldingRegistersRequest(address=address, count=count)).encode()

    assert labels(evaluate("12.4", low_byte_tid).message) == {"field-in-one-byte"}



def test_a_frame_slip_of_a_build_exercise_is_named_only_where_every_wrong_answer_agrees():
    request = mb.ReadHoldingRegistersRequest(address=0, count=1)
    right = [mb.TcpFrame(transaction_id=tid, unit=1, pdu=request).encode() for tid in (280, 300, 400)]
    low = [b"\x00" + frame[1:] for frame in right]  # the transaction id kept to its low byte
    table = [frame[:7] + b"\x04" + frame[8:] for frame in right]  # function 4 for 3
    cases = [((tid,), frame) for tid, frame in zip((280, 300, 400), right)]
    words = bytes_diagnosis(low[0], right[0])
    assert labels(words) == {"field-in-one-byte"}
    assert _fits_every_answer(words, cases[0][0], (cases, [{"out": plain(frame)} for frame in low]))
    mixed = [{"out": plain(low[0])}, {"out": plain(table[1])}, {"out": plain(right[2])}]
    assert not _fits_every_answer(words, cases[0][0], (cases, mixed))


def test_a_function_that_cuts_its_input_is_told_where_its_slice_starts():
    def one_too_many(sent, received):
        if received[:len(sent)] != sent:
            raise ValueError("no echo")
        return received[len(sent) + 1:]

    message = evaluate("16.4", one_too_many).message
    assert "bytes 9-16 of argument 2; the answer is bytes 8-16: the cut is 1 byte off, at its start" \
        in message
    assert not labels(message)


@pytest.mark.parametrize("key, answer, misconception", [
    ("03.4", 8, "another-question"), ("03.4", 25, "register-one-byte"), ("03.4", 43, "crc-forgotten"),
    ("05.3", 6, "another-question"), ("05.3", 13, "register-one-byte"), ("05.3", 29, "mbap-length"),
])
def test_a_response_s_length_comes_from_its_procedure(key, answer, misconception):
    assert labels(evaluate(key, answer).message) == {misconception}


def test_a_response_s_length_that_two_slips_give_names_both_candidates():
    rtu = evaluate("03.4", 44).message  # 45 less one byte: the byte count or the unit
    assert "byte count" in rtu and "unit left out" in rtu and "cannot tell" in rtu and not labels(rtu)
    tcp = evaluate("05.3", 25).message  # 23 and 2: a CRC, or the length field counting itself
    assert "CRC" in tcp and "counts itself" in tcp and not labels(tcp)


@pytest.mark.parametrize("key, answer, words", [
    ("07.1", (17, 2), "17 is the slave address"), ("07.1", (3, 193), "193 is the CRC's first byte"),
    ("05.1", 17, "17 is the unit identifier"),
])
def test_a_one_byte_field_read_from_a_frame_names_the_field_it_took(key, answer, words):
    message = evaluate(key, answer).message
    assert labels(message) == {"another-field"} and words in message


def test_a_read_s_quantity_counted_in_bytes_is_named_in_every_frame_exercise():
    for key, answer in (("00.3", bytes.fromhex("02 03 00 00 00 04 44 3A")), ("04.2", ":050310000004E4\r\n")):
        assert labels(evaluate(key, answer).message) == {"bytes-for-registers"}, key
    one = evaluate("13.5", "01 03 00 00 00 02 C4 0B").message  # 2 for 1: in bytes, or one too many?
    assert "bytes-for-registers" not in labels(one)
    coils = mb.ReadCoilsRequest(address=0, count=2).encode()
    assert "bytes-for-registers" not in labels(frame_verdict(coils[:4] + b"\x04", coils, "pdu") or "")
