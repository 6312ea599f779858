"""Accepted and refused answers of the exercises of notebooks 14 (beyond the eight functions) and 15
(gateways and converters): each right spelling passes, each known mistake gets its own message."""

from __future__ import annotations

import pytest

import modbus_edu as mb
from modbus_edu import exercises
from modbus_edu.exercises.checkers import nb15

# --- 15.1: one transaction at 19200 baud 8E1 -------------------------------------------------------------


@pytest.mark.parametrize("answer", [13.75, "13.75", "13.75 ms", 13.75000001, 0.01375 * 1000])
def test_15_1_accepts_the_time_in_its_spellings(answer):
    assert exercises.evaluate("15.1", answer).ok is True


@pytest.mark.parametrize("answer, words", [
    (12.5, "10 bits for a character with parity"),  # 8N1 arithmetic on an 8E1 line
    (9.74, "the silences forgotten"),           # the two frames without their silences
    (13.18, "9 bytes"),                       # a 7-byte response (one register)
    (0.01375, "seconds"),                     # seconds given for milliseconds
    (22.92, "is not"),                        # the notebook's own 9600-baud measurement
    ("fast", "number of milliseconds"),
])
def test_15_1_names_the_mistake(answer, words):
    result = exercises.evaluate("15.1", answer)
    assert result.ok is False and words in result.message, result.message


# --- 15.2: RTU over TCP in, Modbus/TCP out -----------------------------------------------------------------


def test_15_2_reference_is_the_gateways_conversion():
    pdu = mb.ReadHoldingRegistersRequest(address=0, count=2)
    frame = mb.RtuFrame(unit=1, pdu=pdu).encode()
    assert nb15.rtu_to_tcp(frame, 1) == mb.TcpFrame(transaction_id=1, unit=1, pdu=pdu).encode()
    with pytest.raises(mb.ModbusError):
        nb15.rtu_to_tcp(frame[:-1] + b"\x00", 1)


@pytest.mark.parametrize("function, words", [
    (lambda frame, tid: tid.to_bytes(2, "big") + b"\0\0" + len(frame).to_bytes(2, "big") + frame,
     "a CRC on Modbus/TCP"),
    (lambda frame, tid: (tid.to_bytes(2, "little") + b"\0\0" + (len(frame) - 2).to_bytes(2, "big")
                         + frame[:-2]), "little-endian"),
    (lambda frame, tid: tid.to_bytes(2, "big") + b"\0\0" + (len(frame) - 3).to_bytes(2, "big") + frame[:-2],
     "an MBAP length that counts the wrong bytes"),
    (lambda frame, tid: tid.to_bytes(2, "big") + b"\0\0" + (len(frame) - 2).to_bytes(2, "big") + frame[:-2],
     "should raise"),                     # right bytes, but a damaged frame is forwarded
])
def test_15_2_names_the_mistake(function, words):
    result = exercises.evaluate("15.2", function)
    assert result.ok is False and words.lower() in result.message.lower(), result.message


# --- 15.3: what the client sees -----------------------------------------------------------------------


@pytest.mark.parametrize("answer", [
    {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout"},
    {"a": "0A", "b": "0x0B", "c": "01", "d": "Timeout"},
    {"A": 10, "B": 11, "C": 1, "D": "timed out"},
    {"a": "exception 0A", "b": "exception 0B", "c": "exception 01", "d": "no answer"},
])
def test_15_3_accepts_codes_and_timeouts_in_their_spellings(answer):
    assert exercises.evaluate("15.3", answer).ok is True


@pytest.mark.parametrize("change, words", [
    ({"a": 0x0B}, "reserved address"),
    ({"b": 0x0A}, "the meter just does not answer"),
    ({"b": "timeout"}, "gateway's 0B arrives first"),
    ({"c": 0x0B}, "passed on unchanged"),
    ({"d": 0x0B}, "gave up after 0.1 s"),
    ({"c": "maybe"}, "neither an exception code"),
])
def test_15_3_names_the_mistake_case_by_case(change, words):
    answer = {"a": 0x0A, "b": 0x0B, "c": 0x01, "d": "timeout", **change}
    result = exercises.evaluate("15.3", answer)
    assert result.ok is False and words in result.message, result.message


def test_15_3_wants_every_case_in_a_dict():
    assert "missing" in exercises.evaluate("15.3", {"a": 0x0A}).message
    assert "give a dict" in exercises.evaluate("15.3", [0x0A, 0x0B, 1, "timeout"]).message


def test_15_3_expected_answers_are_what_the_gateway_does():
    """Cases a, b and c, run against a gateway like the notebook's (case d needs a real bus's time)."""
    meter = mb.Slave(unit=1)
    pump = mb.Slave(unit=2, bank=mb.DataBank(sparse=True))
    pump.bank.holding_registers.declare(0, 1, 1)
    bus = mb.loopback_serial([meter, pump], baudrate=9600)
    expected = nb15.expected_15_3()
    with mb.TcpGateway(bus, timeout=0.2) as gateway, mb.tcp_link(*gateway.address) as link:
        master = mb.Master(link, timeout=5)
        with pytest.raises(mb.ModbusExceptionError) as error:
            master.read_holding_registers(unit=248, address=0, count=1)
        assert error.value.code == expected["a"]
        link.send(bytes.fromhex("00 09 00 00 00 02 01 41"))         # function 0x41 for the meter
        assert link.receive(2.0) == bytes([0, 9, 0, 0, 0, 3, 1, 0xC1, expected["c"]])
        bus.faults.silence(1)                                          # the meter's cable comes off
        with pytest.raises(mb.ModbusExceptionError) as error:
            master.read_holding_registers(unit=1, address=0, count=1)
        assert error.value.code == expected["b"]


# --- 14.3: a bus message count, predicted ------------------------------------------------------------


def test_14_3_expected_count_follows_the_serial_line_guide():
    from modbus_edu.exercises.checkers.nb14 import counters_scenario

    counts = counters_scenario()
    # unit 1's two reads, the read for unit 2 and unit 2's response, the 0x0B request itself; the damaged
    # request is a checksum error (0x0C), not a message heard (Appendix A of the serial-line guide)
    assert counts == {"heard": 5, "checksum_errors": 1}


@pytest.mark.parametrize("answer", [5, 0x05])
def test_14_3_accepts_the_count(answer):
    assert exercises.evaluate("14.3", answer).ok is True


@pytest.mark.parametrize("answer, words", [
    (6, "a damaged frame counted or the clear request counted?"),
    (4, "the count request itself left out or another unit's response left out?"),
    (3, "only the requests addressed to it"),
    (9, "is not the count"),
    ("five", "whole number"),
])
def test_14_3_names_the_mistake(answer, words):
    result = exercises.evaluate("14.3", answer)
    assert result.ok is False and words in result.message, result.message
