"""The virtual serial line: exact timing, the silence splitter, multidrop, the monitor."""

from __future__ import annotations

import pytest

from modbus_edu.clock import VirtualClock
from modbus_edu.errors import ConfigError, LinkError, ModbusTimeoutError
from modbus_edu.framing import AsciiFrame, RtuFrame
from modbus_edu.links import Link, SerialTiming, character_time, loopback_serial, wire
from modbus_edu.master import Master
from modbus_edu.pdu import ReadHoldingRegistersRequest
from modbus_edu.slave import Slave

FC3_RTU = bytes.fromhex("01 03 00 00 00 01 84 0A")  # 8 bytes; its response is 7 bytes
TOL = 1e-12


def bits_per_char(parity: str, stopbits: int, data_bits: int = 8) -> int:
    return 1 + data_bits + (0 if parity == "N" else 1) + stopbits


LINES = [
    (1200, "N", 1), (2400, "E", 1), (4800, "O", 1), (9600, "N", 1), (9600, "E", 1), (9600, "O", 1),
    (9600, "N", 2), (19200, "E", 1), (19200, "N", 2), (38400, "N", 1), (57600, "E", 1), (115200, "O", 2),
]


@pytest.mark.parametrize(("baud", "parity", "stopbits"), LINES)
def test_fc3_transaction_takes_exactly_the_arithmetic(baud, parity, stopbits):
    link = loopback_serial(Slave(unit=1), baudrate=baud, parity=parity, stopbits=stopbits)
    char = bits_per_char(parity, stopbits) / baud
    t35 = 0.00175 if baud > 19200 else 3.5 * char
    link.send(FC3_RTU)
    response = link.receive(timeout=1.0)
    assert RtuFrame.decode(response, "response").pdu.registers == (0,)
    assert link.clock.now == pytest.approx(8 * char + t35 + 7 * char + t35, abs=TOL)
    assert link.timing.transaction_time(8, 7) == pytest.approx(link.clock.now, abs=TOL)


def test_9600_8n1_is_22_92_ms_and_43_6_transactions_per_second():
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 1234
    link = loopback_serial(slave)
    master = Master(link)
    assert master.read_holding_registers(unit=1, address=0, count=1) == [1234]
    assert link.clock.now == pytest.approx((8 + 3.5 + 7 + 3.5) * 10 / 9600, abs=TOL)
    assert round(link.clock.now * 1000, 2) == 22.92
    # back to back: the silence ending a response is the one preceding the next request
    for _ in range(99):
        master.read_holding_registers(unit=1, address=0, count=1)
    assert link.clock.now == pytest.approx(100 * 22 * 10 / 9600, abs=1e-9)
    assert 1 / (link.clock.now / 100) == pytest.approx(43.6, abs=0.05)


def test_processing_time_adds_to_the_transaction():
    link = loopback_serial(Slave(unit=1, processing_time=0.005))
    link.send(FC3_RTU)
    assert link.receive(1.0) is not None
    assert link.clock.now == pytest.approx(22 * 10 / 9600 + 0.005, abs=TOL)


@pytest.mark.parametrize(("baud", "parity", "stopbits", "data_bits"),
                         [(9600, "N", 1, 7), (9600, "E", 1, 7), (19200, "N", 2, 7), (9600, "N", 1, 8)])
def test_ascii_transaction_has_no_silence_only_characters(baud, parity, stopbits, data_bits):
    request = AsciiFrame(1, ReadHoldingRegistersRequest(address=0, count=1)).encode()
    link = loopback_serial(Slave(unit=1), baudrate=baud, parity=parity, stopbits=stopbits, mode="ascii",
                           bytesize=data_bits)
    link.send(request)
    response = link.receive(2.0)
    assert AsciiFrame.decode(response, "response").pdu.registers == (0,)
    assert (len(request), len(response)) == (17, 15)
    char = bits_per_char(parity, stopbits, data_bits) / baud
    assert link.clock.now == pytest.approx((17 + 15) * char, abs=TOL)


def test_timing_object():
    t = SerialTiming(9600, "E", 1)
    assert t.bits_per_char == 11 and t.char_time == 11 / 9600
    assert t.t15 == pytest.approx(1.5 * 11 / 9600) and t.t35 == pytest.approx(3.5 * 11 / 9600)
    fast = SerialTiming(38400)
    assert (fast.t15, fast.t35) == (0.00075, 0.00175)
    assert SerialTiming(19200).t35 == pytest.approx(3.5 * 10 / 19200)  # 19200 itself: still characters
    # the serial line guide (2.5.1.1) recommends those fixed values; it does not impose them
    assert "recommends fixed values" in " ".join(wire.__doc__.split()) and "fixes" not in wire.__doc__
    assert character_time(9600) == 10 / 9600
    assert character_time(9600, "N", 2, 7) == 10 / 9600
    assert str(SerialTiming(9600, "e", 2)) == "9600 baud 8E2"
    assert SerialTiming(9600, mode="ascii", bytesize=7).frame_gap == 0
    for bad in [dict(baudrate=0), dict(parity="X"), dict(stopbits=3), dict(bytesize=7),
                dict(mode="tcp"), dict(bytesize=6, mode="ascii"), dict(baudrate=True)]:
        with pytest.raises(ConfigError):
            SerialTiming(**bad)


def test_each_byte_arrives_when_its_last_bit_does():
    link = loopback_serial(Slave(unit=1))
    char = 10 / 9600
    link.send(FC3_RTU)
    link.receive(1.0)
    request, response = list(link.monitor)
    assert request.time == 0 and request.duration == pytest.approx(8 * char)
    assert request.source == "master" and request.dest == "unit 1" and request.direction == "tx"
    assert response.time == pytest.approx(11.5 * char) and response.duration == pytest.approx(7 * char)
    assert response.source == "slave 1" and response.direction == "rx"


# --- the silence splitter ------------------------------------------------------------------------------
def rtu_pair(**kwargs):
    slave = Slave(unit=1)
    link = loopback_serial(slave, **kwargs)
    return slave, link, Master(link, timeout=0.5)


@pytest.mark.parametrize("gap", [1.6, 2.0, 3.0, 3.4])
def test_a_gap_over_1_5_chars_breaks_the_request(gap):
    slave, link, master = rtu_pair()
    link.faults.insert_gap(at_byte=4, chars=gap, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert link.stats.broken_frames == 1
    assert slave.counters.requests == 0 and slave.counters.checksum_errors == 0  # never handed over
    assert master.stats.timeouts == 1
    assert "broken" in link.monitor[0].note and "silence before byte 4" in link.monitor[0].note
    # the line recovers: the next request goes through
    assert master.read_holding_registers(1, 0, 1) == [0]


@pytest.mark.parametrize("gap", [0.5, 1.0, 1.5])
def test_a_gap_up_to_1_5_chars_is_tolerated_and_only_costs_time(gap):
    slave, link, master = rtu_pair()
    link.faults.insert_gap(at_byte=3, chars=gap, target="request")
    assert master.read_holding_registers(1, 0, 1) == [0]
    assert link.stats.broken_frames == 0
    assert link.clock.now == pytest.approx((22 + gap) * 10 / 9600, abs=TOL)


def test_a_gap_of_3_5_chars_or_more_cuts_the_frame_in_two():
    slave, link, master = rtu_pair()
    link.faults.insert_gap(at_byte=4, chars=5, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert link.stats.broken_frames == 0
    assert link.stats.frames == 2  # two pieces, each delivered
    assert slave.counters.checksum_errors + slave.counters.bad_frames == 2
    assert [e.data for e in slave.log] == [FC3_RTU[:4], FC3_RTU[4:]]


def test_a_gap_in_the_response_breaks_it_before_the_master():
    slave, link, master = rtu_pair()
    link.faults.insert_gap(at_byte=2, chars=2.5, target="response")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert slave.counters.responses == 1 and link.stats.broken_frames == 1
    assert master.stats.timeouts == 1 and master.stats.checksum_errors == 0


def test_above_19200_baud_the_silences_are_fixed_in_milliseconds():
    # at 115200 8N1 a character is 86.8 us: 5 characters (434 us) are under 0.750 ms, 10 are over it
    slave, link, master = rtu_pair(baudrate=115200)
    link.faults.insert_gap(at_byte=4, chars=5, target="request")
    assert master.read_holding_registers(1, 0, 1) == [0]
    link.faults.insert_gap(at_byte=4, chars=10, target="request")
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert link.stats.broken_frames == 1


def test_ascii_inter_character_timeout_and_restart():
    slave = Slave(unit=1)
    link = loopback_serial(slave, mode="ascii")
    master = Master(link, timeout=3.0)
    link.faults.insert_gap(at_byte=5, chars=2000, target="request")  # 2000 x 9/9600 s = 1.875 s > 1 s
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    assert link.stats.discarded_frames == 1 and slave.counters.requests == 0
    assert link.stats.junk_bytes == 12  # the 12 characters after the gap belong to no frame
    # junk before ':' and a restarted frame
    link.send(b"xx:0103" + AsciiFrame(1, ReadHoldingRegistersRequest(address=0, count=1)).encode())
    assert link.receive(1.0) is not None
    assert link.stats.junk_bytes == 14 and link.stats.discarded_frames == 2


def test_ascii_gap_under_the_timeout_is_fine():
    link = loopback_serial(Slave(unit=1), mode="ascii")
    link.faults.insert_gap(at_byte=5, chars=500, target="request")  # 0.47 s
    assert Master(link).read_holding_registers(1, 0, 1) == [0]


# --- multidrop -------------------------------------------------------------------------------------------
def test_three_slaves_on_one_bus():
    slaves = [Slave(unit=u) for u in (1, 2, 3)]
    for s in slaves:
        s.bank.holding_registers[0] = 100 + s.unit
    link = loopback_serial(slaves, baudrate=19200, parity="E")
    master = Master(link)
    assert [master.read_holding_registers(unit=u, address=0, count=1) for u in (1, 2, 3)] == [
        [101], [102], [103]]
    for s in slaves:
        # each heard 3 requests (1 for it) and the 2 responses of the others
        assert s.counters.requests == 1 and s.counters.responses == 1
        assert s.counters.other_unit == 4
    assert link.clock.now == pytest.approx(3 * link.timing.transaction_time(8, 7), abs=1e-12)
    assert [e.source for e in link.monitor] == ["master", "slave 1", "master", "slave 2", "master", "slave 3"]
    assert "3 slaves" in link.description and "RS-485" in link.description
    # broadcast reaches everyone, nobody answers
    master.write_single_register(unit=0, address=5, value=7)
    assert [s.bank.holding_registers[5] for s in slaves] == [7, 7, 7]
    assert len(link.monitor) == 7
    # nobody at unit 4
    with pytest.raises(ModbusTimeoutError):
        Master(link, timeout=0.1).read_holding_registers(unit=4, address=0, count=1)


def test_each_slave_logs_who_sent_the_frames_it_hears():
    # On a bus every slave hears every frame: the master's requests and the other slaves' answers.
    one, two = Slave(unit=1), Slave(unit=2)
    link = loopback_serial([one, two])
    master = Master(link)
    master.read_holding_registers(unit=1, address=0, count=1)
    master.read_holding_registers(unit=2, address=0, count=1)
    assert [(e.direction, e.label(), e.note) for e in one.log] == [
        ("rx", "master -> slave 1", ""),
        ("tx", "slave 1 -> master", "Read Holding Registers response: registers [0]"),
        ("rx", "master -> slave 1", "for unit 2: ignored"),
        ("rx", "slave 2 -> slave 1", "for unit 2: ignored"),
    ]
    assert [(e.direction, e.label()) for e in two.log] == [
        ("rx", "master -> slave 2"), ("rx", "slave 1 -> slave 2"),
        ("rx", "master -> slave 2"), ("tx", "slave 2 -> master"),
    ]
    # what a slave heard from another is exactly what the monitor saw that slave send
    sent = {(e.source, e.data) for e in link.monitor}
    assert all((e.source, e.data) in sent for s in (one, two) for e in s.log if e.direction == "rx")
    assert one.sender == two.sender == "master"  # only while a frame is being handled


def test_attach_and_detach():
    a, b = Slave(unit=1), Slave(unit=2)
    link = loopback_serial(a)
    link.attach(b)
    link.attach(b)
    assert link.slaves == [a, b]
    assert Master(link).read_coils(2, 0, 3) == [False] * 3
    link.detach(b)
    with pytest.raises(ModbusTimeoutError):
        Master(link, timeout=0.05).read_coils(2, 0, 3)
    with pytest.raises(ConfigError):
        link.attach("slave")  # type: ignore[arg-type]
    with pytest.raises(ConfigError):
        loopback_serial([a, 3])  # type: ignore[list-item]


# --- the monitor -----------------------------------------------------------------------------------------
def test_monitor_log_search_text_and_explain():
    slaves = [Slave(unit=1), Slave(unit=2)]
    link = loopback_serial(slaves)
    master = Master(link)
    master.read_holding_registers(1, 0, 2)
    master.write_single_coil(2, 10, True)
    master.read_coils(2, 10, 1)
    log = link.monitor
    assert len(log) == 6
    assert [e.direction for e in log] == ["tx", "rx"] * 3
    assert len(log.search(unit=2)) == 4 and len(log.search(function=5)) == 2
    assert len(log.search(text="84 0a")) == 0 and len(log.search(text="SLAVE 2")) == 2
    assert len(log.search(unit=1, direction="rx")) == 1
    times = [e.time for e in log]
    assert times == sorted(times)
    text = log.to_text()
    assert "01 03 00 00 00 02" in text and "slave 1 -> master" in text
    assert "<table" in log._repr_html_()
    dissection = log.explain(1)
    assert dissection.error is None and dissection.role == "response"
    log.clear()
    assert len(log) == 0


def test_the_monitor_shows_ascii_frames_as_text():
    link = loopback_serial(Slave(unit=5), mode="ascii")
    Master(link).write_single_register(unit=5, address=0x1001, value=0x0200)
    assert [e.text for e in link.monitor] == [":050610010200E2\\r\\n"] * 2
    assert link.monitor.search(text=":0506")[0].unit == 5


# --- the Link interface ------------------------------------------------------------------------------------
def test_link_interface_receive_flush_close():
    link = loopback_serial(Slave(unit=1))
    assert isinstance(link, Link) and isinstance(link.clock, VirtualClock)
    assert link.mode == "rtu"
    assert link.receive(0) is None and link.clock.now == 0
    assert link.receive(0.25) is None and link.clock.now == 0.25
    link.send(FC3_RTU)
    link.flush()  # the request has left the line and its 3.5-character silence has passed
    assert link.clock.now == pytest.approx(0.25 + 11.5 * 10 / 9600)
    assert link.receive(1.0) is not None
    link.run(1.0)
    with link:
        pass
    assert link.closed
    with pytest.raises(LinkError):
        link.send(FC3_RTU)
    with pytest.raises(LinkError):
        link.receive(0.1)


def test_bad_arguments():
    link = loopback_serial(Slave())
    with pytest.raises(LinkError):
        link.send("01 03")  # type: ignore[arg-type]
    with pytest.raises(ConfigError):
        link.receive(-1)
    with pytest.raises(ConfigError):
        link.receive("soon")  # type: ignore[arg-type]
    for bad in [dict(mode="tcp"), dict(parity="M"), dict(baudrate=-9600), dict(mode="rtu", bytesize=7)]:
        with pytest.raises(ConfigError):
            loopback_serial(Slave(), **bad)
    assert loopback_serial(Slave(), mode="ascii").timing.bytesize == 7
    assert "1 slave" in loopback_serial(Slave()).description


def test_a_late_answer_is_taken_for_the_next_one_in_rtu():
    slave = Slave(unit=1)
    link = loopback_serial(slave)
    link.faults.delay(1, 0.030, requests=1)
    master = Master(link, timeout=0.035)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    # The master gives up at 35 ms and sends again.  The slave decides to answer the first request at
    # 42 ms, while the second request is on the line: it waits for the line, and since it was busy
    # talking (half duplex) it does not take in the second request (link.stats.ignored_frames).
    # The late answer reaches the master, which cannot tell it from an answer to its second request:
    # RTU has no transaction id.
    assert master.read_holding_registers(1, 0, 1) == [0]
    assert link.stats.ignored_frames == 1 and link.stats.waits == 1
    assert slave.counters.requests == 1
    assert master.read_holding_registers(1, 0, 1) == [0]
    assert master.stats.valid_responses == 2 and master.stats.timeouts == 1
    assert [e.source for e in link.monitor] == ["master", "master", "slave 1", "master", "slave 1"]
