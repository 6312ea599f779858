"""What every socket role of the library checks and shares: the framings a socket carries, a host, a
port, a number of seconds, whether a host is this computer only, and closing a socket quietly.

Used by :mod:`~modbus_edu.links.tcp_server`, :mod:`~modbus_edu.links.tcp_client`, :mod:`~modbus_edu.links.udp`
and :mod:`~modbus_edu.links.serial`.
"""

from __future__ import annotations

import ipaddress
import socket
from typing import Any

from ..errors import ConfigError, shown

#: The framings a TCP socket can carry: Modbus/TCP's MBAP, or RTU/ASCII frames (a serial device server).
FRAMINGS = ("tcp", "rtu", "ascii")


def is_loopback_host(host: str) -> bool:
    """True if ``host`` names this computer only (127.0.0.0/8, ::1 or 'localhost')."""
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _is_int(value: Any) -> bool:
    """True for a whole number (``True`` and ``False`` are not port numbers)."""
    return isinstance(value, int) and not isinstance(value, bool)


def _check_host(host: Any, what: str, example: str) -> None:
    """A host must be a non-empty text: a name or an IP address."""
    if not isinstance(host, str) or not host.strip():
        shown = f"{type(host).__name__} {host!r}" if not isinstance(host, str) else repr(host)
        raise ConfigError(
            f"the host to {what} must be a host name or an IP address written as text, such as {example}; "
            f"got {shown}"
        )


def _positive_seconds(name: str, value: Any, hint: str) -> float:
    """``value`` as a number of seconds > 0, or a ConfigError naming the setting."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(
            f"{name} must be a positive number of seconds {hint}, got {type(value).__name__} {shown(value)}"
        )
    if not value > 0:  # also refuses NaN
        raise ConfigError(f"{name} must be a positive number of seconds {hint}, got {shown(value)}")
    return float(value)


def _close_socket(sock: socket.socket) -> None:
    try:
        sock.close()
    except OSError:  # pragma: no cover
        pass

