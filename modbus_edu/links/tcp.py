"""Modbus/TCP on real sockets: the server (:mod:`~modbus_edu.links.tcp_server`) and the client link
(:mod:`~modbus_edu.links.tcp_client`), under the one name they have always had.

``from modbus_edu.links.tcp import TcpServer, tcp_link`` keeps working; the teaching text about the MBAP
header and the unit identifier on TCP is in :mod:`modbus_edu.links.tcp_server`.
"""

from __future__ import annotations

from ..codes import MBAP_HEADER_SIZE
from .routing import (  # noqa: F401 (routing's names, re-exported where they were first defined)
    DIRECT_UNITS,
    GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND,
    SERVER_DEVICE_FAILURE,
    dispatch,
    exception_reply,
    normalize_slaves,
    route_unit,
)
from .sockets import FRAMINGS, is_loopback_host
from .tcp_client import DRAIN_SECONDS, TcpLink, tcp_link
from .tcp_server import TcpServer, TcpServerCounters

__all__ = [
    "DRAIN_SECONDS",
    "FRAMINGS",
    "MBAP_HEADER_SIZE",
    "TcpServer",
    "TcpServerCounters",
    "tcp_link",
    "TcpLink",
    "normalize_slaves",
    "route_unit",
    "is_loopback_host",
]
