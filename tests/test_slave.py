"""Slave: every function, every exception case, units, broadcast, hooks, counters."""

from __future__ import annotations

import pytest

from modbus_edu.crc import crc16, lrc
from modbus_edu.datamodel import DataBank
from modbus_edu.errors import ConfigError, FrameError, ModbusExceptionError
from modbus_edu.framing import AsciiFrame, RtuFrame, TcpFrame
from modbus_edu.pdu import (
    ExceptionResponse,
    MaskWriteRegisterRequest,
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    ReadInputRegistersRequest,
    ReadInputRegistersResponse,
    WriteFileRecordRequest,
    WriteMultipleCoilsRequest,
    WriteMultipleCoilsResponse,
    WriteMultipleRegistersRequest,
    WriteMultipleRegistersResponse,
    WriteSingleCoilRequest,
    WriteSingleCoilResponse,
    WriteSingleRegisterRequest,
    WriteSingleRegisterResponse,
)
from modbus_edu.slave import Slave, SlaveCounters, dispatch


def rtu(body_hex: str) -> bytes:
    body = bytes.fromhex(body_hex)
    return body + crc16(body).to_bytes(2, "little")


def ascii_frame(body_hex: str) -> bytes:
    body = bytes.fromhex(body_hex)
    return b":" + (body + bytes([lrc(body)])).hex().upper().encode() + b"\r\n"


def rtu_response(data: bytes):
    return RtuFrame.decode(data, role="response")


@pytest.fixture
def slave() -> Slave:
    s = Slave(unit=17)
    bank = s.bank
    bank.coils.write(19, [True, False, True, True, False, False, True, True, True, False])
    bank.discrete_inputs.write(196, [False, False, True, True, False, True, False, True])
    bank.holding_registers.write(107, [0x022B, 0x0000, 0x0064])
    bank.input_registers[8] = 0x000A
    return s


# --- the eight functions, straight on PDUs ----------------------------------------------------------
def test_read_coils(slave):
    response = slave.handle_pdu(ReadCoilsRequest(address=19, count=10))
    bits = (True, False, True, True, False, False, True, True, True, False)
    assert response == ReadCoilsResponse(bits=bits)


def test_read_discrete_inputs(slave):
    response = slave.handle_pdu(ReadDiscreteInputsRequest(address=196, count=8))
    assert response == ReadDiscreteInputsResponse(bits=(False, False, True, True, False, True, False, True))


def test_read_holding_registers(slave):
    response = slave.handle_pdu(ReadHoldingRegistersRequest(address=107, count=3))
    assert response == ReadHoldingRegistersResponse(registers=(0x022B, 0, 0x64))


def test_read_input_registers(slave):
    assert slave.handle_pdu(ReadInputRegistersRequest(address=8, count=1)) == ReadInputRegistersResponse(
        registers=(10,)
    )


def test_write_single_coil(slave):
    assert slave.handle_pdu(WriteSingleCoilRequest(address=172, value=True)) == WriteSingleCoilResponse(
        address=172, value=True
    )
    assert slave.bank.coils[172] is True


def test_write_single_register(slave):
    assert slave.handle_pdu(WriteSingleRegisterRequest(address=1, value=3)) == WriteSingleRegisterResponse(
        address=1, value=3
    )
    assert slave.bank.holding_registers[1] == 3


def test_write_multiple_coils(slave):
    bits = (True, False, True, True, False, False, True, True, True, False)
    response = slave.handle_pdu(WriteMultipleCoilsRequest(address=100, values=bits))
    assert response == WriteMultipleCoilsResponse(address=100, count=10)
    assert tuple(slave.bank.coils.read(100, 10)) == bits


def test_write_multiple_registers(slave):
    response = slave.handle_pdu(WriteMultipleRegistersRequest(address=1, values=(10, 258)))
    assert response == WriteMultipleRegistersResponse(address=1, count=2)
    assert slave.bank.holding_registers.read(1, 2) == [10, 258]
    assert slave.counters.requests == 1 and slave.counters.responses == 1


# --- the spec's example frames -----------------------------------------------------------------------
def test_rtu_frames_from_the_spec(slave):
    answer = slave.handle(bytes.fromhex("11 03 00 6B 00 03 76 87"), "rtu")
    assert answer == RtuFrame(17, ReadHoldingRegistersResponse(registers=(0x022B, 0, 0x64))).encode()
    answer = slave.handle(bytes.fromhex("11 05 00 AC FF 00 4E 8B"), "rtu")
    assert answer == bytes.fromhex("11 05 00 AC FF 00 4E 8B")  # the echo
    answer = slave.handle(bytes.fromhex("11 0F 00 13 00 0A 02 CD 01 BF 0B"), "rtu")
    assert rtu_response(answer).pdu == WriteMultipleCoilsResponse(address=19, count=10)
    assert slave.bank.coils.read(19, 10) == [True, False, True, True, False, False, True, True, True, False]


def test_ascii_exchange_of_source_004():
    slave = Slave(unit=5)
    slave.bank.holding_registers.write(0x1000, [0xFF06, 0x0064])
    assert slave.handle(b":050310000002E6\r\n", "ascii") == b":050304FF0600648B\r\n"
    assert slave.handle(b":050610010200E2\r\n", "ascii") == b":050610010200E2\r\n"
    assert slave.bank.holding_registers[0x1001] == 0x0200


def test_tcp_exchange_of_source_000_keeps_the_transaction_id():
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 1234
    answer = slave.handle(bytes.fromhex("01 18 00 00 00 06 01 03 00 00 00 01"), "tcp")
    assert answer == bytes.fromhex("01 18 00 00 00 05 01 03 02 04 D2")


# --- exception responses -----------------------------------------------------------------------------
def exception_of(answer: bytes, mode: str = "rtu") -> ExceptionResponse:
    frame = {"rtu": RtuFrame, "ascii": AsciiFrame, "tcp": TcpFrame}[mode].decode(answer, role="response")
    assert isinstance(frame.pdu, ExceptionResponse), frame
    return frame.pdu


@pytest.mark.parametrize("function", [9, 0x0D, 0x13, 0x41, 0x2C, 0x7F])
def test_unknown_function_is_exception_01(slave, function):
    answer = slave.handle(rtu(f"11 {function:02X} 00 00 00 01"), "rtu")
    assert exception_of(answer) == ExceptionResponse(function=function, code=1)
    assert slave.counters.exceptions == 1


def test_exception_01_in_ascii_and_tcp(slave):
    assert exception_of(slave.handle(ascii_frame("11 2C 0E 01 00"), "ascii"), "ascii").code == 1
    assert exception_of(slave.handle(bytes.fromhex("00 07 00 00 00 02 11 09"), "tcp"), "tcp").code == 1


def test_function_codes_that_cannot_be_requests_get_no_answer(slave):
    assert slave.handle(rtu("11 00 00 00"), "rtu") is None
    assert slave.handle(rtu("11 83 02"), "rtu") is None
    assert slave.counters.bad_frames == 2 and slave.counters.responses == 0


def test_illegal_address_02_out_of_a_sparse_bank():
    bank = DataBank(sparse=True)
    bank.holding_registers.declare(0, 2, 7)
    slave = Slave(unit=1, bank=bank)
    ok = slave.handle_pdu(ReadHoldingRegistersRequest(address=0, count=2))
    assert ok.registers == (7, 7)
    for request in (
        ReadHoldingRegistersRequest(address=1, count=2),
        ReadHoldingRegistersRequest(address=5, count=1),
        WriteSingleRegisterRequest(address=9, value=1),
        WriteMultipleRegistersRequest(address=1, values=(1, 2)),
        ReadCoilsRequest(address=0, count=1),
        ReadInputRegistersRequest(address=0, count=1),
    ):
        assert slave.handle_pdu(request) == ExceptionResponse(request.function_code, 2), request
    assert bank.holding_registers[1] == 7  # a failed multiple write changes nothing


def test_address_range_past_65535_is_exception_02(slave):
    answer = slave.handle(rtu("11 03 FF FF 00 02"), "rtu")
    assert exception_of(answer) == ExceptionResponse(3, 2)


@pytest.mark.parametrize(
    "body",
    [
        "11 03 00 00 00 00",  # quantity 0
        "11 03 00 00 00 7E",  # quantity 126 > 125
        "11 01 00 00 07 D1",  # 2001 coils
        "11 05 00 01 12 34",  # coil value not FF00/0000
        "11 10 00 01 00 02 03 00 0A 01",  # byte count disagrees with quantity
        "11 10 00 01 00 02 04 00 0A 01",  # implied length wrong (truncated)
        "11 03 00 00 00 01 00",  # trailing byte
        "11 0F 00 13 00 0A 01 CD",  # byte count 1 for 10 coils
    ],
)
def test_bad_quantity_or_value_is_exception_03(slave, body):
    function = bytes.fromhex(body)[1]
    assert exception_of(slave.handle(rtu(body), "rtu")) == ExceptionResponse(function, 3)


def test_hook_failure_is_exception_04():
    def broken(slave, kind, address, count):
        raise RuntimeError("sensor unplugged")

    slave = Slave(unit=1, on_read=broken)
    assert slave.handle_pdu(ReadInputRegistersRequest(address=0, count=1)) == ExceptionResponse(4, 4)
    assert isinstance(slave.last_error, RuntimeError)
    answer = slave.handle(rtu("01 04 00 00 00 01"), "rtu")
    assert exception_of(answer) == ExceptionResponse(4, 4)


def test_write_hook_failure_is_exception_04_and_hook_may_choose_a_code():
    def busy(slave, kind, address, values):
        raise ModbusExceptionError(6, 6)

    slave = Slave(unit=1, on_write=busy)
    assert slave.handle_pdu(WriteSingleRegisterRequest(address=0, value=1)) == ExceptionResponse(6, 6)

    def weird(slave, kind, address, values):
        raise ModbusExceptionError(6, 0)

    slave.on_write = weird
    assert slave.handle_pdu(WriteSingleRegisterRequest(address=0, value=1)) == ExceptionResponse(6, 4)


def test_a_response_pdu_given_as_request_is_illegal_function(slave):
    assert slave.handle_pdu(ReadCoilsResponse(bits=(True,))) == ExceptionResponse(1, 1)


# --- frames that get no answer -----------------------------------------------------------------------
def test_bad_crc_gets_no_answer_and_is_counted(slave):
    frame = bytearray(bytes.fromhex("11 03 00 6B 00 03 76 87"))
    frame[3] ^= 0x01
    assert slave.handle(bytes(frame), "rtu") is None
    assert slave.counters.checksum_errors == 1
    assert "CRC" in slave.log[-1].note


def test_bad_lrc_and_malformed_frames(slave):
    assert slave.handle(b":110300000001EA\r\n", "ascii") is None  # LRC should be EB
    assert slave.counters.checksum_errors == 1
    assert slave.handle(b"110300000001EB\r\n", "ascii") is None  # no ':'
    assert slave.handle(b"\x11\x03", "rtu") is None  # too short
    assert slave.handle(bytes.fromhex("00 01 00 01 00 06 11 03 00 00 00 01"), "tcp") is None  # protocol 1
    assert slave.handle(bytes.fromhex("00 01 00 00 00 09 11 03 00 00 00 01"), "tcp") is None  # bad length
    assert slave.counters.bad_frames == 4
    assert slave.counters.responses == 0


def test_a_reserved_serial_unit_is_heard_but_not_answered_by_an_any_unit_slave():
    slave = Slave(unit=None)
    assert slave.handle(rtu("F8 03 00 00 00 01"), "rtu") is None
    assert slave.counters.other_unit == 1 and slave.counters.bad_frames == 0


def test_handle_rejects_non_bytes_and_bad_mode(slave):
    with pytest.raises(FrameError):
        slave.handle("11 03", "rtu")  # type: ignore[arg-type]
    with pytest.raises(ConfigError):
        slave.handle(rtu("11 03 00 00 00 01"), "modbus+udp")


# --- units and broadcast -----------------------------------------------------------------------------
def test_other_unit_is_silent(slave):
    assert slave.handle(rtu("01 03 00 00 00 01"), "rtu") is None
    assert slave.handle(rtu("01 2B 0E 01 00"), "rtu") is None  # even an unknown function: not ours
    assert slave.handle(bytes.fromhex("00 01 00 00 00 06 01 03 00 00 00 01"), "tcp") is None
    assert slave.counters.other_unit == 3
    assert slave.counters.requests == 0


def test_unit_none_answers_every_unit():
    slave = Slave(unit=None)
    for unit in (1, 17, 247):
        answer = slave.handle(rtu(f"{unit:02X} 03 00 00 00 01"), "rtu")
        assert RtuFrame.decode(answer, "response").unit == unit
    tcp = slave.handle(bytes.fromhex("00 09 00 00 00 06 FF 03 00 00 00 01"), "tcp")
    assert TcpFrame.decode(tcp, "response").unit == 255 and tcp[:2] == b"\x00\x09"


@pytest.mark.parametrize("mode", ["rtu", "ascii", "tcp"])
def test_broadcast_writes_and_never_answers(mode):
    slaves = [Slave(unit=u) for u in (1, 2, 3)]
    request = {"rtu": RtuFrame(0, WriteSingleRegisterRequest(address=4, value=99)),
               "ascii": AsciiFrame(0, WriteSingleRegisterRequest(address=4, value=99)),
               "tcp": TcpFrame(7, 0, WriteSingleRegisterRequest(address=4, value=99))}[mode].encode()
    assert dispatch(slaves, request, mode) == []
    for s in slaves:
        assert s.bank.holding_registers[4] == 99
        assert s.counters.broadcasts == 1 and s.counters.responses == 0


def test_broadcast_read_is_ignored_and_broadcast_exception_is_silent(slave):
    assert slave.handle(rtu("00 03 00 00 00 01"), "rtu") is None
    assert slave.handle(rtu("00 03 00 00 00 00"), "rtu") is None  # quantity 0: no exception either
    assert slave.handle(rtu("00 2B 0E 01 00"), "rtu") is None
    assert slave.counters.broadcasts == 3 and slave.counters.responses == 0


@pytest.mark.parametrize("request_pdu, written", [
    (WriteFileRecordRequest(records=[(4, 2, [7, 8])]), lambda bank: bank.files.read(4, 2, 2) == [7, 8]),
    (MaskWriteRegisterRequest(address=3, and_mask=0x0000, or_mask=0x0025),
     lambda bank: bank.holding_registers[3] == 0x0025),
], ids=["FC 21", "FC 22"])
def test_every_write_function_is_carried_out_on_broadcast(request_pdu, written):
    """FC 21 and 22 write: a broadcast of them is carried out (never answered), not ignored as a read.
    FC 23 reads back what it asks for, so a broadcast of it is ignored (tests/test_broadcast.py)."""
    slave = Slave(unit=1)
    assert slave.handle(RtuFrame(0, request_pdu).encode(), "rtu") is None
    assert written(slave.bank)
    assert slave.counters.broadcasts == 1 and slave.counters.responses == 0


def test_bad_unit_argument():
    for unit in (0, 256, -1, "1", True):
        with pytest.raises(ConfigError):
            Slave(unit=unit)  # type: ignore[arg-type]
    with pytest.raises(ConfigError):
        Slave(processing_time=-1)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"bank": 5}, "bank must be a DataBank"),
        ({"bank": {"40001": 5}}, "bank must be a DataBank"),
        ({"processing_time": "slow"}, "processing_time must be a number"),
        ({"on_read": "measure"}, "on_read must be a function"),
        ({"on_write": 3}, "on_write must be a function"),
        ({"name": 7}, "name must be a text"),
    ],
)
def test_bad_settings_are_config_errors_not_a_later_exception_04(kwargs, message):
    # Slave(bank=5) used to be accepted, and then every request was answered with exception 04
    with pytest.raises(ConfigError, match=message):
        Slave(**kwargs)


# --- Modbus/TCP: the device itself (handle_direct) -------------------------------------------------------
def tcp(tid: int, unit: int, pdu) -> bytes:
    return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()


@pytest.mark.parametrize("unit", [0, 0xFF, 17, 99])
def test_handle_direct_answers_whatever_the_unit_and_echoes_it(slave, unit):
    write = slave.handle_direct(tcp(5, unit, WriteSingleRegisterRequest(address=3, value=333)))
    frame = TcpFrame.decode(write, "response")
    assert (frame.transaction_id, frame.unit) == (5, unit)
    assert frame.pdu == WriteSingleRegisterResponse(address=3, value=333)
    read = TcpFrame.decode(slave.handle_direct(tcp(6, unit, ReadHoldingRegistersRequest(3, 1))), "response")
    assert (read.transaction_id, read.unit, read.pdu.registers) == (6, unit, (333,))
    assert slave.counters.requests == slave.counters.responses == 2
    assert slave.counters.broadcasts == slave.counters.other_unit == 0
    note = slave.log[-2].note
    assert ("this device itself" in note) == (unit != 17)


def test_handle_direct_answers_exceptions_too(slave):
    # quantity 0: illegal data value; an unknown function: illegal function - both echo unit 0
    bad = slave.handle_direct(bytes.fromhex("00 01 00 00 00 06 00 03 00 00 00 00"))
    assert TcpFrame.decode(bad, "response").pdu == ExceptionResponse(3, 3)
    assert bad[6] == 0
    unknown = slave.handle_direct(bytes.fromhex("00 02 00 00 00 04 FF 2C 0E 01"))
    assert TcpFrame.decode(unknown, "response").pdu == ExceptionResponse(0x2C, 1)
    assert slave.counters.exceptions == 2 and slave.counters.broadcasts == 0


def test_handle_keeps_unit_0_a_broadcast_and_handle_direct_does_not_leak(slave):
    # handle() cannot know how the frame came: unit 0 stays the serial-line broadcast in every mode;
    # only a server that knows the device was reached by its IP address calls handle_direct()
    write = tcp(1, 0, WriteSingleRegisterRequest(address=1, value=11))
    assert slave.handle(write, "tcp") is None
    assert slave.counters.broadcasts == 1
    assert slave.handle_direct(write) is not None
    assert slave.handle(tcp(2, 0xFF, ReadHoldingRegistersRequest(0, 1)), "tcp") is None  # not unit 17
    assert slave.counters.other_unit == 1


def test_handle_direct_goes_through_an_overridden_handle():
    seen = []

    class Buffered(Slave):
        def handle(self, frame, mode="rtu"):
            seen.append(mode)
            return super().handle(frame, mode)

    device = Buffered(unit=4)
    assert device.handle_direct(tcp(1, 0, ReadHoldingRegistersRequest(0, 1))) is not None
    assert seen == ["tcp"]


def test_dispatch_multidrop_only_the_addressed_slave_answers():
    slaves = [Slave(unit=u) for u in (1, 2, 3)]
    slaves[1].bank.holding_registers[0] = 42
    answers = dispatch(slaves, rtu("02 03 00 00 00 01"), "rtu")
    assert len(answers) == 1
    assert rtu_response(answers[0]).pdu.registers == (42,)
    assert [s.counters.other_unit for s in slaves] == [1, 0, 1]
    assert dispatch(slaves[0], rtu("01 03 00 00 00 01"), "rtu")


# --- hooks ---------------------------------------------------------------------------------------------
def test_hooks_see_reads_before_and_writes_after():
    calls = []

    def on_read(slave, kind, address, count):
        calls.append(("read", kind, address, count))
        slave.bank.input_registers[address] = 321  # a device measures when asked

    def on_write(slave, kind, address, values):
        stored = slave.bank.table(kind).read(address, len(values))
        calls.append(("write", kind, address, list(values), stored))

    slave = Slave(unit=1, on_read=on_read, on_write=on_write)
    assert slave.handle_pdu(ReadInputRegistersRequest(address=3, count=1)).registers == (321,)
    slave.handle_pdu(WriteMultipleCoilsRequest(address=2, values=(True, True)))
    slave.handle_pdu(WriteSingleRegisterRequest(address=9, value=5))
    assert calls == [
        ("read", "input_registers", 3, 1),
        ("write", "coils", 2, [True, True], [True, True]),
        ("write", "holding_registers", 9, [5], [5]),
    ]


def test_subclass_overrides_before_read_and_response_delay():
    class Counter(Slave):
        def before_read(self, table_kind, address, count):
            self.bank.holding_registers[0] += 1

        def response_delay(self, arrival_time):
            return 0.05 if arrival_time < 1 else 0.0

    s = Counter(unit=2, processing_time=0.01)
    assert s.handle_pdu(ReadHoldingRegistersRequest(address=0, count=1)).registers == (1,)
    assert s.handle_pdu(ReadHoldingRegistersRequest(address=0, count=1)).registers == (2,)
    assert s.response_delay(0.5) == 0.05 and s.response_delay(2) == 0.0
    assert Slave(processing_time=0.02).response_delay(123.0) == 0.02


# --- counters and log ----------------------------------------------------------------------------------
def test_counters_add_up_and_reset(slave):
    slave.handle(rtu("11 03 00 00 00 01"), "rtu")
    slave.handle(rtu("11 03 00 00 00 00"), "rtu")
    slave.handle(rtu("12 03 00 00 00 01"), "rtu")
    slave.handle(rtu("00 06 00 00 00 01"), "rtu")
    slave.handle(rtu("11 03 00 00 00 01")[:-1] + b"\x00", "rtu")
    assert slave.counters.as_dict() == {
        "requests": 3, "responses": 2, "exceptions": 1, "checksum_errors": 1, "bad_frames": 0,
        "broadcasts": 1, "other_unit": 1,
    }
    slave.counters.reset()
    assert slave.counters == SlaveCounters()
    assert len(slave.log) == 7  # 5 received + 2 answers
    assert [e.direction for e in slave.log][:2] == ["rx", "tx"]
    assert "17" in repr(slave)


def test_the_log_says_who_sent_each_frame():
    slave = Slave(unit=1)
    request = rtu("01 03 00 00 00 01")
    slave.handle(request, "rtu")
    assert [(e.source, e.dest) for e in slave.log] == [("master", "slave 1"), ("slave 1", "master")]
    # a link that knows the sender passes the frame through hear(): another slave's answer, say
    assert slave.hear(rtu("02 03 02 00 07"), "rtu", "slave 2") is None
    assert (slave.log[-1].source, slave.log[-1].dest, slave.log[-1].note) == (
        "slave 2", "slave 1", "for unit 2: ignored")
    assert slave.hear(request, "rtu", "master") is not None
    assert [e.label() for e in slave.log][-2:] == ["master -> slave 1", "slave 1 -> master"]
    # the label is restored afterwards, even when handling fails
    with pytest.raises(FrameError):
        slave.hear("not bytes", "rtu", "slave 9")  # type: ignore[arg-type]
    assert slave.sender == "master"


def test_the_same_request_again_gets_the_same_answer_and_counts_again(slave):
    # each different serial request is decoded once and remembered: repeating it changes nothing else
    request = rtu("11 03 00 00 00 01")
    answers = {slave.handle(request, "rtu") for _ in range(3)}
    assert len(answers) == 1 and slave.counters.requests == 3 and slave.counters.responses == 3
    bad = request[:-1] + bytes([request[-1] ^ 0xFF])
    assert slave.handle(bad, "rtu") is None and slave.handle(bad, "rtu") is None
    assert slave.counters.checksum_errors == 2


def test_listeners_hear_each_handled_request_after_it_is_logged():
    slave = Slave(unit=1)
    heard = []
    slave.listeners.append(lambda s: heard.append((s.counters.requests, len(s.log))))
    request = RtuFrame(unit=1, pdu=WriteSingleRegisterRequest(address=0, value=7)).encode()
    slave.handle(request, "rtu")
    slave.handle(request[:-1] + bytes([request[-1] ^ 1]), "rtu")  # a bad CRC: handled, not answered
    slave.handle_pdu(ReadHoldingRegistersRequest(address=0, count=1))
    assert heard == [(1, 2), (1, 3), (2, 3)]  # after the log: the request and its answer are in it
    slave.listeners.clear()
    slave.handle(request, "rtu")
    assert len(heard) == 3
