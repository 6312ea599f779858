"""One rule per function code for a broadcast (unit 0 on a serial line), kept in one table
(:data:`modbus_edu.codes.BROADCAST_FUNCTIONS`) that the master and the slave both follow, and what a
gateway answers to unit 0 on Modbus/TCP.

A broadcast may only write, and nobody answers it: FC 5, 6, 15, 16, 21 and 22 are carried out by every
slave; a read, FC 23 (its point is the registers it reads back) and FC 8 have no meaning as a broadcast.
The master refuses to send them; a slave that hears one neither acts on it nor answers.
"""

from __future__ import annotations

import pytest
from conftest_io import HOST  # noqa: F401  (the gateway test listens on 127.0.0.1)

import modbus_edu as mb
from modbus_edu import pdu as P
from modbus_edu.codes import BROADCAST_FUNCTIONS

#: One request of every function code the library implements; each write puts 0x0025 (or a coil on)
#: at address 3, or record 2 of file 4, so ``_written`` can tell whether a slave carried it out.
REQUESTS = {
    1: P.ReadCoilsRequest(address=0, count=1),
    2: P.ReadDiscreteInputsRequest(address=0, count=1),
    3: P.ReadHoldingRegistersRequest(address=0, count=1),
    4: P.ReadInputRegistersRequest(address=0, count=1),
    5: P.WriteSingleCoilRequest(address=3, value=True),
    6: P.WriteSingleRegisterRequest(address=3, value=0x0025),
    7: P.ReadExceptionStatusRequest(),
    8: P.DiagnosticsRequest(0x0A),  # clear counters: it would change something, were it carried out
    11: P.GetCommEventCounterRequest(),
    12: P.GetCommEventLogRequest(),
    15: P.WriteMultipleCoilsRequest(address=3, values=[True]),
    16: P.WriteMultipleRegistersRequest(address=3, values=[0x0025]),
    17: P.ReportServerIdRequest(),
    20: P.ReadFileRecordRequest(records=[(4, 2, 1)]),
    21: P.WriteFileRecordRequest(records=[(4, 2, [0x0025])]),
    22: P.MaskWriteRegisterRequest(address=3, and_mask=0x0000, or_mask=0x0025),
    23: P.ReadWriteMultipleRegistersRequest(read_address=0, read_count=1, write_address=3, values=[0x0025]),
    24: P.ReadFifoQueueRequest(address=0),
    43: P.ReadDeviceIdentificationRequest(1, 0),
}
ALLOWED = {5, 6, 15, 16, 21, 22}


def _written(slave: mb.Slave) -> bool:
    bank = slave.bank
    return bank.coils[3] or bank.holding_registers[3] == 0x0025 or bank.files.read(4, 2, 1) == [0x0025]


def _slave() -> mb.Slave:
    slave = mb.Slave(unit=1)
    slave.bank.files.write([(4, 2, [0])])  # a file record to write (FC 21) or read (FC 20)
    return slave


def test_every_function_code_has_its_rule_and_the_table_is_the_writes_that_read_nothing_back():
    assert set(REQUESTS) == set(P.REQUEST_CLASSES)
    assert BROADCAST_FUNCTIONS == ALLOWED
    assert 0x17 not in BROADCAST_FUNCTIONS and 0x17 in mb.codes.WRITE_FUNCTIONS  # FC 23 writes, but reads


@pytest.mark.parametrize("mode", ["rtu", "ascii"])
@pytest.mark.parametrize("function", sorted(REQUESTS))
def test_the_master_sends_a_broadcast_of_a_write_only_and_refuses_the_rest(function, mode):
    slaves = [_slave(), _slave()]
    for s in slaves:
        s.unit = None if s is slaves[1] else 1
    link = mb.loopback_serial(slaves, mode=mode)
    master = mb.Master(link, timeout=0.2)
    if function in ALLOWED:
        assert master.execute(0, REQUESTS[function]) is None
        assert master.stats.broadcasts == 1 and master.stats.timeouts == 0
        assert all(_written(s) for s in slaves)
    else:
        with pytest.raises(mb.ConfigError, match="cannot be broadcast"):
            master.execute(0, REQUESTS[function])
        assert master.stats.requests == 0 and len(link.monitor) == 0  # nothing went on the line
        assert not any(_written(s) for s in slaves)


def test_the_masters_own_methods_follow_the_table():
    link = mb.loopback_serial(_slave())
    master = mb.Master(link, timeout=0.2)
    with pytest.raises(mb.ConfigError, match=r"Read/Write Multiple Registers \(FC 23\) cannot be broadcast"):
        master.read_write_multiple_registers(0, 0, 1, 3, [0x0025])
    with pytest.raises(mb.ConfigError, match="a read cannot be broadcast"):
        master.read_holding_registers(0, 0, 1)
    with pytest.raises(mb.ConfigError, match=r"Diagnostics \(FC 8\) cannot be broadcast"):
        master.diagnostics(0, 0x04)  # force listen-only mode: sent to one device, not to all
    assert master.stats.requests == 0
    master.mask_write_register(0, 3, 0x0000, 0x0025)
    master.write_file_record(0, 4, 2, [7])
    bank = link.slaves[0].bank
    assert bank.holding_registers[3] == 0x0025 and bank.files.read(4, 2, 1) == [7]
    assert master.stats.broadcasts == 2


@pytest.mark.parametrize("mode", ["rtu", "ascii", "tcp"])
@pytest.mark.parametrize("function", sorted(REQUESTS))
def test_a_slave_carries_out_a_broadcast_write_and_ignores_the_rest_never_answering(function, mode):
    slave = _slave()
    frame = mb.make_frame(mode, 0, REQUESTS[function], 7).encode()
    assert slave.handle(frame, mode) is None
    assert slave.counters.broadcasts == 1 and slave.counters.responses == 0
    assert _written(slave) == (function in ALLOWED)
    if function not in ALLOWED:
        assert f"broadcast of FC {function}: ignored" in slave.log[-1].note


def test_a_gateway_answers_unit_0_with_0x0a_at_once_and_puts_nothing_on_the_line():
    slaves = [_slave(), mb.Slave(unit=2)]
    bus = mb.loopback_serial(slaves, baudrate=9600)
    with mb.TcpGateway(bus, timeout=0.2) as gateway, mb.tcp_link(*gateway.address) as tcp:
        master = mb.Master(tcp, timeout=5)
        for ask in (lambda: master.write_single_register(0, 3, 0x0025),
                    lambda: master.read_write_multiple_registers(0, 0, 1, 3, [0x0025]),
                    lambda: master.read_holding_registers(0, 0, 1)):
            with pytest.raises(mb.ModbusExceptionError) as caught:
                ask()
            assert caught.value.code == 0x0A and "gateway path unavailable" in str(caught.value)
    assert gateway.counters["path_unavailable"] == 3 and gateway.counters["no_response"] == 0
    assert len(bus.monitor) == 0 and not any(_written(s) for s in slaves)
