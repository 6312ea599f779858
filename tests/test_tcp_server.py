"""TcpServer: life cycle, settings, routing by unit, byte-stream framing, counters (127.0.0.1 only)."""

from __future__ import annotations

import logging
import socket
import threading

import pytest
from conftest_io import HOST, raw_client, recv_frame

from modbus_edu.errors import ConfigError, LinkError, ModbusExceptionError
from modbus_edu.framing import TcpFrame
from modbus_edu.links.tcp import TcpServer, is_loopback_host, normalize_slaves, route_unit, tcp_link
from modbus_edu.master import Master
from modbus_edu.pdu import (
    ExceptionResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    WriteSingleRegisterRequest,
)
from modbus_edu.slave import Slave


def request(tid: int, unit: int, address: int = 0, count: int = 1) -> bytes:
    pdu = ReadHoldingRegistersRequest(address=address, count=count)
    return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()


def response(data: bytes) -> TcpFrame:
    return TcpFrame.decode(data, role="response")


# --- life cycle ----------------------------------------------------------------------------------------
def test_context_manager_binds_an_ephemeral_loopback_port_and_closes():
    with TcpServer(Slave()) as server:
        host, port = server.address
        assert host == HOST and port > 0
        assert server.running
        assert f"{HOST}:{port}" in repr(server) and "running" in repr(server)
        with raw_client(port) as sock:
            sock.sendall(request(1, 1))
            assert response(recv_frame(sock)).pdu == ReadHoldingRegistersResponse(registers=(0,))
    assert not server.running and "closed" in repr(server)
    with pytest.raises(ConnectionRefusedError):
        socket.create_connection((HOST, port), timeout=1).close()
    server.close()  # a second close is harmless
    with pytest.raises(LinkError, match="closed"):
        server.start()


def test_start_and_close_without_context_manager():
    server = TcpServer(Slave()).start()
    try:
        assert server.start() is server  # starting twice is harmless
        assert server.running
    finally:
        server.close()
    assert not server.running


def test_serve_forever_in_a_thread_stops_on_close():
    server = TcpServer(Slave())
    thread = threading.Thread(target=server.serve_forever)
    thread.start()
    try:
        for _ in range(200):  # wait until bound
            if server.address is not None:
                break
            threading.Event().wait(0.01)
        with raw_client(server.address[1]) as sock:
            sock.sendall(request(9, 1))
            assert response(recv_frame(sock)).transaction_id == 9
    finally:
        server.close()
        thread.join(5)
    assert not thread.is_alive()


def test_binding_beyond_loopback_warns_that_modbus_tcp_has_no_authentication(caplog, monkeypatch):
    # 192.0.2.1 is TEST-NET-1: not assigned to this machine, so the bind fails - and a server that never
    # listened must not say it listens.
    with caplog.at_level(logging.WARNING, logger="modbus_edu.tcp"):
        with pytest.raises(LinkError, match="cannot listen on 192.0.2.1"):
            TcpServer(Slave(), host="192.0.2.1").start()
    assert "no authentication" not in caplog.text
    # A server that does listen beyond loopback says so once it listens. (It really binds 127.0.0.1 here:
    # the test only makes the server believe the address is reachable from other computers.)
    import modbus_edu.links.tcp_listener as tcp_module

    monkeypatch.setattr(tcp_module, "is_loopback_host", lambda host: False)
    with caplog.at_level(logging.WARNING, logger="modbus_edu.tcp"), TcpServer(Slave(), host="127.0.0.1"):
        pass
    assert "no authentication" in caplog.text


def test_loopback_binding_does_not_warn(caplog):
    with caplog.at_level(logging.WARNING, logger="modbus_edu.tcp"):
        with TcpServer(Slave(), host="localhost"):
            pass
    assert "no authentication" not in caplog.text


def test_is_loopback_host():
    assert is_loopback_host("127.0.0.1") and is_loopback_host("127.1.2.3")
    assert is_loopback_host("::1") and is_loopback_host("localhost")
    assert not is_loopback_host("0.0.0.0") and not is_loopback_host("192.168.1.10")
    assert not is_loopback_host("plc.example.com")


def test_port_already_in_use_is_a_teaching_link_error():
    with TcpServer(Slave()) as first:
        with pytest.raises(LinkError, match="another program already listens there"):
            TcpServer(Slave(), port=first.address[1]).start()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"port": -1}, "TCP port"),
        ({"port": 70000}, "TCP port"),
        ({"port": "502"}, "TCP port"),
        ({"port": 502.0}, "TCP port"),
        ({"port": True}, "TCP port"),
        ({"port": None}, "TCP port"),
        ({"host": 5}, "host to listen on must be a host name or an IP address written as text"),
        ({"host": None}, "host to listen on"),
        ({"host": ""}, "host to listen on"),
        ({"host": ("127.0.0.1", 502)}, "host to listen on"),
        ({"idle_timeout": 0}, "idle_timeout"),
        ({"idle_timeout": -1.5}, "idle_timeout"),
        ({"idle_timeout": "x"}, "idle_timeout must be a positive number of seconds"),
        ({"idle_timeout": float("nan")}, "idle_timeout"),
        ({"idle_timeout": True}, "idle_timeout"),
        ({"max_connections": 0}, "max_connections"),
        ({"max_connections": 2.5}, "max_connections"),
        ({"max_connections": "8"}, "max_connections"),
        ({"max_connections": None}, "max_connections"),
        ({"logger": "modbus"}, "logger"),
    ],
)
def test_bad_settings_are_config_errors(kwargs, message):
    # never an AttributeError (host=5 used to fail in .lower()) or a TypeError ("x" <= 0)
    slave = Slave()
    with pytest.raises(ConfigError, match=message):
        TcpServer(slave, **kwargs)
    assert slave.clock is None  # a refused server leaves its slaves untouched


def test_good_settings_are_kept():
    server = TcpServer(Slave(), host="localhost", port=0, idle_timeout=2, max_connections=1)
    assert (server.host, server.idle_timeout, server.max_connections) == ("localhost", 2.0, 1)
    assert TcpServer(Slave(), idle_timeout=None).idle_timeout is None


# --- which slaves ----------------------------------------------------------------------------------------
def test_normalize_slaves_accepts_one_a_list_or_a_mapping():
    a, b = Slave(unit=1), Slave(unit=2)
    assert normalize_slaves(a) == {1: a}
    assert normalize_slaves([a, b]) == {1: a, 2: b}
    assert normalize_slaves({2: b}) == {2: b}
    anyone = Slave(unit=None)
    assert normalize_slaves([a, anyone]) == {1: a, None: anyone}


@pytest.mark.parametrize(
    "slaves, message",
    [
        (None, "at least one Slave"),
        ([], "at least one Slave"),
        ([Slave(unit=1), Slave(unit=1)], "two slaves answer to unit 1"),
        ({3: Slave(unit=1)}, "registered under unit 3 answers to unit 1"),
        ("not a slave", "expected a Slave"),
    ],
)
def test_normalize_slaves_rejects_what_cannot_be_served(slaves, message):
    with pytest.raises(ConfigError, match=message):
        TcpServer(slaves)


def test_requests_are_routed_by_unit_and_unknown_units_get_exception_0B():
    a, b = Slave(unit=1), Slave(unit=2)
    a.bank.holding_registers[0] = 1
    b.bank.holding_registers[0] = 2
    with TcpServer([a, b]) as server, raw_client(server.address[1]) as sock:
        for tid, unit in ((10, 1), (11, 2)):
            sock.sendall(request(tid, unit))
            frame = response(recv_frame(sock))
            assert (frame.transaction_id, frame.unit, frame.pdu.registers) == (tid, unit, (unit,))
        sock.sendall(request(0xBEEF, 99))
        frame = response(recv_frame(sock))
        assert frame.transaction_id == 0xBEEF and frame.unit == 99
        assert frame.pdu == ExceptionResponse(function=3, code=0x0B)
    assert server.counters.unknown_unit == 1
    assert a.counters.requests == 1 and b.counters.requests == 1


# --- the unit id on Modbus/TCP (implementation guide, section 4.4.1.2) ----------------------------------
def test_route_unit_one_slave_is_the_device_itself():
    one = normalize_slaves(Slave(unit=1))
    assert route_unit(one, 0) == (one[1], True)
    assert route_unit(one, 0xFF) == (one[1], True)
    assert route_unit(one, 1) == (one[1], False)
    assert route_unit(one, 2) == (None, False)
    anyone = normalize_slaves(Slave(unit=None))
    assert route_unit(anyone, 0) == (anyone[None], True) and route_unit(anyone, 9) == (anyone[None], False)


def test_route_unit_several_slaves_is_a_gateway():
    a, b = Slave(unit=1), Slave(unit=2)
    gateway = normalize_slaves([a, b])
    assert route_unit(gateway, 2) == (b, False)
    assert route_unit(gateway, 0) == (None, False)  # no broadcast on TCP, and no single device
    assert route_unit(gateway, 0xFF) == (None, False)  # 0xFF is no serial slave's address
    assert route_unit(gateway, 3) == (None, False)
    anyone = Slave(unit=None)
    with_any = normalize_slaves([a, anyone])
    assert route_unit(with_any, 0xFF) == (anyone, False) and route_unit(with_any, 0) == (None, False)
    owner = Slave(unit=255)
    assert route_unit(normalize_slaves([a, owner]), 0xFF) == (owner, False)


@pytest.mark.parametrize("unit", [0, 0xFF])
def test_one_slave_answers_units_0_and_FF_as_the_device_itself(unit):
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 1234
    with TcpServer(slave) as server, raw_client(server.address[1]) as sock:
        # a write to unit 0 is not a broadcast on TCP: carried out and answered
        write = WriteSingleRegisterRequest(address=5, value=55)
        sock.sendall(TcpFrame(transaction_id=1, unit=unit, pdu=write).encode())
        frame = response(recv_frame(sock))
        assert (frame.transaction_id, frame.unit) == (1, unit)  # the request's unit id, echoed
        assert frame.pdu.value == 55
        sock.sendall(request(2, unit, address=0))
        frame = response(recv_frame(sock))
        assert (frame.transaction_id, frame.unit, frame.pdu.registers) == (2, unit, (1234,))
        sock.sendall(request(3, 7))  # any other unit still finds nobody
        assert response(recv_frame(sock)).pdu == ExceptionResponse(function=3, code=0x0B)
    assert slave.bank.holding_registers[5] == 55
    assert slave.counters.requests == slave.counters.responses == 2
    assert slave.counters.broadcasts == 0
    assert server.counters.requests == server.counters.responses == 3
    assert server.counters.unknown_unit == 1


def test_one_any_unit_slave_answers_0_and_FF_too():
    slave = Slave(unit=None)
    with TcpServer(slave) as server, raw_client(server.address[1]) as sock:
        for tid, unit in enumerate((0, 0xFF, 1, 200)):
            sock.sendall(request(tid, unit))
            frame = response(recv_frame(sock))
            assert (frame.transaction_id, frame.unit, frame.pdu.registers) == (tid, unit, (0,))
    assert server.counters.unknown_unit == 0


@pytest.mark.parametrize("unit", [0, 0xFF])
def test_several_slaves_refuse_units_0_and_FF_with_exception_0B(unit):
    a, b = Slave(unit=1), Slave(unit=2)
    with TcpServer([a, b]) as server, raw_client(server.address[1]) as sock:
        write = WriteSingleRegisterRequest(address=5, value=55)
        sock.sendall(TcpFrame(transaction_id=4, unit=unit, pdu=write).encode())
        frame = response(recv_frame(sock))
        assert (frame.transaction_id, frame.unit) == (4, unit)
        assert frame.pdu == ExceptionResponse(function=6, code=0x0B)
    assert a.bank.holding_registers[5] == b.bank.holding_registers[5] == 0  # nobody acted on it
    assert a.counters.requests == b.counters.requests == a.counters.broadcasts == 0
    assert server.counters.unknown_unit == 1


def test_master_on_tcp_waits_for_the_answer_to_unit_0():
    slave = Slave(unit=1)
    with TcpServer(slave) as server, tcp_link(*server.address) as link:
        master = Master(link, timeout=2.0)
        assert master.write_single_register(unit=0, address=2, value=22) is None
        assert master.read_holding_registers(unit=0, address=2, count=1) == [22]
        assert master.read_holding_registers(unit=0xFF, address=2, count=1) == [22]
        assert master.stats.valid_responses == 3 and master.stats.broadcasts == 0
        assert master.log[0].dest == "unit 0"
    with TcpServer([Slave(unit=1), Slave(unit=2)]) as gateway, tcp_link(*gateway.address) as link:
        master = Master(link, timeout=2.0)
        with pytest.raises(ModbusExceptionError) as info:
            master.write_single_register(unit=0, address=2, value=22)
        assert info.value.code == 0x0B and master.stats.broadcasts == 0


# --- the byte stream --------------------------------------------------------------------------------------
def test_frames_split_over_many_segments_and_glued_together():
    slave = Slave()
    slave.bank.holding_registers.write(0, [10, 11, 12])
    with TcpServer(slave) as server, raw_client(server.address[1]) as sock:
        one = request(1, 1, address=0)
        for piece in (one[:3], one[3:7], one[7:]):
            sock.sendall(piece)
            threading.Event().wait(0.01)
        assert response(recv_frame(sock)).pdu.registers == (10,)
        # three requests in one segment: three answers, in order (pipelining)
        sock.sendall(request(2, 1, 1) + request(3, 1, 2) + request(4, 1, 0, 3))
        answers = [response(recv_frame(sock)) for _ in range(3)]
        assert [a.transaction_id for a in answers] == [2, 3, 4]
        assert [a.pdu.registers for a in answers] == [(11,), (12,), (10, 11, 12)]


def test_bad_pdu_inside_a_good_mbap_gets_an_exception_response_not_a_hang_up():
    with TcpServer(Slave()) as server, raw_client(server.address[1]) as sock:
        # FC 3 with quantity 0: illegal data value (03)
        sock.sendall(bytes.fromhex("0007 0000 0006 01 03 0000 0000"))
        frame = response(recv_frame(sock))
        assert frame.transaction_id == 7 and frame.pdu == ExceptionResponse(function=3, code=3)
        # function 0x2C: not implemented, illegal function (01)
        sock.sendall(bytes.fromhex("0008 0000 0004 01 2C 0E 01"))
        assert response(recv_frame(sock)).pdu == ExceptionResponse(function=0x2C, code=1)
        # and the connection still serves
        sock.sendall(request(9, 1))
        assert response(recv_frame(sock)).transaction_id == 9
    assert server.counters.bad_frames == 0


def test_a_failing_hook_is_answered_with_exception_04():
    def broken(slave, kind, address, count):
        raise RuntimeError("sensor unplugged")

    with TcpServer(Slave(on_read=broken)) as server, raw_client(server.address[1]) as sock:
        sock.sendall(request(1, 1))
        assert response(recv_frame(sock)).pdu == ExceptionResponse(function=3, code=4)


def test_counters_and_lock():
    slave = Slave()
    with TcpServer(slave) as server:
        with server.lock:  # a notebook updating several registers at once
            slave.bank.holding_registers.write(0, [1, 2])
        with raw_client(server.address[1]) as sock:
            for tid in range(5):
                sock.sendall(request(tid, 1, 0, 2))
                assert response(recv_frame(sock)).pdu.registers == (1, 2)
        counters = server.counters.as_dict()
    assert counters["connections"] == 1
    assert counters["requests"] == counters["responses"] == 5
    assert counters["bad_frames"] == counters["evicted"] == counters["idle_closed"] == 0
    assert slave.counters.requests == 5
    assert slave.clock is not None  # time stamps for the slave's traffic log
