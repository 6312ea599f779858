"""Routing a request to the slave it is for, shared by every server and by the virtual TCP link.

The servers only move bytes; what happens to a request once it is cut from the stream is decided here,
once: which slave a unit id reaches (:func:`route_unit`, after the *Modbus Messaging on TCP/IP
Implementation Guide*, section 4.4.1.2), the exception responses a server sends by itself
(:func:`exception_reply`: 0x0B when nobody is at that unit, 0x04 when a slave fails), and one Modbus/TCP
request carried from frame to reply (:func:`dispatch`).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from ..codes import MBAP, ExceptionCode
from ..errors import ConfigError
from ..framing import TcpFrame
from ..pdu import ExceptionResponse

if TYPE_CHECKING:  # pragma: no cover - typing only
    from ..slave import Slave

__all__ = [
    "GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND",
    "SERVER_DEVICE_FAILURE",
    "DIRECT_UNITS",
    "normalize_slaves",
    "route_unit",
    "exception_reply",
    "dispatch",
]

#: Exception code a gateway returns when the addressed device does not answer (spec section 7).
GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND = int(ExceptionCode.GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND)
#: Exception code for "an unrecoverable error occurred while the server was performing the action".
SERVER_DEVICE_FAILURE = int(ExceptionCode.SERVER_DEVICE_FAILURE)
#: The unit ids that mean "the device itself" on Modbus/TCP (implementation guide, section 4.4.1.2):
#: 0xFF is the recommended one, 0 is accepted too.
DIRECT_UNITS = (0x00, 0xFF)


def normalize_slaves(slaves: Any) -> dict[int | None, Slave]:
    """Turn ``slaves`` - one Slave, an iterable of Slaves or a mapping unit -> Slave - into a dict.

    The keys are the units the slaves answer to; ``None`` is the key of a ``Slave(unit=None)``, which
    answers any unit that no other slave owns. Every Slave filters requests by its own ``unit``, so in
    a mapping each key must equal its slave's unit, and two slaves may not share a unit (on a real bus
    they would both answer and garble each other's response).
    """
    if slaves is None:
        raise ConfigError("a server needs at least one Slave to serve; got None")
    if isinstance(slaves, Mapping):
        pairs = list(slaves.items())
        for key, slave in pairs:
            own = _unit_of(slave)
            if own != key:
                raise ConfigError(
                    f"the slave registered under unit {key} answers to unit {own}: "
                    "the key of the mapping must be the slave's own unit id"
                )
        items = [slave for _, slave in pairs]
    elif isinstance(slaves, (list, tuple, set, frozenset)):
        items = list(slaves)
    else:
        items = [slaves]
    result: dict[int | None, Slave] = {}
    for slave in items:
        unit = _unit_of(slave)
        if unit in result:
            who = "any unit (unit=None)" if unit is None else f"unit {unit}"
            raise ConfigError(f"two slaves answer to {who}; give every slave its own unit id (1..247)")
        result[unit] = slave
    if not result:
        raise ConfigError("a server needs at least one Slave to serve; got an empty collection")
    return result


def route_unit(slaves: Mapping[int | None, Slave], unit: int) -> tuple[Slave | None, bool]:
    """Which slave answers a Modbus/TCP request for ``unit``: ``(slave, direct)``, or ``(None, False)``.

    ``slaves`` is what :func:`normalize_slaves` returns.  The rules, after the *Modbus Messaging on
    TCP/IP Implementation Guide* (V1.0b, section 4.4.1.2):

    * **one slave** - the server *is* the device, reached by its IP address: units **0** and **0xFF**
      mean "you" and reach it whatever its own unit (``direct`` is True: the server calls
      :meth:`~modbus_edu.slave.Slave.handle_direct`, and the response echoes the request's unit id).
      Its own unit reaches it too; any other unit finds nobody.
    * **several slaves** - the server is a *gateway* and routes by unit id: the slave with that unit,
      else a ``Slave(unit=None)`` if there is one (it answers any unit 1..255, 0xFF included), else
      nobody.  Unit **0** finds nobody: it would be a broadcast on the serial line behind a gateway,
      and TCP has no broadcast (the client waits for an answer).  Unit 0xFF finds nobody unless a slave
      owns it: the guide chose 0xFF because no serial slave has that address.

    "Nobody" is answered with exception 0x0B by :class:`TcpServer`.

    >>> from modbus_edu.slave import Slave
    >>> one = normalize_slaves(Slave(unit=1))
    >>> [route_unit(one, unit)[1] for unit in (0, 1, 0xFF)]
    [True, False, True]
    >>> route_unit(one, 5)
    (None, False)
    >>> gateway = normalize_slaves([Slave(unit=1), Slave(unit=2)])
    >>> route_unit(gateway, 2)[0].unit, route_unit(gateway, 0), route_unit(gateway, 0xFF)
    (2, (None, False), (None, False))
    """
    if len(slaves) == 1 and unit in DIRECT_UNITS:
        return next(iter(slaves.values())), True
    if unit == 0:
        return None, False
    slave = slaves.get(unit)
    if slave is None:
        slave = slaves.get(None)
    return slave, False


def _unit_of(slave: Any) -> int | None:
    if not hasattr(slave, "handle") or not hasattr(slave, "unit"):
        raise ConfigError(
            f"expected a Slave (an object with .unit and .handle(frame, mode)), got {type(slave).__name__}"
        )
    return slave.unit


def _units_text(slaves: Mapping[int | None, Any]) -> str:
    units = sorted(u for u in slaves if u is not None)
    text = ",".join(str(u) for u in units)
    if None in slaves:
        text = f"{text}+any" if text else "any"
    return text


def exception_reply(frame: bytes, code: int) -> bytes | None:
    """The exception response a Modbus/TCP server sends itself for request ``frame`` (same transaction id
    and unit), e.g. 0x0B when no slave is at that unit; None for a frame without a function code."""
    tid, _, _, unit = MBAP.unpack_from(frame, 0)
    function = frame[7] & 0x7F if len(frame) > 7 else 0
    if function == 0:
        return None
    pdu = ExceptionResponse(function=function, code=code)
    return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()


def dispatch(slaves: Mapping[int | None, Slave], frame: bytes, lock: threading.Lock,
             log: logging.Logger) -> tuple[bytes | None, bool]:
    """One Modbus/TCP request ``frame`` to the slave of its unit: ``(reply, found)``.

    ``reply`` is the bytes to send back (None: nothing), ``found`` whether a slave was at that unit
    (nobody is answered 0x0B at once).  A slave turns every protocol problem into an exception response
    itself; one that raises has a bug or a failing callback (on_read/on_write), and the client is told
    0x04, server device failure.
    """
    unit = frame[6]
    slave, direct = route_unit(slaves, unit)
    if slave is None:  # nobody at that unit (or unit 0 at a gateway): tell the client at once
        reply = exception_reply(frame, GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND)
        if log.isEnabledFor(logging.DEBUG):
            log.debug("no slave at unit %d: %s answered 0x0B with %s", unit, frame.hex(" ").upper(),
                      reply.hex(" ").upper() if reply else "nothing")
        return reply, False
    try:
        with lock:
            if direct and hasattr(slave, "handle_direct"):  # unit 0 / 0xFF: the device itself
                return slave.handle_direct(frame), True
            return slave.handle(frame, "tcp"), True
    except Exception:
        log.exception("slave for unit %d failed on request %s", unit, frame.hex(" "))
        return exception_reply(frame, SERVER_DEVICE_FAILURE), True
