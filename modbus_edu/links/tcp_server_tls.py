"""Modbus/TCP Security on a :class:`~modbus_edu.links.tcp_server.TcpServer` (``tls=``): its settings
checked, each client's handshake stepped by the server's loop within ``handshake_timeout`` (the handshake
itself is :class:`~modbus_edu.links.tls.ServerHandshake`), the client's role read from its certificate,
refusals and timeouts counted and kept in ``tls_log``, and each request judged by ``authorization=`` (a
refused one answered with exception 01).

A mixin of :class:`~modbus_edu.links.tcp_server.TcpServer`.
"""

from __future__ import annotations

import selectors
from collections import deque
from typing import Any

from ..codes import MBAP_HEADER_SIZE
from ..errors import ConfigError
from ..security import load_x509, role_of
from .routing import exception_reply
from .sockets import _positive_seconds
from .tcp_connection import _Connection
from .tls import TlsRefused, check_context

__all__: list[str] = []


class _ServerTls:
    """The server's side of Modbus/TCP Security: handshakes, roles, authorization."""

    def _tls_setup(self, tls: Any, handshake_timeout: float | None, authorization: Any, framing: str,
                   request_timeout: Any) -> None:
        """Check the TLS settings: ``tls`` a server context requiring client certificates,
        ``handshake_timeout`` (default: ``request_timeout``), ``authorization`` an object with
        ``check(pdu, role, peer) -> decision`` such as :class:`~modbus_edu.security.RoleTable`."""
        self.tls = check_context(tls, "server")
        if self.tls is not None and framing != "tcp":
            raise ConfigError("Modbus/TCP Security carries MBAP frames: tls= needs framing=\"tcp\"")
        if self.tls is not None:
            load_x509()  # cryptography loads now, not during the first client's handshake
        if handshake_timeout is None:
            handshake_timeout = request_timeout
        self.handshake_timeout = _positive_seconds(
            "handshake_timeout", handshake_timeout, "(the time a client has to finish the TLS handshake)")
        if authorization is not None and not callable(getattr(authorization, "check", None)):
            raise ConfigError("authorization= takes a RoleTable (modbus_edu.security.course_roles()), "
                              f"got {type(authorization).__name__}")
        self.authorization = authorization
        self.tls_log: deque[str] = deque(maxlen=100)
        """The last 100 TLS refusals and timeouts: who, and why."""

    def _tls_step(self, conn: _Connection) -> None:
        """One step of a client's handshake; when done, its role is read from its certificate."""
        handshake = conn.handshake
        assert handshake is not None
        try:
            want = handshake.step()
        except TlsRefused as exc:
            self._tls_refuse(conn, str(exc))
            return
        if want != "done":
            self._set_events(conn, selectors.EVENT_READ if want == "read" else selectors.EVENT_WRITE)
            return
        conn.handshake = None
        try:
            conn.role = role_of(handshake.peer_certificate())
        except Exception as exc:  # a role extension that is not a UTF8String: refuse the client
            self._tls_refuse(conn, f"the client's certificate has a broken role: {exc}")
            return
        self.counters.tls_handshakes += 1
        self.log.debug("client %s: TLS handshake done, role %r", conn.peer, conn.role)
        self._set_events(conn, selectors.EVENT_READ)
        self._read(conn)  # a request may have come with the end of the handshake

    def _tls_refuse(self, conn: _Connection, why: str, timeout: bool = False) -> None:
        if timeout:
            self.counters.tls_timeouts += 1
        else:
            self.counters.tls_refused += 1
        self.tls_log.append(f"{conn.peer[0]}:{conn.peer[1]}: {why}")
        self._drop(conn, f"TLS: {why}")  # logged as info: the counters and tls_log keep the record

    def _tls_authorize(self, conn: _Connection, frame: bytes) -> bytes | None:
        """The exception 01 a refused request gets (counted), or None to let the slave answer."""
        if self.authorization is None or self.framing != "tcp" or len(frame) <= MBAP_HEADER_SIZE:
            return None
        peer = f"{conn.peer[0]}:{conn.peer[1]}"
        decision = self.authorization.check(frame[MBAP_HEADER_SIZE:], conn.role, peer)
        if decision.allowed:
            return None
        self.counters.requests += 1
        self.counters.unauthorized += 1
        self.counters.responses += 1
        return exception_reply(frame, 0x01)
