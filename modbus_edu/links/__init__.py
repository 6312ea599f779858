"""Links: the wires a master talks over.

* :class:`~modbus_edu.links.base.Link` -- the interface every link implements;
* :func:`loopback_serial` -- a virtual RS-232/RS-485 line with exact character timing, on a virtual clock
  (timing rules in :mod:`modbus_edu.links.wire`, fault injection in :mod:`modbus_edu.links.faults`);
* :mod:`modbus_edu.links.echo` -- taking an adapter's local echo off the bytes read back;
* :func:`loopback_tcp` -- a virtual Modbus/TCP connection, on a virtual clock;
* :mod:`modbus_edu.links.tcp` and :mod:`modbus_edu.links.serial` -- real sockets and serial ports.
"""

from __future__ import annotations

from .base import Link
from .faults import Faults
from .loopback import LoopbackSerialLink, LoopbackTcpLink, loopback_serial, loopback_tcp
from .wire import BusStats, SerialBus, SerialTiming, character_time

__all__ = [
    "BusStats",
    "Faults",
    "Link",
    "LoopbackSerialLink",
    "LoopbackTcpLink",
    "SerialBus",
    "SerialTiming",
    "character_time",
    "loopback_serial",
    "loopback_tcp",
]
