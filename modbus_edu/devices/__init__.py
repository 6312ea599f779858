"""Simulated Modbus devices and the data generators that bring them to life.

A device is a :class:`~modbus_edu.slave.Slave` with a register map of its own, so it goes wherever a
slave goes (a loopback wire, a TCP server, ``modbus-edu serve``):

* :class:`PowerMeter` -- the three-phase meter of the power-meter paper (Table 5's map, Table 6's two trials);
* :class:`ArduinoSlave` -- the Arduino Uno slave of the Arduino slave paper (a sparse bank declared with
  reference numbers, potentiometers, switches, LEDs, and a main loop that can be too slow);
* :class:`BenchMeter` -- the single-phase meter of notebook 16's bench day: front-panel line settings,
  a slow first answer, a sparse float32 map from its datasheet excerpt.

:mod:`modbus_edu.devices.generators` holds seeded, clock-driven data sources (ramp, sine, noise,
random) and the dummy-data tools of a test tool's data grid (random fill, fill with a start value and
an increment, auto fill).
"""

from __future__ import annotations

from .arduino import ArduinoSlave, loop_time_experiment
from .bench import DATASHEET, BenchMeter, bench_map, bench_map_path
from .generators import (
    AutoFill,
    Constant,
    Generator,
    Noise,
    Ramp,
    Sine,
    Uniform,
    clamp_register,
    increment_fill,
    random_fill,
)
from .meter import (
    METER_BY_NAME,
    METER_MAP,
    TRIAL_ENERGY_KWH,
    TRIALS,
    MeterRegister,
    PowerMeter,
    decode_meter,
    meter_blocks,
    meter_table,
    read_meter,
)

__all__ = [
    "PowerMeter",
    "MeterRegister",
    "METER_MAP",
    "METER_BY_NAME",
    "TRIALS",
    "TRIAL_ENERGY_KWH",
    "meter_blocks",
    "decode_meter",
    "read_meter",
    "meter_table",
    "ArduinoSlave",
    "BenchMeter",
    "DATASHEET",
    "bench_map",
    "bench_map_path",
    "loop_time_experiment",
    "Generator",
    "Constant",
    "Ramp",
    "Sine",
    "Noise",
    "Uniform",
    "AutoFill",
    "random_fill",
    "increment_fill",
    "clamp_register",
]
