"""Simulated Modbus devices and the data generators that bring them to life.

A device is a :class:`~modbus_edu.slave.Slave` with a register map of its own, so it goes wherever a
slave goes (a loopback wire, a TCP server).  :mod:`modbus_edu.devices.generators` holds seeded,
clock-driven data sources (ramp, sine, noise, random) and the dummy-data tools of a test tool's data
grid (random fill, fill with a start value and an increment, auto fill).
"""
