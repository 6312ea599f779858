"""Modbus/UDP: pymodbus's UDP client reads our UdpServer; our udp_link reads it too; a lost datagram
is made good by the master's retries; a datagram that is not one MBAP frame is dropped."""

import importlib.util
import socket
import time
from pathlib import Path

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


def _bench_udp_flood():
    """bench/udp_flood.py, whose scenario these tests run smaller."""
    path = Path(__file__).resolve().parents[1] / "bench" / "udp_flood.py"
    spec = importlib.util.spec_from_file_location("bench_udp_flood", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("flood", ["junk", "valid requests"])
def test_a_flooding_source_does_not_starve_a_master(flood):
    """Another port sends 100,000 datagrams a second for 2 s (junk, or valid FC 3 requests); a master
    with timeout 0.3 s and 2 retries reading every 0.05 s gets at least 95% of its reads within 1 s."""
    bench = _bench_udp_flood()
    payload = bench.JUNK if flood == "junk" else bench.valid_request()
    r = bench.run(payload, datagrams=200_000, seconds=2.0, every=0.05)
    assert r["answered"] >= 0.95 * r["made"], r
    assert r["made"] >= 5, r


@pytest.mark.parametrize("flood", ["junk", "valid requests"])
def test_a_backlog_from_one_source_waits_its_turn(flood):
    """300 datagrams from one port wait in the socket, then one request from another: the server keeps
    at most QUEUE_PER_SOURCE requests of a source (the rest counted as dropped), drops junk at once, and
    serves the sources in turn, so the second source is answered after one request of the first."""
    from modbus_edu.links import udp

    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers[0:2] = [5, 6]
    served = []  # the transaction ids in the order the slave sees them
    handle = slave.handle
    slave.handle = lambda frame, mode: served.append(int.from_bytes(frame[:2], "big")) or handle(frame, mode)
    server = mb.UdpServer(slave)  # bound, not yet serving: the datagrams wait in its socket
    flooder = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    master = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    master.settimeout(2.0)
    junk = flood == "junk"
    try:
        for tid in range(300):
            pdu = mb.ReadHoldingRegistersRequest(address=0, count=1)
            flooder.sendto(bytes(12) if junk else mb.TcpFrame(transaction_id=tid, unit=1, pdu=pdu).encode(),
                           server.address)
        ours = mb.ReadHoldingRegistersRequest(address=0, count=2)
        master.sendto(mb.TcpFrame(transaction_id=999, unit=1, pdu=ours).encode(), server.address)
        with server:
            reply = mb.TcpFrame.decode(master.recv(300), role="response")
            deadline = time.monotonic() + 2.0
            while server.requests < (1 if junk else 1 + udp.QUEUE_PER_SOURCE) and time.monotonic() < deadline:
                time.sleep(0.01)
    finally:
        flooder.close()
        master.close()
    assert reply.transaction_id == 999 and list(reply.pdu.registers) == [5, 6]
    if junk:
        assert (server.bad_datagrams, server.requests, server.dropped_datagrams) == (300, 1, 0)
    else:
        assert served == [296, 999, 297, 298, 299]  # the flood's newest four, ours after its first
        assert server.requests == 1 + udp.QUEUE_PER_SOURCE
        assert server.dropped_datagrams == 300 - udp.QUEUE_PER_SOURCE
