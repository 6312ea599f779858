"""TcpGateway: pymodbus's TCP client reads and writes two slaves on a loopback serial bus through it,
gets 0x0B for an absent unit after the gateway's timeout, and 10 clients at once get their own replies."""

import threading

from pymodbus.client import ModbusTcpClient

import modbus_edu as mb

HOST = "127.0.0.1"


def _bus():
    a, b = mb.Slave(unit=1, bank=mb.DataBank()), mb.Slave(unit=2, bank=mb.DataBank())
    a.bank.holding_registers[0:3] = [11, 12, 13]
    b.bank.holding_registers[0:3] = [21, 22, 23]
    return mb.loopback_serial([a, b], baudrate=9600), a, b


def test_pymodbus_client_through_gateway():
    bus, a, b = _bus()
    with mb.TcpGateway(bus, timeout=0.2) as gw:
        client = ModbusTcpClient(HOST, port=gw.address[1], timeout=5, retries=0)
        assert client.connect()
        try:
            assert client.read_holding_registers(0, count=3, device_id=1).registers == [11, 12, 13]
            assert client.read_holding_registers(0, count=3, device_id=2).registers == [21, 22, 23]
            assert not client.write_register(7, 0xBEEF, device_id=2).isError()
            assert b.bank.holding_registers[7] == 0xBEEF
            start = bus.clock.now
            r = client.read_holding_registers(0, count=1, device_id=9)
            assert r.isError() and r.exception_code == 0x0B
            # the absent unit costs the request's 8 characters on the line, then the gateway's timeout
            # (it starts when the request has left, as a serial master's response timeout does)
            assert abs((bus.clock.now - start) - (8 * 10 / 9600 + 0.2)) < 1e-9
            r = client.read_holding_registers(0, count=1, device_id=0)
            assert r.isError() and r.exception_code == 0x0A
            r = client.read_holding_registers(65535, count=2, device_id=1)  # the slave's own exception 02
            assert r.isError() and r.exception_code == 0x02
        finally:
            client.close()
    assert gw.counters["no_response"] == 1 and gw.counters["path_unavailable"] == 1


def test_round_trip_on_the_virtual_wire_matches_the_arithmetic():
    bus, _, _ = _bus()
    with mb.TcpGateway(bus) as gw, mb.tcp_link(*gw.address) as tcp:
        master = mb.Master(tcp, timeout=5)
        master.read_holding_registers(unit=1, address=0, count=1)
        t0 = bus.clock.now
        master.read_holding_registers(unit=1, address=0, count=1)
        # (8 + 3.5 + 7 + 3.5) characters of 10 bits at 9600 baud = 22.92 ms
        assert abs((bus.clock.now - t0) - 22 * 10 / 9600) < 1e-6


def test_ten_clients_get_their_own_replies():
    bus, a, b = _bus()
    for i in range(10):
        a.bank.holding_registers[100 + i] = 1000 + i
        b.bank.holding_registers[100 + i] = 2000 + i
    errors = []
    with mb.TcpGateway(bus, timeout=0.2) as gw:

        def client(i):
            try:
                with mb.tcp_link(*gw.address) as tcp:
                    m = mb.Master(tcp, timeout=10, transaction_id=i * 1000)
                    for k in range(20):
                        unit = 1 + (i + k) % 2
                        got = m.read_holding_registers(unit=unit, address=100 + i, count=1)
                        if got != [unit * 1000 + i]:
                            errors.append((i, k, unit, got))
            except Exception as exc:  # pragma: no cover - reported below
                errors.append((i, repr(exc)))

        threads = [threading.Thread(target=client, args=(i,)) for i in range(10)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(timeout=60)
    assert errors == []
    assert gw.counters["forwarded"] == 200
