"""The listening side of a :class:`~modbus_edu.links.tcp_server.TcpServer`: binding its socket (a warning
beyond loopback, where Modbus/TCP's lack of authentication reaches other computers), accepting clients up
to ``max_connections`` (evicting an unfinished TLS handshake first, then a client never served, then the
longest idle), and pausing when ``accept()`` fails instead of spinning; warnings rate-limited.

A mixin of :class:`~modbus_edu.links.tcp_server.TcpServer`: it reads and sets the server's state (its
selector, its connections, its earliest deadline), and hands each new client to the server's splitter
(:mod:`~modbus_edu.links.tcp_requests`) and TLS handshake (:mod:`~modbus_edu.links.tcp_server_tls`).
"""

from __future__ import annotations

import errno
import selectors
import socket
import time
from typing import Any

from ..errors import LinkError
from .sockets import is_loopback_host
from .tcp_connection import _Connection
from .tls import ServerHandshake

__all__: list[str] = []


class _Listener:
    """Bind, accept, evict, pause: the server's listening socket."""

    def _bind(self) -> None:
        if self._listener is not None:
            return
        if self._closed:
            raise LinkError("this TcpServer was closed; create a new one to serve again")
        try:
            infos = socket.getaddrinfo(self.host, self.port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
        except socket.gaierror as exc:
            raise LinkError(f"cannot listen on {self.host!r}: unknown host name ({exc.strerror})") from exc
        family, socktype, proto, _, sockaddr = infos[0]
        listener = socket.socket(family, socktype, proto)
        try:
            listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            listener.bind(sockaddr)
            listener.listen(128)
            listener.setblocking(False)
        except OSError as exc:
            listener.close()
            hint = ""
            if exc.errno == errno.EADDRINUSE:
                hint = " - another program already listens there; pick another port (port=0 picks a free one)"
            elif exc.errno == errno.EACCES:
                hint = " - ports below 1024 (such as 502) need administrator rights; try 5020"
            raise LinkError(f"cannot listen on {self.host}:{self.port}: {exc.strerror}{hint}") from exc
        if not is_loopback_host(self.host) and self.tls is None:  # said once it really listens
            self.log.warning(
                "Modbus/TCP server listening on %s, which is reachable from other computers: "
                "Modbus/TCP has no authentication and no encryption - anyone who can reach this "
                "port can read and write every register. Use 127.0.0.1 unless you mean it.",
                self.host,
            )
        self._listener = listener
        self.address = listener.getsockname()[:2]
        self._selector = selectors.DefaultSelector()
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._selector.register(listener, selectors.EVENT_READ, None)
        self._selector.register(self._wake_r, selectors.EVENT_READ, None)
        self.log.info("Modbus/TCP server listening on %s:%d", *self.address)

    def _warn(self, key: str, message: str, *args: Any) -> None:
        """Log a warning at most once per 10 s per ``key``, saying how many were held back."""
        now = time.monotonic()
        last, held = self._warned.get(key, (-1e9, 0))
        if now - last < 10.0:
            self._warned[key] = (last, held + 1)
            return
        self._warned[key] = (now, 0)
        if held:
            message += f" ({held} more like it in the last 10 s not logged)"
        self.log.warning(message, *args)

    def _accept(self) -> None:
        assert self._listener is not None and self._selector is not None
        while True:
            try:
                sock, peer = self._listener.accept()
            except (BlockingIOError, InterruptedError):
                self._accept_backoff = 0.0
                return
            except OSError as exc:  # e.g. EMFILE: out of file descriptors; pause instead of spinning
                self._accept_backoff = min(1.0, max(0.05, 2 * self._accept_backoff))
                self._accept_paused_until = time.monotonic() + self._accept_backoff
                self._selector.unregister(self._listener)
                self._warn("accept", "accept failed: %s; pausing %.2f s", exc, self._accept_backoff)
                return
            if len(self._connections) >= self.max_connections:
                # room: an unfinished handshake, then a connection never served, then the longest idle
                oldest = min(self._connections.values(),
                             key=lambda c: (c.handshake is None, c.served > 0, c.last_activity))
                self.counters.evicted += 1
                self._warn("evict", "client %s connects with %d connections open (max_connections=%d): "
                           "closing %s", peer, len(self._connections), self.max_connections, oldest.peer)
                self._drop(oldest, "closed to make room for a new client")
            sock.setblocking(False)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            conn = _Connection(sock, peer, time.monotonic(), self._splitter())
            if self.tls is not None:
                conn.handshake = ServerHandshake(self.tls, sock, time.monotonic() + self.handshake_timeout)
                conn.sock = sock = conn.handshake.sock
            self._connections[sock.fileno()] = conn
            self._selector.register(sock, selectors.EVENT_READ, conn)
            self._earliest = min(self._earliest, self._deadlines(conn))
            self.counters.connections += 1
            self.log.debug("client %s connected", peer)
