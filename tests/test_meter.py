"""The power meter of source 003: Table 5's map, Table 6's two trials, read through a Master."""

from __future__ import annotations

import pytest

from modbus_edu.devices.meter import (
    METER_BY_NAME,
    METER_MAP,
    TRIAL_ENERGY_KWH,
    TRIALS,
    PowerMeter,
    meter_blocks,
    meter_table,
    read_meter,
)
from modbus_edu.errors import ConfigError, ModbusExceptionError
from modbus_edu.links.loopback import loopback_serial
from modbus_edu.master import Master
from modbus_edu.values import decode_value

# 003, Table 5, as printed (hexadecimal register pairs)
PAPER_TABLE_5 = {
    "VL1": (0x00, 0x01), "VL2": (0x0A, 0x0B), "VL3": (0x14, 0x15),
    "AL1": (0x02, 0x03), "AL2": (0x0C, 0x0D), "AL3": (0x16, 0x17),
    "THD_VL1": (0x30, 0x31), "THD_VL2": (0x32, 0x33), "THD_VL3": (0x34, 0x35),
    "THD_AL1": (0x36, 0x37), "THD_AL2": (0x38, 0x39), "THD_AL3": (0x3A, 0x3B),
    "kWh": (0x3C, 0x3D),
    "PF1": (0x08, 0x09), "PF2": (0x12, 0x13), "PF3": (0x1C, 0x1D),
}

# 003, Table 6, as printed: (trial 1, trial 2)
PAPER_TABLE_6 = {
    "VL1": (403.6, 412.6), "VL2": (399.9, 410.5), "VL3": (399.3, 411.7),
    "AL1": (304.9, 288.9), "AL2": (319.6, 300.1), "AL3": (302.0, 284.1),
    "THD_VL1": (1.6, 1.8), "THD_VL2": (1.0, 1.0), "THD_VL3": (0.7, 1.0),
    "THD_AL1": (4.2, 4.3), "THD_AL2": (4.7, 4.1), "THD_AL3": (4.4, 4.4),
    "PF1": (0.66, 0.60), "PF2": (0.70, 0.64), "PF3": (0.72, 0.68),
}


def _wire(meter: PowerMeter) -> tuple[Master, object]:
    link = loopback_serial(meter, baudrate=PowerMeter.BAUDRATE, parity=PowerMeter.PARITY,
                           stopbits=PowerMeter.STOPBITS)
    return Master(link, timeout=0.5), link


def test_map_has_the_papers_addresses_exactly():
    assert {e.name: tuple(e.addresses) for e in METER_MAP} == PAPER_TABLE_5
    assert [e.name for e in METER_MAP][:3] == ["VL1", "VL2", "VL3"]
    units = {e.name: (e.raw_unit, e.scale, e.unit) for e in METER_MAP}
    assert units["VL1"] == ("V x 10", 10, "V")
    assert units["AL1"] == ("mA", 1000, "A")
    assert units["THD_AL3"] == ("% x 10", 10, "%")
    assert units["PF2"] == ("P.F. x 100", 100, "")
    assert units["kWh"] == ("kWh", 1, "kWh")
    assert METER_BY_NAME["VL1"].reference == "40001"
    assert METER_BY_NAME["kWh"].reference == "40061"


def test_serial_settings_of_the_paper():
    assert (PowerMeter.UNIT, PowerMeter.BAUDRATE, PowerMeter.DATABITS, PowerMeter.PARITY,
            PowerMeter.STOPBITS) == (1, 19200, 8, "N", 1)
    assert PowerMeter().unit == 1


def test_blocks_follow_the_gaps_of_the_map():
    assert [(a, c) for a, c, _ in meter_blocks()] == [(0x00, 4), (0x08, 6), (0x12, 6), (0x1C, 2), (0x30, 14)]


@pytest.mark.parametrize("trial", [1, 2])
def test_table_6_read_through_a_master_at_19200_8n1(trial):
    meter = PowerMeter(unit=1, trial=trial)
    master, link = _wire(meter)
    assert link.timing.baudrate == 19200 and link.timing.bits_per_char == 10
    values = read_meter(master, unit=1)
    for name, printed in PAPER_TABLE_6.items():
        assert values[name] == printed[trial - 1], name
    assert values["kWh"] == TRIAL_ENERGY_KWH[trial]
    assert set(values) == set(PAPER_TABLE_5)
    assert master.stats.valid_responses == 5 and master.stats.timeouts == 0
    # the first block (4 registers) on the wire at 19200 8N1: request 8 chars, t3.5, response 13 chars, t3.5
    assert master.stats.latencies[0] == pytest.approx((8 + 3.5 + 13 + 3.5) * 10 / 19200)


def test_registers_carry_uint32_high_word_first():
    meter = PowerMeter(trial=1)
    master, _ = _wire(meter)
    regs = master.read_holding_registers(unit=1, address=0, count=4)
    assert regs == [0x0000, 4036, 0x0004, 0xA704]  # 403.6 V x 10; 304 900 mA = 0x0004A704
    assert decode_value(regs[2:4], "uint32", "ABCD") == 304_900
    assert master.read_holding_registers(unit=1, address=0x08, count=2) == [0, 66]  # PF1 0.66 x 100
    assert master.read_holding_registers(unit=1, address=0x30, count=2) == [0, 16]  # THD VL1 1.6 % x 10


@pytest.mark.parametrize("address, count", [(0x04, 1), (0x00, 5), (0x3E, 1), (0x1E, 2), (0x100, 2)])
def test_unmapped_registers_answer_exception_02(address, count):
    master, _ = _wire(PowerMeter())
    with pytest.raises(ModbusExceptionError) as info:
        master.read_holding_registers(unit=1, address=address, count=count)
    assert info.value.code == 2


def test_other_functions_answer_exception_01_and_change_nothing():
    meter = PowerMeter(trial=2)
    master, _ = _wire(meter)
    for call in (lambda: master.write_single_register(unit=1, address=0, value=1),
                 lambda: master.write_multiple_registers(unit=1, address=0, values=[1, 2]),
                 lambda: master.read_input_registers(unit=1, address=0, count=2),
                 lambda: master.read_coils(unit=1, address=0, count=1)):
        with pytest.raises(ModbusExceptionError) as info:
            call()
        assert info.value.code == 1
    assert meter.read_values()["VL1"] == 412.6


def test_other_units_are_ignored():
    master, _ = _wire(PowerMeter(unit=1))
    with pytest.raises(Exception) as info:
        master.read_holding_registers(unit=2, address=0, count=2)
    assert "no response" in str(info.value)


def test_live_values_drift_reproducibly_around_the_trial():
    def trend(seed):
        meter = PowerMeter(trial=1, live=True, seed=seed)
        master, link = _wire(meter)
        out = []
        for i in range(0, 600, 60):
            link.clock.run_until(float(i))
            out.append(read_meter(master))
        return out

    a, b, c = trend(7), trend(7), trend(8)
    assert a == b
    assert a != c
    assert len({r["VL1"] for r in a}) > 1  # it does drift
    for reading in a:
        for name, printed in PAPER_TABLE_6.items():
            assert reading[name] == pytest.approx(printed[0], rel=0.25, abs=0.3), name
    energies = [r["kWh"] for r in a]
    assert energies == sorted(energies) and energies[-1] > energies[0]


def test_not_live_means_exactly_the_table_at_any_time():
    meter = PowerMeter(trial=2)
    assert meter.values_at(0) == meter.values_at(1234.5)
    assert meter.values_at(10)["AL3"] == 284.1


def test_meter_table_prints_table_6_side_by_side():
    text = meter_table(TRIALS[1], TRIALS[2])
    lines = {line.split("  ")[0].strip(): line for line in text.splitlines()}
    assert "403.6 V" in lines["Phase voltage - VL1"] and "412.6 V" in lines["Phase voltage - VL1"]
    assert "304.9 A" in lines["Current - AL1"] and "288.9 A" in lines["Current - AL1"]
    assert "0.66" in lines["Power factor - PF1"] and "0.60" in lines["Power factor - PF1"]
    assert lines["Active energy"].endswith("-")


@pytest.mark.parametrize("kwargs", [{"trial": 3}, {"trial": 0}, {"trial": True}, {"seed": "x"}])
def test_bad_settings_raise_config_error(kwargs):
    with pytest.raises(ConfigError):
        PowerMeter(**kwargs)
