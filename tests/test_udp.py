"""Modbus/UDP: pymodbus's UDP client reads our UdpServer; our udp_link reads it too; a lost datagram
is made good by the master's retries; a datagram that is not one MBAP frame is dropped."""

import socket

import pytest
from pymodbus.client import ModbusUdpClient

import modbus_edu as mb

HOST = "127.0.0.1"


def _slaves():
    a, b = mb.Slave(unit=1, bank=mb.DataBank()), mb.Slave(unit=2, bank=mb.DataBank())
    a.bank.holding_registers[0:3] = [11, 12, 13]
    b.bank.holding_registers[0:3] = [21, 22, 23]
    return [a, b]


def test_pymodbus_udp_client_reads_and_writes_our_server():
    with mb.UdpServer(_slaves()) as server:
        client = ModbusUdpClient(HOST, port=server.address[1], timeout=2, retries=0)
        assert client.connect()
        try:
            assert client.read_holding_registers(0, count=3, device_id=1).registers == [11, 12, 13]
            assert client.read_holding_registers(0, count=3, device_id=2).registers == [21, 22, 23]
            assert not client.write_register(5, 0xBEEF, device_id=2).isError()
            r = client.read_holding_registers(0, count=1, device_id=9)
            assert r.isError() and r.exception_code == 0x0B
        finally:
            client.close()
        assert server.requests == 4


def test_udp_link_reads_our_server_and_retries_a_lost_datagram():
    slaves = _slaves()
    with mb.UdpServer(slaves) as server:
        with mb.udp_link(*server.address) as link:
            master = mb.Master(link, timeout=0.3, retries=2)
            assert master.read_holding_registers(unit=2, address=0, count=3) == [21, 22, 23]
            # lose the next request: the server's slave drops it once
            original = slaves[0].handle
            calls = []

            def lossy(frame, mode):
                calls.append(frame)
                return None if len(calls) == 1 else original(frame, mode)

            slaves[0].handle = lossy
            assert master.read_holding_registers(unit=1, address=0, count=3) == [11, 12, 13]
            assert len(calls) == 2 and master.stats.retries == 1


def test_a_datagram_that_is_not_one_frame_is_dropped():
    with mb.UdpServer(_slaves()) as server:
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.settimeout(0.3)
        try:
            s.sendto(b"\x00\x01\x00\x00\x00\x06\x01\x03\x00\x00\x00\x01junk", server.address)
            with pytest.raises(TimeoutError):
                s.recv(300)
        finally:
            s.close()
        assert server.bad_datagrams == 1


def test_bad_port_is_a_config_error():
    with pytest.raises(mb.ModbusError, match="UDP port"):
        mb.udp_link(HOST, 0)


def test_udp_link_reads_pymodbus_udp_server():
    import asyncio

    from conftest_io import PymodbusServer, pymodbus_device
    from pymodbus.server import ModbusUdpServer

    class PymodbusUdpServer(PymodbusServer):
        def _run(self):
            async def main():
                self._server = ModbusUdpServer(self.devices, address=(HOST, 0))
                await self._server.serve_forever(background=True)
                self.port = self._server.transport.get_extra_info("sockname")[1]
                self._loop = asyncio.get_running_loop()
                self._ready.set()
                await self._server.serving

            try:
                asyncio.run(main())
            except BaseException as exc:  # noqa: BLE001 - reported to the test thread
                self._error = exc
                self._ready.set()

    with PymodbusUdpServer(pymodbus_device(1, holding=[7, 8, 9])) as server:
        with mb.udp_link(HOST, server.port) as link:
            master = mb.Master(link, timeout=2, retries=1)
            assert master.read_holding_registers(unit=1, address=0, count=3) == [7, 8, 9]
            master.write_single_register(unit=1, address=1, value=88)
            assert master.read_holding_registers(unit=1, address=0, count=3) == [7, 88, 9]
