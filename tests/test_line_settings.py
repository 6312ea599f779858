"""A slave with line settings of its own: the UART model, and the virtual wire honouring the settings."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modbus_edu.devices.arduino import ArduinoSlave
from modbus_edu.devices.meter import PowerMeter
from modbus_edu.errors import ConfigError, CrcError, ModbusTimeoutError
from modbus_edu.framing import RtuFrame
from modbus_edu.links.loopback import loopback_serial
from modbus_edu.links.wire import SerialTiming, UartChar, same_format, uart_receive
from modbus_edu.master import Master
from modbus_edu.pdu import ReadHoldingRegistersRequest
from modbus_edu.slave import Slave

FC3_RTU = bytes.fromhex("01 03 00 00 00 01 84 0A")
LINE = SerialTiming(9600)
TOL = 1e-12

FORMATS = [SerialTiming(b, p, s) for b in (4800, 9600, 19200) for p in "NEO" for s in (1, 2)]


# --- the UART model ------------------------------------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=40), st.sampled_from(FORMATS))
def test_matching_settings_give_the_bytes_back_without_errors(data, fmt):
    reading = uart_receive(data, fmt, fmt)
    assert reading.data == data
    assert all(c.ok for c in reading.chars) and len(reading.chars) == len(data)


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=40), st.sampled_from(FORMATS))
def test_a_stop_bit_difference_alone_goes_unnoticed(data, fmt):
    # a receiver checks the first stop bit only: 8N1 and 8N2 understand each other, both ways
    other = SerialTiming(fmt.baudrate, fmt.parity, 3 - fmt.stopbits)
    assert not same_format(fmt, other)
    for sent, heard in ((fmt, other), (other, fmt)):
        reading = uart_receive(data, sent, heard)
        assert reading.data == data and all(c.ok for c in reading.chars)


def test_sampling_at_another_speed_by_hand():
    # 0xFF at 9600: a start bit, then 1s.  At 19200 the receiver samples twice as often: its bit 0 falls
    # in the second half of the start bit (0), its bits 1-7 in the 1s: 0xFE, and its stop bit is a 1.
    assert uart_receive(b"\xff", SerialTiming(9600), SerialTiming(19200)).chars == (UartChar(0xFE),)
    # 0x00 at 9600, read at 4800: each sample spans two sent bits; bits 3-7 land on the stop bit and the
    # idle line after it: 0xF8, and the stop bit sample (19 bit times in) is idle line: no error.
    assert uart_receive(b"\x00", SerialTiming(9600), SerialTiming(4800)).chars == (UartChar(0xF8),)
    # 8N1 read as 8E1: the sender's stop bit is taken for the parity bit (right for 0x01: one 1, even
    # parity wants 1), and the receiver's stop bit lands on the next character's start bit: framing error
    first = uart_receive(b"\x01\x01", SerialTiming(9600), SerialTiming(9600, "E")).chars[0]
    assert first == UartChar(0x01, parity_error=False, framing_error=True)
    # 0x03 has two 1s: even parity wants a 0, the receiver reads the stop bit, a 1: parity error
    assert uart_receive(b"\x03", SerialTiming(9600), SerialTiming(9600, "E")).chars == (
        UartChar(0x03, parity_error=True),)
    assert uart_receive(b"\x03", SerialTiming(9600), SerialTiming(9600, "E")).data == b""  # dropped


def test_reading_describes_itself():
    reading = uart_receive(FC3_RTU, LINE, SerialTiming(19200))
    assert reading.describe() == "9 characters, 7 with a framing error"
    assert reading.framing_errors == 7 and reading.parity_errors == 0 and len(reading.data) == 9
    parity = uart_receive(FC3_RTU, LINE, SerialTiming(9600, "E"))
    assert parity.describe() == "6 characters, 4 with a framing error, 3 with a parity error (dropped)"
    assert uart_receive(b"", LINE, SerialTiming(19200)).describe() == "0 characters"


@pytest.mark.parametrize("fmt", [f for f in FORMATS if f.baudrate != 9600 or f.parity != "N"])
def test_every_mismatch_of_speed_or_parity_garbles_a_request(fmt):
    reading = uart_receive(FC3_RTU, LINE, fmt)
    assert reading.data != FC3_RTU


# --- the wire honours a slave's own settings --------------------------------------------------------------
def poll(slave: Slave, polls: int = 3, **line) -> tuple[list, object]:
    link = loopback_serial(slave, **line)
    master = Master(link, timeout=0.2)
    outcomes = master.poll(polls=polls, function=3, unit=1, address=0, quantity=1)
    return outcomes, link


@pytest.mark.parametrize("own", [{"baudrate": 19200}, {"baudrate": 4800}, {"parity": "E"},
                                 {"parity": "O", "stopbits": 2}, {"baudrate": 19200, "parity": "E"}])
def test_a_slave_at_other_settings_never_answers(own):
    slave = Slave(unit=1)
    slave.serial_settings = own  # type: ignore[attr-defined]
    outcomes, link = poll(slave, baudrate=9600)
    assert all(isinstance(o, ModbusTimeoutError) for o in outcomes)
    c = slave.counters
    assert c.requests == c.responses == 0
    assert c.checksum_errors + c.bad_frames == 3  # it heard something each time, and dropped it
    # the monitor shows the request as sent, with what the slave's receiver made of it
    for entry in link.monitor:
        assert entry.data == FC3_RTU and "slave 1 listens at " in entry.note
    # the slave's log shows the bytes it assembled: the UART model's, every time the same
    garbled = uart_receive(FC3_RTU, link.timing, link.uart_of(slave)).data
    assert [e.data for e in slave.log] == [garbled] * 3


def test_a_baud_mismatch_is_a_checksum_error_at_the_slave():
    slave = Slave(unit=1)
    slave.serial_settings = {"baudrate": 19200}  # type: ignore[attr-defined]
    _outcomes, link = poll(slave, baudrate=9600)
    assert slave.counters.checksum_errors == 3
    assert link.monitor[0].note == (
        "slave 1 listens at 19200 baud 8N1: its receiver assembles 9 characters, 7 with a framing error")


def test_matching_settings_change_nothing():
    # same timing, same bytes, no notes: a board whose settings are the line's is a plain slave
    for baud, parity, stopbits in [(9600, "N", 1), (19200, "E", 1), (4800, "N", 2)]:
        board = ArduinoSlave(unit=1, baudrate=baud, parity=parity, stopbits=stopbits, sketch=False)
        board.add(40001, 1234)
        link = loopback_serial(board, **board.serial_settings)
        assert link.uart_of(board) is None
        assert Master(link).read_holding_registers(unit=1, address=0, count=1) == [1234]
        assert link.clock.now == pytest.approx(link.timing.transaction_time(8, 7), abs=TOL)
        assert [e.note for e in link.monitor] == ["", ""]


def test_a_missing_key_means_as_the_line():
    slave = Slave(unit=1)
    slave.serial_settings = {"parity": "E"}  # type: ignore[attr-defined]
    outcomes, _link = poll(slave, baudrate=19200, parity="E")
    assert all(o == [0] for o in outcomes)


def test_correcting_the_setting_mends_the_wire():
    board = ArduinoSlave(unit=1, baudrate=19200)
    link = loopback_serial(board, baudrate=9600)
    master = Master(link, timeout=0.2)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(unit=1, address=0, count=1)
    board.baudrate = 9600  # the settings are read for every frame
    assert master.read_holding_registers(unit=1, address=0, count=1) == [700]


def test_the_power_meter_answers_only_at_19200():
    meter = PowerMeter(unit=1)
    assert meter.serial_settings == {"baudrate": 19200, "parity": "N", "stopbits": 1, "bytesize": 8}
    with pytest.raises(ModbusTimeoutError):
        Master(loopback_serial(meter, baudrate=9600), timeout=0.2).read_holding_registers(1, 0, 2)
    assert meter.counters.checksum_errors == 1
    good = Master(loopback_serial(meter, **meter.serial_settings))
    assert len(good.read_holding_registers(1, 0, 2)) == 2


def test_on_a_bus_only_the_mismatched_slave_is_deaf():
    good, deaf = Slave(unit=1), ArduinoSlave(unit=2, parity="E")
    link = loopback_serial([good, deaf], baudrate=9600)
    master = Master(link, timeout=0.2)
    assert master.read_holding_registers(unit=1, address=0, count=1) == [0]
    assert link.clock.now == pytest.approx(link.timing.transaction_time(8, 7), abs=TOL)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(unit=2, address=0, count=1)
    assert good.counters.other_unit == 1 and deaf.counters.requests == 0


def test_ascii_line_with_a_slave_at_another_speed():
    slave = Slave(unit=1)
    slave.serial_settings = {"baudrate": 19200}  # type: ignore[attr-defined]
    outcomes, _link = poll(slave, baudrate=9600, mode="ascii")
    assert all(isinstance(o, ModbusTimeoutError) for o in outcomes)
    assert slave.counters.requests == 0


def test_a_node_that_talks_at_another_speed_reaches_the_master_as_garbage():
    # the way back: what a node sends at its own settings is what the line's receivers assemble
    link = loopback_serial([], baudrate=9600)
    rogue = link.bus.attach("rogue", lambda frame, when: None)
    answer = RtuFrame(1, ReadHoldingRegistersRequest(address=0, count=1)).encode()
    rogue.transmit(answer, "master", SerialTiming(4800))
    got = link.receive(0.1)
    assert got == uart_receive(answer, SerialTiming(4800), link.timing).data != answer
    assert "sent at 4800 baud 8N1 on a 9600 baud 8N1 line" in link.monitor[0].note
    with pytest.raises(CrcError):
        RtuFrame.decode(got, "request")


def test_bad_serial_settings_are_config_errors():
    slave = Slave(unit=1)
    for bad in ({"baudrate": -5}, {"parity": "X"}, "9600 8N1"):
        slave.serial_settings = bad  # type: ignore[attr-defined]
        link = loopback_serial(slave)
        link.send(FC3_RTU)
        with pytest.raises(ConfigError, match="slave 1"):
            link.receive(0.1)
