"""The virtual Modbus/TCP link routes unit ids as the real TcpServer does (implementation guide 4.4.1.2)."""

from __future__ import annotations

import pytest

from modbus_edu.datamodel import DataBank
from modbus_edu.errors import ModbusExceptionError, ModbusTimeoutError
from modbus_edu.links import loopback_tcp
from modbus_edu.master import Master
from modbus_edu.slave import Slave


def _slave(unit: int, value: int) -> Slave:
    bank = DataBank()
    bank.holding_registers[0] = value
    return Slave(unit=unit, bank=bank)


@pytest.mark.parametrize("unit", [1, 0, 0xFF])
def test_one_slave_is_reached_by_its_unit_and_by_0_and_0xff(unit):
    master = Master(loopback_tcp(_slave(1, 1234)))
    assert master.read_holding_registers(unit=unit, address=0, count=1) == [1234]
    assert master.log[-1].data[6] == unit  # the response echoes the request's unit id


def test_a_write_to_unit_0_is_answered_on_tcp():
    slave = _slave(1, 0)
    master = Master(loopback_tcp(slave))
    master.write_single_register(unit=0, address=0, value=7)  # no broadcast on TCP: it waits, and gets
    assert slave.bank.holding_registers[0] == 7 and master.stats.valid_responses == 1


def test_a_gateway_routes_by_unit_and_answers_0x0b_for_nobody():
    master = Master(loopback_tcp([_slave(1, 11), _slave(2, 22)]))
    assert master.read_holding_registers(unit=2, address=0, count=1) == [22]
    for unit in (0, 5, 0xFF):
        with pytest.raises(ModbusExceptionError) as info:
            master.read_holding_registers(unit=unit, address=0, count=1)
        assert info.value.code == 0x0B


def test_with_no_slave_attached_nobody_answers():
    link = loopback_tcp([])
    with pytest.raises(ModbusTimeoutError):
        Master(link, timeout=0.5).read_holding_registers(unit=1, address=0, count=1)
