"""RTU and ASCII over TCP (a serial device server's socket): pymodbus's client with its RTU/ASCII framer
reads our TcpServer(framing=...), and our tcp_link(framing=...) reads pymodbus's server of the same kind."""

import pytest
from conftest_io import HOST, PymodbusServer, pymodbus_device
from pymodbus.client import ModbusTcpClient
from pymodbus.framer import FramerType

import modbus_edu as mb


def _slaves():
    a, b = mb.Slave(unit=1, bank=mb.DataBank()), mb.Slave(unit=2, bank=mb.DataBank())
    a.bank.holding_registers[0:3] = [11, 12, 13]
    b.bank.holding_registers[0:3] = [21, 22, 23]
    return [a, b]


@pytest.mark.parametrize("framing, framer", [("rtu", FramerType.RTU), ("ascii", FramerType.ASCII)])
def test_pymodbus_client_reads_our_serial_over_tcp_server(framing, framer):
    slaves = _slaves()
    with mb.TcpServer(slaves, framing=framing) as server:
        client = ModbusTcpClient(HOST, port=server.address[1], framer=framer, timeout=2, retries=0)
        assert client.connect()
        try:
            assert client.read_holding_registers(0, count=3, device_id=1).registers == [11, 12, 13]
            assert client.read_holding_registers(0, count=3, device_id=2).registers == [21, 22, 23]
            assert not client.write_register(9, 4321, device_id=2).isError()
        finally:
            client.close()
    assert slaves[1].bank.holding_registers[9] == 4321


@pytest.mark.parametrize("framing", ["rtu", "ascii"])
def test_our_link_reads_our_server_and_pymodbus_server(framing):
    with (
        mb.TcpServer(_slaves(), framing=framing) as server,
        mb.tcp_link(*server.address, framing=framing) as link,
    ):
        assert link.mode == framing
        m = mb.Master(link, timeout=2)
        assert m.read_holding_registers(unit=2, address=0, count=3) == [21, 22, 23]
        # a unit nobody serves: silence, as on a serial line
        with pytest.raises(mb.ModbusTimeoutError):
            mb.Master(link, timeout=0.2).read_holding_registers(unit=9, address=0, count=1)
    device = pymodbus_device(1, holding=[7, 8, 9])
    with PymodbusServer(device, framer=framing) as server:
        with mb.tcp_link(HOST, server.port, framing=framing) as link:
            assert mb.Master(link, timeout=2).read_holding_registers(unit=1, address=0, count=3) == [7, 8, 9]


def test_bad_framing_is_a_config_error():
    with pytest.raises(mb.ConfigError, match="framing must be one of tcp, rtu, ascii"):
        mb.TcpServer(_slaves(), framing="udp")
