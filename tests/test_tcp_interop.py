"""Modbus/TCP between this library and pymodbus 3.16, both ways, over real sockets on 127.0.0.1.

1. a pymodbus ``ModbusTcpClient`` drives our :class:`TcpServer`: the eight functions, exceptions;
2. our :class:`Master` over :func:`tcp_link` drives a pymodbus ``ModbusTcpServer`` the same way.
"""

from __future__ import annotations

import pytest
from conftest_io import HOST, MAX_ALLOWED_VALUE, SIZE, PymodbusServer, pymodbus_device
from pymodbus.client import ModbusTcpClient
from pymodbus.pdu import ExceptionResponse as PymodbusException

from modbus_edu.datamodel import DataBank
from modbus_edu.errors import ConfigError, LinkError, ModbusExceptionError
from modbus_edu.links.tcp import TcpServer, tcp_link
from modbus_edu.master import Master
from modbus_edu.slave import Slave


def _course_slave() -> Slave:
    """A slave with a sparse bank: 0..99 of every table exist, everything else is 'illegal address'."""
    bank = DataBank(sparse=True)
    for table in (bank.coils, bank.discrete_inputs, bank.input_registers, bank.holding_registers):
        table.declare(0, 100)
    for i in range(10):
        bank.discrete_inputs[i] = i % 3 == 0
        bank.input_registers[i] = 1000 + i
    return Slave(unit=1, bank=bank)


@pytest.fixture
def served():
    slave = _course_slave()
    with TcpServer(slave) as server:
        client = ModbusTcpClient(HOST, port=server.address[1], timeout=2, retries=0)
        assert client.connect()
        try:
            yield slave, server, client
        finally:
            client.close()


# --- 1. pymodbus client -> our server ----------------------------------------------------------------
def test_pymodbus_client_reads_and_writes_all_eight_functions(served):
    slave, server, client = served
    bank = slave.bank

    r = client.write_coil(3, True, device_id=1)                                   # FC 5
    assert not r.isError() and bank.coils[3] is True
    r = client.write_coils(10, [True, False, True, True, False], device_id=1)     # FC 15
    assert not r.isError()
    assert bank.coils.read(10, 5) == [True, False, True, True, False]
    r = client.read_coils(10, count=5, device_id=1)                               # FC 1
    assert r.bits[:5] == [True, False, True, True, False]

    r = client.read_discrete_inputs(0, count=10, device_id=1)                     # FC 2
    assert r.bits[:10] == [i % 3 == 0 for i in range(10)]

    r = client.write_register(7, 0xBEEF, device_id=1)                             # FC 6
    assert not r.isError() and bank.holding_registers[7] == 0xBEEF
    r = client.write_registers(20, [1, 2, 65535, 0, 1234], device_id=1)          # FC 16
    assert not r.isError()
    r = client.read_holding_registers(20, count=5, device_id=1)                  # FC 3
    assert r.registers == [1, 2, 65535, 0, 1234]
    assert client.read_holding_registers(7, count=1, device_id=1).registers == [0xBEEF]

    r = client.read_input_registers(0, count=10, device_id=1)                    # FC 4
    assert r.registers == [1000 + i for i in range(10)]

    assert server.counters.requests == 9 == server.counters.responses
    assert server.counters.bad_frames == 0


def test_pymodbus_client_gets_illegal_data_address(served):
    slave, server, client = served
    r = client.read_holding_registers(95, count=10, device_id=1)  # 100..104 are not declared
    assert isinstance(r, PymodbusException)
    assert r.function_code == 0x83 and r.exception_code == 0x02
    r = client.write_register(500, 1, device_id=1)
    assert r.function_code == 0x86 and r.exception_code == 0x02
    assert slave.counters.exceptions == 2


def test_pymodbus_client_gets_illegal_function(served):
    slave, server, client = served
    r = client.diag_getclear_modbus_response(device_id=1)  # FC 8/0x15 (Modbus Plus): not implemented
    assert isinstance(r, PymodbusException)
    assert r.function_code == 0x88 and r.exception_code == 0x01


def test_pymodbus_client_gets_gateway_exception_for_unknown_unit(served):
    slave, server, client = served
    r = client.read_holding_registers(0, count=1, device_id=9)
    assert isinstance(r, PymodbusException)
    assert r.exception_code == 0x0B  # gateway target device failed to respond
    assert server.counters.unknown_unit == 1
    assert slave.counters.requests == 0


@pytest.mark.parametrize("unit", [0, 0xFF])
def test_pymodbus_client_reaches_the_device_itself_with_unit_0_or_FF(served, unit):
    # implementation guide 4.4.1.2: a device reached by its IP address answers 0xFF (recommended) and 0
    slave, server, client = served
    r = client.read_input_registers(0, count=2, device_id=unit)
    assert not r.isError() and r.registers == [1000, 1001]
    assert not client.write_register(7, 77, device_id=unit).isError()
    assert slave.bank.holding_registers[7] == 77
    assert server.counters.unknown_unit == 0 and slave.counters.broadcasts == 0


def test_several_units_behind_one_server():
    a, b = Slave(unit=1), Slave(unit=2)
    a.bank.holding_registers[0] = 111
    b.bank.holding_registers[0] = 222
    with TcpServer({1: a, 2: b}) as server:
        client = ModbusTcpClient(HOST, port=server.address[1], timeout=2, retries=0)
        assert client.connect()
        try:
            assert client.read_holding_registers(0, count=1, device_id=1).registers == [111]
            assert client.read_holding_registers(0, count=1, device_id=2).registers == [222]
            # a gateway: units 0 and 0xFF reach no slave of its own (no broadcast on TCP)
            for unit in (0, 0xFF):
                r = client.read_holding_registers(0, count=1, device_id=unit)
                assert isinstance(r, PymodbusException) and r.exception_code == 0x0B
        finally:
            client.close()
    assert server.counters.unknown_unit == 2


def test_any_unit_slave_answers_every_unit():
    slave = Slave(unit=None)
    slave.bank.holding_registers[3] = 33
    with TcpServer(slave) as server:
        client = ModbusTcpClient(HOST, port=server.address[1], timeout=2, retries=0)
        assert client.connect()
        try:
            for unit in (1, 17, 255):
                assert client.read_holding_registers(3, count=1, device_id=unit).registers == [33]
        finally:
            client.close()
    assert server.counters.unknown_unit == 0


# --- 2. our master -> pymodbus server ----------------------------------------------------------------
@pytest.fixture
def pymodbus_server():
    device = pymodbus_device(
        1, discrete=[True, False, False, True], inputs=[10, 20, 30, 40], holding=[7, 8, 9]
    )
    with PymodbusServer(device, framer="tcp") as server:
        yield server


def test_master_drives_pymodbus_server_all_eight_functions(pymodbus_server):
    with tcp_link(HOST, pymodbus_server.port) as link:
        assert link.mode == "tcp"
        master = Master(link, timeout=2.0, transaction_id=100)
        assert master.read_holding_registers(unit=1, address=0, count=3) == [7, 8, 9]     # FC 3
        master.write_single_register(unit=1, address=5, value=4321)                      # FC 6
        master.write_multiple_registers(unit=1, address=10, values=[1, 2, 3, 40000])     # FC 16
        assert master.read_holding_registers(unit=1, address=5, count=1) == [4321]
        assert master.read_holding_registers(unit=1, address=10, count=4) == [1, 2, 3, 40000]
        assert master.read_input_registers(unit=1, address=0, count=4) == [10, 20, 30, 40]  # FC 4
        assert master.read_discrete_inputs(unit=1, address=0, count=4) == [True, False, False, True]
        master.write_single_coil(unit=1, address=2, value=True)                           # FC 5
        master.write_multiple_coils(unit=1, address=8, values=[True, True, False, True])  # FC 15
        assert master.read_coils(unit=1, address=0, count=3) == [False, False, True]      # FC 1
        assert master.read_coils(unit=1, address=8, count=4) == [True, True, False, True]
        assert master.stats.valid_responses == 11
        assert master.stats.timeouts == 0 and master.stats.mismatches == 0
        assert master.transaction_id == 111  # one id per request, matched by the master


def test_master_sees_pymodbus_exceptions(pymodbus_server):
    with tcp_link(HOST, pymodbus_server.port) as link:
        master = Master(link, timeout=2.0)
        with pytest.raises(ModbusExceptionError) as info:
            master.read_holding_registers(unit=1, address=SIZE - 2, count=5)
        assert info.value.code == 0x02 and info.value.function == 3
        with pytest.raises(ModbusExceptionError) as info:
            master.write_single_register(unit=1, address=0, value=MAX_ALLOWED_VALUE + 1)
        assert info.value.code == 0x03 and info.value.function == 6
        with pytest.raises(ModbusExceptionError) as info:
            master.read_holding_registers(unit=42, address=0, count=1)
        # a unit the server lacks: pymodbus 3.16 answers 04 (device failure) with simulated devices,
        # 0B (gateway target failed to respond) with the older datastore; ours answers 0B
        assert info.value.code in (0x04, 0x0B)
        # the connection is still good after the exceptions
        assert master.read_holding_registers(unit=1, address=0, count=1) == [7]
        assert master.stats.exceptions == 3


def test_master_against_our_own_server_over_real_tcp():
    slave = _course_slave()
    with TcpServer(slave) as server, tcp_link(*server.address) as link:
        master = Master(link, timeout=2.0)
        master.write_multiple_registers(unit=1, address=0, values=list(range(50)))
        assert master.read_holding_registers(unit=1, address=0, count=50) == list(range(50))
        with pytest.raises(ModbusExceptionError) as info:
            master.read_input_registers(unit=1, address=99, count=2)
        assert info.value.code == 0x02


def test_tcp_link_refused_connection_teaches():
    with TcpServer(Slave()) as server:
        port = server.address[1]
    # the server is closed now: nothing listens on that port any more
    with pytest.raises(LinkError, match=r"connection refused - is a Modbus/TCP server listening there"):
        tcp_link(HOST, port, timeout=1.0)


@pytest.mark.parametrize(
    "args, kwargs, message",
    [
        ((5, 502), {}, "host to connect to must be a host name or an IP address written as text"),
        ((None, 502), {}, "host to connect to"),  # used to try localhost: "connection refused"
        (("", 502), {}, "host to connect to"),
        ((HOST, "502"), {}, "TCP port"),
        ((HOST, 0), {}, "TCP port"),
        ((HOST, True), {}, "TCP port"),
        ((HOST, 502), {"timeout": "x"}, "connect timeout must be a positive number of seconds"),
        ((HOST, 502), {"timeout": 0}, "connect timeout"),
        ((HOST, 502), {"timeout": None}, "connect timeout"),
    ],
)
def test_tcp_link_bad_settings_are_config_errors(args, kwargs, message):
    with pytest.raises(ConfigError, match=message):
        tcp_link(*args, **kwargs)


def test_tcp_link_reports_server_closing_then_reconnects():
    slave = Slave()
    with TcpServer(slave, idle_timeout=0.2) as server, tcp_link(*server.address) as link:
        master = Master(link, timeout=1.0)
        assert master.read_holding_registers(unit=1, address=0, count=1) == [0]
        # stay silent past the idle timeout: the server hangs up
        with pytest.raises(LinkError, match="closed the connection"):
            link.receive(2.0)
        assert master.read_holding_registers(unit=1, address=0, count=1) == [0]
        assert link.reconnects == 1
        assert server.counters.idle_closed == 1
