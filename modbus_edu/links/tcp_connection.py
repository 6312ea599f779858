"""What a :class:`~modbus_edu.links.tcp_server.TcpServer` keeps: its counters, and per accepted client
the socket, the bytes not yet a whole frame, the requests waiting and the answers owed.
"""

from __future__ import annotations

import selectors
import socket
from collections import deque
from dataclasses import dataclass, fields
from typing import Any

from .tls import ServerHandshake

__all__ = ["TcpServerCounters"]


@dataclass
class TcpServerCounters:
    """What a :class:`TcpServer` has seen since it started.

    ``connections``  clients accepted;  ``requests``  complete frames received;  ``responses``  frames
    sent back;  ``bad_frames``  connections closed because their bytes were not Modbus/TCP (bad MBAP);
    ``unknown_unit``  requests for a unit no slave here answers (see :func:`~.routing.route_unit`; unit 0 on a
    server with several slaves), answered with exception 0x0B;
    ``idle_closed``  connections closed after ``idle_timeout`` seconds of silence;
    ``slow_closed``  connections closed because a request did not complete within ``request_timeout``
    seconds of its first byte;  ``evicted``  connections closed to make room for a new client (unfinished
    TLS handshakes first, then clients that never completed a request, then the longest idle);
    ``held_back``  times a connection was not read because its unanswered input or unsent output was
    at its bound (a client that pipelines without reading);  ``late_replies``  answers of an
    asynchronous slave (a gateway) that came after their connection had gone, and were dropped.

    With ``tls=`` (Modbus/TCP Security): ``tls_handshakes``  clients that completed the handshake;
    ``tls_refused``  clients refused during it (no certificate, an expired one, another authority's:
    the server's ``tls_log`` says which and why);  ``tls_timeouts``  clients that did not finish it
    within ``handshake_timeout``;  ``unauthorized``  requests their role may not send (answered with
    exception 01, see :class:`~modbus_edu.security.RoleTable`).
    """

    connections: int = 0
    requests: int = 0
    responses: int = 0
    bad_frames: int = 0
    unknown_unit: int = 0
    idle_closed: int = 0
    slow_closed: int = 0
    evicted: int = 0
    held_back: int = 0
    late_replies: int = 0
    tls_handshakes: int = 0
    tls_refused: int = 0
    tls_timeouts: int = 0
    unauthorized: int = 0

    def as_dict(self) -> dict[str, int]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


class _Connection:
    """One accepted client: its socket, what it sent that is not yet a whole frame, what we owe it."""

    __slots__ = ("sock", "fd", "peer", "outbuf", "last_activity", "last_byte", "partial_since", "events",
                 "splitter", "frames", "served", "junk_mark", "awaiting", "handshake", "role")

    def __init__(self, sock: socket.socket, peer: Any, now: float, splitter: Any) -> None:
        self.sock = sock
        self.fd = sock.fileno()
        self.peer = peer
        self.outbuf = bytearray()
        self.last_activity = now
        self.last_byte = now
        self.partial_since: float | None = None  # when the first byte of an unfinished request came
        self.events = selectors.EVENT_READ
        self.splitter = splitter  # cuts this connection's requests out of its byte stream
        self.frames: deque[bytes] = deque()  # whole requests cut by the splitter, not yet answered
        self.served = 0  # requests answered: a client that has never completed one is the first to go
        self.junk_mark = 0  # the splitter's discarded count when the last whole request came
        self.awaiting = False  # an asynchronous slave (a gateway) has this connection's request
        self.handshake: ServerHandshake | None = None  # TLS: the handshake under way
        self.role: str | None = None  # TLS: the role in the client's certificate
