"""Master: the eight functions over loopback serial (RTU, ASCII) and TCP; ids, timeouts, retries, stats."""

from __future__ import annotations

from collections import deque

import pytest

from modbus_edu.clock import VirtualClock
from modbus_edu.datamodel import DataBank
from modbus_edu.errors import (
    ConfigError,
    CrcError,
    ModbusError,
    ModbusExceptionError,
    ModbusTimeoutError,
    PduError,
    QuantityError,
    TransactionMismatchError,
    UnitError,
)
from modbus_edu.framing import RtuFrame, TcpFrame
from modbus_edu.links import Link, loopback_serial, loopback_tcp
from modbus_edu.master import Master, MasterStats
from modbus_edu.pdu import (
    ExceptionResponse,
    ReadCoilsResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    WriteSingleRegisterResponse,
)
from modbus_edu.slave import Slave


def make_link(kind: str, slaves):
    if kind == "tcp":
        return loopback_tcp(slaves, latency=0.002)
    return loopback_serial(slaves, mode=kind, baudrate=19200, parity="E")


@pytest.fixture(params=["rtu", "ascii", "tcp"])
def setup(request):
    slave = Slave(unit=7)
    bank = slave.bank
    bank.coils.write(0, [True, False, True])
    bank.discrete_inputs.write(10, [True] * 9)
    bank.holding_registers.write(100, [1, 2, 3, 65535])
    bank.input_registers.write(30, [0x4142, 0x4344])
    link = make_link(request.param, slave)
    return slave, link, Master(link)


def test_all_eight_functions(setup):
    slave, link, master = setup
    assert master.read_coils(unit=7, address=0, count=3) == [True, False, True]
    assert master.read_discrete_inputs(unit=7, address=10, count=9) == [True] * 9
    assert master.read_holding_registers(unit=7, address=100, count=4) == [1, 2, 3, 65535]
    assert master.read_input_registers(unit=7, address=30, count=2) == [0x4142, 0x4344]
    assert master.write_single_coil(unit=7, address=1, value=True) is None
    master.write_single_register(unit=7, address=101, value=0xBEEF)
    master.write_multiple_coils(unit=7, address=20, values=[True, True, False, True] * 5)
    master.write_multiple_registers(unit=7, address=200, values=list(range(123)))
    assert slave.bank.coils.read(0, 3) == [True, True, True]
    assert slave.bank.holding_registers[101] == 0xBEEF
    assert slave.bank.coils.read(20, 20) == [True, True, False, True] * 5
    assert slave.bank.holding_registers.read(200, 123) == list(range(123))
    assert master.stats.requests == master.stats.valid_responses == 8
    assert len(master.stats.latencies) == 8 and all(t > 0 for t in master.stats.latencies)
    assert len(master.log) == 16
    assert [e.direction for e in master.log] == ["tx", "rx"] * 8
    assert all(e.mode == link.mode for e in master.log)
    assert link.clock.now > 0


def test_read_bits_returns_exactly_count(setup):
    slave, link, master = setup
    for count in (1, 7, 8, 9, 16, 17, 2000):
        assert len(master.read_coils(7, 0, count)) == count


def test_positional_and_limits(setup):
    slave, link, master = setup
    assert master.read_holding_registers(7, 100, 1) == [1]
    with pytest.raises(QuantityError):
        master.read_holding_registers(7, 0, 126)  # refused before anything is sent
    with pytest.raises(ModbusError):
        master.write_single_register(7, 0, 70000)
    assert master.stats.requests == 1


def test_exception_responses_raise(setup):
    slave, link, master = setup
    sparse = Slave(unit=8, bank=DataBank(sparse=True))
    link.attach(sparse)
    with pytest.raises(ModbusExceptionError) as info:
        master.read_holding_registers(unit=8, address=0, count=1)
    assert info.value.code == 2 and info.value.function == 3 and "address" in info.value.meaning.lower()
    response = master.execute(8, ReadHoldingRegistersRequest(address=0, count=1), check=False)
    assert response == ExceptionResponse(3, 2)
    assert master.stats.exceptions == 2 and master.stats.valid_responses == 0
    assert len(master.stats.latencies) == 2
    assert "Exception" in master.log[-1].note


def test_exception_is_not_retried():
    slave = Slave(unit=1, on_read=lambda *a: 1 / 0)
    master = Master(loopback_serial(slave), retries=3)
    with pytest.raises(ModbusExceptionError) as info:
        master.read_input_registers(1, 0, 1)
    assert info.value.code == 4
    assert master.stats.requests == 1 and master.stats.retries == 0


def test_broadcast_returns_without_an_answer():
    slaves = [Slave(unit=u) for u in (1, 2)]
    link = loopback_serial(slaves)
    master = Master(link, delay=0.1)
    assert master.write_multiple_coils(unit=0, address=3, values=[True, True]) is None
    assert [s.bank.coils.read(3, 2) for s in slaves] == [[True, True]] * 2
    # the frame (10 bytes), its 3.5-character silence, then the turnaround delay
    assert link.clock.now == pytest.approx((10 + 3.5) * 10 / 9600 + 0.1)
    assert master.stats.broadcasts == 1 and master.stats.timeouts == 0 and master.stats.requests == 1
    with pytest.raises(ConfigError):
        master.read_coils(unit=0, address=0, count=1)


def test_broadcast_over_ascii():
    link = loopback_serial([Slave(unit=1), Slave(unit=2)], mode="ascii")
    master = Master(link)
    master.write_single_register(unit=0, address=1, value=9)
    assert [s.bank.holding_registers[1] for s in link.slaves] == [9, 9]
    assert master.stats.broadcasts == 1


def test_unit_0_on_tcp_is_not_a_broadcast_the_master_waits_for_the_answer():
    # Modbus/TCP has no broadcast (implementation guide 4.4.1.2): unit 0 is the device itself
    link = ScriptedLink([[]], mode="tcp")  # a server that does not answer
    master = Master(link, timeout=0.5)
    with pytest.raises(ModbusTimeoutError):
        master.write_single_register(unit=0, address=1, value=9)
    assert link.clock.now == pytest.approx(0.5)
    assert master.stats.broadcasts == 0 and master.stats.timeouts == 1
    assert master.log[0].dest == "unit 0"


def test_unit_0_on_tcp_may_be_read_and_written():
    tid_1 = TcpFrame(1, 0, WriteSingleRegisterResponse(address=1, value=9)).encode()
    tid_2 = TcpFrame(2, 0, ReadHoldingRegistersResponse(registers=(9,))).encode()
    link = ScriptedLink([[tid_1], [tid_2]], mode="tcp")
    master = Master(link)
    assert master.write_single_register(unit=0, address=1, value=9) is None
    assert master.read_holding_registers(unit=0, address=1, count=1) == [9]
    assert [frame[6] for frame in link.sent] == [0, 0]
    assert master.stats.valid_responses == 2 and master.stats.broadcasts == 0
    assert master.poll(0, 0, unit=0) == []  # no ConfigError: a read of unit 0 is fine on TCP


def test_bad_unit_and_bad_arguments():
    master = Master(loopback_serial(Slave()))
    with pytest.raises(UnitError):
        master.read_coils(unit=256, address=0, count=1)
    from modbus_edu.errors import ModbusTimeoutError, ReservedUnitWarning

    # a reserved address is sent (with a warning); a standard slave stays silent
    with pytest.warns(ReservedUnitWarning), pytest.raises(ModbusTimeoutError):
        master.read_coils(unit=248, address=0, count=1)
    with pytest.raises(ConfigError):
        master.execute(1, ReadCoilsResponse(bits=(True,)))
    with pytest.raises(ConfigError):
        master.read_once(5, 1, 0, 1)
    for bad in [dict(timeout=-1), dict(retries=-1), dict(retries=1.5), dict(delay="x"),
                dict(transaction_id=70000)]:
        with pytest.raises(ConfigError):
            Master(loopback_serial(Slave()), **bad)
    with pytest.raises(ConfigError):
        Master("COM1")  # type: ignore[arg-type]


# --- timeouts and retries -----------------------------------------------------------------------------
def test_timeout_on_the_link_clock():
    link = loopback_serial(Slave(unit=1))
    master = Master(link, timeout=0.5)
    with pytest.raises(ModbusTimeoutError, match="unit 2"):
        master.read_holding_registers(unit=2, address=0, count=1)
    assert link.clock.now == pytest.approx(0.5)
    assert master.stats.timeouts == 1 and master.stats.requests == 1


def test_retries_and_delay():
    link = loopback_serial(Slave(unit=1))
    master = Master(link, timeout=0.2, retries=2, delay=0.05)
    with pytest.raises(ModbusTimeoutError):
        master.read_coils(unit=9, address=0, count=1)
    assert master.stats.requests == 3 and master.stats.retries == 2 and master.stats.timeouts == 3
    assert link.clock.now == pytest.approx(3 * 0.2 + 2 * 0.05)
    assert [e.time for e in master.log] == pytest.approx([0.0, 0.25, 0.5])


def test_a_retry_rescues_a_lost_request():
    link = loopback_serial(Slave(unit=1))
    master = Master(link, timeout=0.1, retries=1)
    link.faults.flip_bits(1, target="request")
    assert master.read_holding_registers(1, 0, 1) == [0]
    assert master.stats.as_dict()["timeouts"] == 1
    assert master.stats.valid_responses == 1 and master.stats.retries == 1
    assert link.slaves[0].counters.checksum_errors == 1


# --- TCP transaction ids ----------------------------------------------------------------------------------
def test_transaction_id_increments_and_wraps():
    link = loopback_tcp(Slave(unit=1))
    master = Master(link, transaction_id=65534)
    for _ in range(3):
        master.read_coils(1, 0, 1)
    tids = [TcpFrame.decode(e.data, e.guessed_role).transaction_id for e in master.log]
    assert tids == [65534, 65534, 65535, 65535, 0, 0]
    assert master.transaction_id == 1 and master.last_transaction_id == 0


def test_source_000_exchange_byte_for_byte():
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 1234
    link = loopback_tcp(slave)
    master = Master(link, transaction_id=0x0118)
    assert master.read_holding_registers(unit=1, address=0, count=1) == [1234]
    assert master.log[0].data == bytes.fromhex("01 18 00 00 00 06 01 03 00 00 00 01")
    assert master.log[1].data == bytes.fromhex("01 18 00 00 00 05 01 03 02 04 D2")


def test_a_late_tcp_answer_is_a_transaction_mismatch_and_the_master_keeps_waiting():
    slave = Slave(unit=1)
    link = loopback_tcp(slave)
    master = Master(link, timeout=0.2)
    link.faults.delay(1, 0.3)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)  # transaction 1 answered at 0.3 s
    link.faults.clear()
    # transaction 2 waits its turn in the server (busy until 0.3 s), then both answers arrive:
    assert master.read_holding_registers(1, 0, 1) == [0]
    assert master.stats.mismatches == 1 and master.stats.valid_responses == 1
    assert "transaction id 1, expected 2" in master.log[-2].note
    assert link.clock.now == pytest.approx(0.3)


def test_only_mismatches_raise_transaction_mismatch_error():
    link = loopback_tcp(Slave(unit=1), latency=0.001)
    link.faults.answer_as(1, 2)
    master = Master(link, timeout=0.1)
    with pytest.raises(TransactionMismatchError, match="unit 2, expected 1"):
        master.read_holding_registers(1, 0, 1)
    assert master.stats.timeouts == 1 and master.stats.mismatches == 1


def test_stale_frames_are_discarded_before_a_request():
    link = loopback_tcp(Slave(unit=1))
    master = Master(link, timeout=0.2)
    link.faults.delay(1, 0.3, requests=1)
    with pytest.raises(ModbusTimeoutError):
        master.read_input_registers(1, 0, 1)
    link.run(0.5)  # the late answer arrives while nobody waits
    assert master.read_input_registers(1, 0, 1) == [0]
    assert master.stats.mismatches == 1
    assert "stale" in master.log[1].note and master.log[1].direction == "rx"


# --- a scripted link: the master against any bytes -----------------------------------------------------
class ScriptedLink(Link):
    """Answers each request with the next scripted frames (a list per request)."""

    def __init__(self, script, mode="rtu"):
        self.mode = mode
        self.clock = VirtualClock()
        self.script = deque(script)
        self.inbox: deque[bytes] = deque()
        self.sent: list[bytes] = []

    def send(self, frame):
        self.sent.append(frame)
        if self.script:
            self.inbox.extend(self.script.popleft())

    def receive(self, timeout):
        if self.inbox:
            self.clock.advance(0.001)
            return self.inbox.popleft()
        self.clock.advance(timeout)
        return None


def rtu(unit, pdu):
    return RtuFrame(unit, pdu).encode()


def test_master_classifies_every_kind_of_answer():
    good = rtu(1, ReadHoldingRegistersResponse(registers=(5,)))
    bad_crc = good[:-1] + bytes([good[-1] ^ 0xFF])
    wrong_count = rtu(1, ReadHoldingRegistersResponse(registers=(5, 6)))
    other_function = rtu(1, ReadCoilsResponse(bits=(True,) * 8))
    other_unit = rtu(2, ReadHoldingRegistersResponse(registers=(9,)))
    truncated_other_unit = RtuFrame(3, ReadHoldingRegistersRequest(address=0, count=1)).encode()
    too_short = b"\x01\x03"
    link = ScriptedLink([
        [bad_crc],
        [wrong_count],
        [other_function, other_unit, truncated_other_unit, good],
        [too_short],
        [],
    ])
    master = Master(link, timeout=0.5)
    with pytest.raises(CrcError):
        master.read_holding_registers(1, 0, 1)
    with pytest.raises(PduError, match="2 registers, expected 1"):
        master.read_holding_registers(1, 0, 1)
    assert master.read_holding_registers(1, 0, 1) == [5]
    with pytest.raises(ModbusError):
        master.read_holding_registers(1, 0, 1)
    with pytest.raises(ModbusTimeoutError):
        master.read_holding_registers(1, 0, 1)
    s = master.stats
    assert (s.requests, s.checksum_errors, s.bad_responses, s.mismatches, s.valid_responses, s.timeouts) == (
        5, 1, 2, 3, 1, 1)
    assert s.requests == s.valid_responses + s.exceptions + s.timeouts + s.checksum_errors + s.bad_responses
    notes = [e.note for e in master.log if e.direction == "rx"]
    assert notes[0].startswith("checksum error") and "mismatch" in notes[2]


def test_write_echo_must_match():
    echo = rtu(1, WriteSingleRegisterResponse(address=1, value=99))
    link = ScriptedLink([[echo]])
    with pytest.raises(PduError, match="echo"):
        Master(link).write_single_register(1, 1, 98)


# --- polling ------------------------------------------------------------------------------------------------
def test_poll_ten_minutes_instantly_with_errors_in_the_results():
    slave = Slave(unit=1)
    ticks = iter(range(10**6))

    def measure(slave, kind, address, count):
        slave.bank.holding_registers[0] = next(ticks)

    slave.on_read = measure
    link = loopback_serial(slave)
    master = Master(link, timeout=0.5)
    link.faults.silence(1, requests=2)
    results = master.poll(interval=1.0, polls=600, function=3, unit=1, address=0, quantity=1)
    assert len(results) == 600
    assert all(isinstance(r, ModbusTimeoutError) for r in results[:2])
    assert results[2:5] == [[0], [1], [2]]
    assert link.clock.now == pytest.approx(599 + 22 * 10 / 9600)
    assert master.stats.valid_responses == 598 and master.stats.timeouts == 2
    assert master.stats.success_rate == pytest.approx(598 / 600)
    timed = master.poll(0.01, 3, with_time=True)  # shorter than a transaction: back to back
    assert [round(t - timed[0][0], 6) for t, _ in timed] == [0, pytest.approx(0.022917, abs=1e-6),
                                                           pytest.approx(0.045833, abs=1e-6)]
    assert master.read_once(3, 1, 0, 1) == [601]


def test_poll_polls_is_the_number_of_polls_and_quantity_the_registers():
    slave = Slave(unit=2)
    slave.bank.input_registers.write(4, [40, 41, 42])
    slave.bank.coils.write(0, [True, False, True])
    master = Master(loopback_serial(slave))
    assert master.poll(0.5, 2, function=4, unit=2, address=4, quantity=3) == [[40, 41, 42]] * 2
    assert master.poll(polls=1, function=1, unit=2, quantity=3) == [[True, False, True]]
    defaults = master.poll()  # 10 polls, 1 s apart, of holding register 0 of unit 1: nobody here
    assert len(defaults) == 10 and all(isinstance(r, ModbusTimeoutError) for r in defaults)


def test_poll_older_spelling_still_works_and_warns():
    slave = Slave(unit=1)
    slave.bank.holding_registers.write(0, [7, 8])
    master = Master(loopback_serial(slave))
    with pytest.warns(PendingDeprecationWarning, match="older spelling"):
        older = master.poll(function=3, unit=1, address=0, count=2, interval=1.0, polls=3)
    assert older == [[7, 8]] * 3
    assert master.poll(interval=0.1, polls=2) == [[7]] * 2  # the spelling of today: no warning
    with pytest.warns(DeprecationWarning, match="now poll\\(polls="):
        assert master.poll(interval=0.1, count=2) == [[7]] * 2  # count= was the number of polls
    with pytest.raises(ConfigError, match="either"):
        master.poll(count=2, quantity=2, polls=3)
    with pytest.raises(ConfigError, match="no setting registers"):
        master.poll(registers=2)


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"polls": -1}, ConfigError, "polls"),
        ({"polls": 2.5}, ConfigError, "polls"),
        ({"polls": True}, ConfigError, "polls"),
        ({"interval": "x"}, ConfigError, "interval"),
        ({"interval": -1}, ConfigError, "interval"),
        ({"quantity": "2"}, ConfigError, "quantity"),
        ({"quantity": 0}, QuantityError, None),
        ({"quantity": 126}, QuantityError, None),
        ({"function": 6}, ConfigError, "function 1, 2, 3 or 4"),
        ({"unit": 0}, ConfigError, "broadcast"),  # on a serial line
    ],
)
def test_poll_bad_settings_raise_before_the_first_poll(kwargs, error, message):
    master = Master(loopback_serial(Slave(unit=1)))
    with pytest.raises(error, match=message):
        master.poll(**kwargs)
    assert master.stats.requests == 0


def test_the_summary_counts_in_words_one_and_many():
    one = MasterStats(requests=1, exceptions=1, timeouts=1, checksum_errors=1, bad_responses=1,
                      mismatches=1, broadcasts=1).summary()
    assert one == ("1 request: 0 valid, 1 exception, 1 timeout, 1 checksum error, 1 bad response, "
                   "1 mismatch, 1 broadcast")
    two = MasterStats(requests=2, mismatches=2, bad_responses=2).summary()
    assert "2 requests:" in two and "2 mismatches" in two and "2 bad responses" in two


def test_stats_reset_summary_and_repr():
    master = Master(loopback_serial(Slave(unit=1)))
    master.read_coils(1, 0, 1)
    assert master.stats.summary().startswith("1 request: 1 valid, 0 exceptions, 0 timeouts")
    assert "latency" in str(master.stats)
    assert "Master on virtual serial line" in repr(master)
    master.stats.reset()
    assert master.stats == MasterStats() and master.stats.success_rate == 0.0
    assert master.stats.answered == 0


# --- the traffic log ----------------------------------------------------------------------------------------
def test_traffic_entries_and_log_views():
    from modbus_edu.traffic import Traffic, TrafficLog

    tcp = Traffic(1.5, "tx", "tcp", bytes.fromhex("01 18 00 00 00 06 01 03 00 00 00 01"), source="client")
    asc = Traffic(2.0, "rx", "ascii", b":050304FF0600648B\r\n", note="meter")
    rtu_exc = Traffic(3.0, "rx", "rtu", bytes.fromhex("01 83 02 C0 F1"))
    short = Traffic(4.0, "rx", "rtu", b"")
    assert (tcp.unit, tcp.function, tcp.guessed_role) == (1, 3, "request")
    assert (asc.unit, asc.function, asc.guessed_role) == (5, 3, "response")
    assert asc.text == ":050304FF0600648B\\r\\n"
    assert (rtu_exc.unit, rtu_exc.function) == (1, 0x83)
    assert (short.unit, short.function) == (None, None)
    assert Traffic(0, "rx", "ascii", b":zz").unit is None
    with pytest.raises(ConfigError):
        Traffic(0, "up", "rtu", b"")
    log = TrafficLog([tcp, asc, rtu_exc, short], maxlen=3)
    assert len(log) == 3 and log[0] is asc and log.maxlen == 3
    assert [e.time for e in log.search(function=3)] == [2.0, 3.0]  # 0x83 answers function 3
    assert len(log.search(text="METER")) == 1 and len(log.search(text="c0 f1")) == 1
    assert len(log.search(text="c0f1")) == 1
    log.annotate("late")
    log.annotate("again")
    assert log[-1].note == "late; again"
    text = log.to_text(newest_first=True)
    assert text.splitlines()[1].lstrip().startswith("4.000000")
    assert "05 03" not in text and ":050304FF0600648B" in str(log)
    html = log._repr_html_()
    assert html.count("<tr") == 4 and "late; again" in html and "-&gt;" not in html
    assert log.explain(1).frame.pdu == ExceptionResponse(3, 2)
    with pytest.raises(ModbusError):
        log[10]
    log.add(5.0, "tx", "rtu", b"\x01", note="x")
    assert len(log) == 3 and "TrafficLog: 3" in repr(log)
    empty = TrafficLog()
    empty.annotate("nothing")
    assert empty.to_text().startswith("      time")


def test_recorded_entries_read_like_added_ones():
    from modbus_edu.traffic import Traffic, TrafficLog

    fields = (1.5, "rx", "rtu", bytearray(b"\x01\x03"), "unit 1", "master", "a note", "response", 0.25)
    added, recorded = TrafficLog(), TrafficLog(maxlen=2)
    added.add(*fields[:4], source="unit 1", dest="master", note="a note", role="response", duration=0.25)
    recorded.record(*fields)
    assert recorded[0] == added[0] == Traffic(*fields) and isinstance(recorded[0].data, bytes)
    assert list(recorded) == list(added) and recorded.to_text() == added.to_text()
    assert recorded._repr_html_() == added._repr_html_()
    assert len(recorded.search(text="a NOTE", unit=1, function=3)) == 1
    recorded.annotate("late")
    added.annotate("late")
    assert recorded[-1].note == "a note; late" and recorded[-1] == added[-1]
    recorded.record(2.0, "tx", "rtu", b"\x01")
    recorded.record(3.0, "tx", "rtu", b"\x02")
    assert [e.time for e in recorded] == [2.0, 3.0]  # maxlen keeps the newest
    with pytest.raises(ConfigError):
        recorded.record(4.0, "up", "rtu", b"")

    class Echo(TrafficLog):  # a log that does something with every entry still sees recorded ones
        def add(self, *args, **kwargs):
            entry = super().add(*args, **kwargs)
            self.seen = entry
            return entry

    echo = Echo()
    echo.record(*fields)
    assert echo.seen == echo[0] == Traffic(*fields)


def test_notes_of_equal_pdus_are_remembered_but_only_for_exactly_equal_values():
    from enum import IntEnum

    from modbus_edu.pdu import ReadCoilsResponse, WriteMultipleRegistersRequest
    from modbus_edu.traffic import pdu_note

    class Mode(IntEnum):
        AUTO = 5

    plain = WriteMultipleRegistersRequest(address=0, values=[5, 6])
    fancy = WriteMultipleRegistersRequest(address=0, values=[Mode.AUTO, 6])
    assert plain == fancy and plain.summary() != fancy.summary()  # the enum prints as itself
    for pdu in (plain, fancy, plain, fancy):
        assert pdu_note(pdu) == pdu.summary()
    three = ReadCoilsResponse(bits=[True, False, True])
    eight = ReadCoilsResponse(bits=[True, False, True] + [False] * 5)  # the same byte on the wire
    assert pdu_note(three) == three.summary() and pdu_note(eight) == eight.summary() != three.summary()
    assert pdu_note(ExceptionResponse(3, 2)) == ExceptionResponse(3, 2).summary()


def test_pdu_notes_are_remembered_for_every_pdu_module():
    """Each PDU class's summary is written once per distinct value, wherever in pdu/ the class lives."""
    from modbus_edu import traffic
    from modbus_edu.pdu import (
        ExceptionResponse,
        ReadCoilsRequest,
        ReadDeviceIdentificationRequest,
        ReadHoldingRegistersRequest,
    )

    traffic._NOTES.clear()
    for pdu in (ReadHoldingRegistersRequest(address=0, count=10), ReadCoilsRequest(address=1, count=2),
                ExceptionResponse(3, 2), ReadDeviceIdentificationRequest(1, 0)):
        traffic.pdu_note(pdu)
        assert traffic._field_names(type(pdu)) is not None, type(pdu).__module__
    assert len(traffic._NOTES) == 4
