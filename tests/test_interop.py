"""modbus_edu.interop: a real pymodbus server in a thread, read by the course's Master over a real socket."""

from __future__ import annotations

import socket

import pytest
from pymodbus.simulator import DataType, SimData, SimDevice

import modbus_edu as mb
from modbus_edu.interop import pymodbus_server


def _device() -> SimDevice:
    return SimDevice(id=1, simdata=[SimData(0, values=[100, 200, 300], datatype=DataType.REGISTERS)])


def test_the_master_reads_and_writes_a_pymodbus_server_and_it_stops_cleanly():
    with pymodbus_server(_device()) as (host, port):
        assert host == "127.0.0.1" and port > 0
        with mb.tcp_link(host, port) as link:
            master = mb.Master(link, timeout=2.0)
            assert master.read_holding_registers(unit=1, address=0, count=3) == [100, 200, 300]
            master.write_single_register(unit=1, address=1, value=7)
            assert master.read_holding_registers(unit=1, address=0, count=2) == [100, 7]
    with pytest.raises(OSError), socket.create_connection((host, port), timeout=1):
        pass


def test_rtu_framing_over_tcp_is_served_too():
    request = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
    with pymodbus_server(_device(), framer="rtu") as (host, port):
        with socket.create_connection((host, port), timeout=2) as connection:
            connection.sendall(request)
            answer = connection.recv(256)
    assert list(mb.RtuFrame.decode(answer, "response").pdu.registers) == [100]


def test_bad_framer_and_busy_port_are_link_errors():
    with pytest.raises(mb.LinkError, match="not one of pymodbus's framers"):
        with pymodbus_server(_device(), framer="x"):
            pass
    with pymodbus_server(_device()) as (host, port):
        with pytest.raises(mb.LinkError, match="did not start"), pymodbus_server(_device(), port=port):
            pass
