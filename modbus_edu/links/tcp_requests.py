"""Each connection of a :class:`~modbus_edu.links.tcp_server.TcpServer`: its bytes and its deadlines.

What comes in is read in bounded pieces and cut into requests by the connection's splitter (Modbus/TCP by
the MBAP length, RTU by length, CRC and quiet gap, ASCII by its delimiters); one request per connection
per turn is answered; what is owed is sent as the socket takes it.  A connection whose input or output is
at its bound is not read until it catches up (TCP's flow control holds the client back).  Every
connection has deadlines (a TLS handshake's, the idle timeout, a request's from its first byte, RTU's
quiet gap): the loop keeps a lower bound of the earliest and scans the connections only once it is due.

A mixin of :class:`~modbus_edu.links.tcp_server.TcpServer`, which dispatches each request
(``_dispatch``, ``_dispatch_serial``, ``_hand_over``) and runs the loop that calls these.
"""

from __future__ import annotations

import selectors
import time
from typing import Any

from ..framing import TcpSplitter, splitter_for
from ..framing.tcp import is_one_frame
from ..pdu import REQUEST_CLASSES
from .sockets import _close_socket
from .tcp_connection import _Connection
from .tls import WOULD_BLOCK, pending

__all__: list[str] = []

#: Stop reading from a client whose unsent responses pile up beyond this (it does not read its socket).
_MAX_PENDING_OUTPUT = 64 * 1024
#: The most bytes one read takes from a client: with :data:`_MAX_QUEUED`, what a connection may hold.
_READ_SIZE = 4096
#: RTU over TCP reads less at a time: junk costs the RTU splitter more per byte (it looks for a CRC).
_SERIAL_READ_SIZE = 512
#: Stop reading from a client with this many whole requests waiting for their turn (it pipelines).
_MAX_QUEUED = 16
#: RTU/ASCII over TCP: bytes that never become a frame before a connection is closed as not Modbus.
_MAX_JUNK = 1024


class _Requests:
    """A connection's bytes in, requests cut and answered in turn, answers out, deadlines kept."""

    def _deadlines(self, conn: _Connection) -> float:
        """When something must happen to ``conn`` if nothing changes: its TLS handshake's deadline, its
        idle timeout, its unfinished request's deadline, or (RTU over TCP) the quiet gap that ends an
        unfinished frame."""
        due = float("inf") if conn.handshake is None else conn.handshake.deadline
        if self.idle_timeout is not None and not conn.awaiting:
            due = min(due, conn.last_activity + self.idle_timeout)
        if conn.partial_since is not None:
            due = min(due, conn.partial_since + self.request_timeout)
        if self.framing == "rtu" and conn.splitter.pending:
            due = min(due, conn.last_byte + self.quiet_gap)
        return due

    def _next_deadline(self) -> float | None:
        """Seconds until the next connection deadline (at the least) or accept pause's end (None: never)."""
        due = self._earliest
        if self._accept_paused_until:
            due = min(due, self._accept_paused_until)
        return None if due == float("inf") else max(0.0, due - time.monotonic())

    def _expire(self) -> None:
        """Close connections past a deadline; resume accepting after a pause."""
        now = time.monotonic()
        if self._accept_paused_until and now >= self._accept_paused_until:
            self._accept_paused_until = 0.0
            if self._selector is not None and self._listener is not None:
                self._selector.register(self._listener, selectors.EVENT_READ, None)
        if now < self._earliest:
            return
        for conn in [c for c in self._connections.values() if self._deadlines(c) <= now]:
            if conn.handshake is not None and now >= conn.handshake.deadline:
                self._tls_refuse(conn, f"no TLS handshake within {self.handshake_timeout:g} s", timeout=True)
            elif self.framing == "rtu" and conn.splitter.pending and now >= conn.last_byte + self.quiet_gap:
                # a quiet gap: what has come is all there is of this frame (a socket's silence)
                self._cut(conn, conn.splitter.flush(), now)
                self._pump(conn)
            elif conn.partial_since is not None and now >= conn.partial_since + self.request_timeout:
                self.counters.slow_closed += 1
                self._drop(conn, f"a request did not arrive whole within {self.request_timeout:g} s")
            else:
                self.counters.idle_closed += 1
                self._drop(conn, f"silent for {self.idle_timeout:g} s (idle timeout)")
        self._earliest = min(map(self._deadlines, self._connections.values()), default=float("inf"))

    def _splitter(self) -> Any:
        """A new connection's splitter: Modbus/TCP by the MBAP length (strict: a bad header ends the
        connection), RTU by length, CRC and quiet gap (open-ended: every byte is meant as Modbus), ASCII
        by its delimiters."""
        if self.framing == "tcp":
            return TcpSplitter(strict=True)
        return splitter_for(self.framing, "request", open_ended=True)

    def _drop(self, conn: _Connection, reason: str | None) -> None:
        if self._connections.get(conn.fd) is not conn:
            return
        del self._connections[conn.fd]
        self._backlog.pop(conn.fd, None)
        if self._selector is not None and conn.events:
            try:
                self._selector.unregister(conn.sock)
            except (KeyError, ValueError):  # pragma: no cover
                pass
        _close_socket(conn.sock)
        if reason:
            self.log.info("closed connection from %s: %s", conn.peer, reason)

    def _set_events(self, conn: _Connection, events: int) -> None:
        """Watch ``conn`` for ``events`` (0: not at all, while it waits its turn with nothing to send)."""
        selector = self._selector
        if conn.events == events or selector is None:
            return
        if not events:
            selector.unregister(conn.sock)
        elif not conn.events:
            selector.register(conn.sock, events, conn)
        else:
            selector.modify(conn.sock, events, conn)
        conn.events = events

    def _read(self, conn: _Connection) -> None:
        if conn.handshake is not None:
            self._tls_step(conn)
            return
        try:
            data = conn.sock.recv(_READ_SIZE if self.framing == "tcp" else _SERIAL_READ_SIZE)
            if self.tls is not None and pending(conn.sock):  # TLS: the rest of a record already decrypted
                data += conn.sock.recv(pending(conn.sock))
        except WOULD_BLOCK:
            return
        except OSError as exc:
            self._drop(conn, f"receive failed: {exc.strerror or exc}")
            return
        if not data:
            self._drop(conn, None)  # the client closed its end: an ordinary goodbye
            return
        conn.last_activity = conn.last_byte = now = time.monotonic()
        if self._direct and self._answer_directly(conn, data):
            return
        self._cut(conn, conn.splitter.feed(data), now)
        self._pump(conn)

    def _cut(self, conn: _Connection, frames: list[bytes], now: float) -> None:
        """Queue the requests cut.  RTU, ASCII: the request clock runs from a byte to the next request."""
        conn.frames.extend(frames)
        if self.framing != "tcp":
            since = conn.partial_since or now  # a whole request stops the clock (restarts if bytes remain)
            conn.partial_since = (now if conn.splitter.pending else None) if any(
                self._implemented(frame) for frame in frames) else since
            self._earliest = min(self._earliest, self._deadlines(conn))

    def _answer_directly(self, conn: _Connection, data: bytes) -> bool:
        """Answer ``data`` now if it is one whole Modbus/TCP request and nothing of ``conn`` waits (no
        bytes, requests or answers): the splitter, :meth:`_pump` and :meth:`_process` in one step."""
        if conn.frames or conn.outbuf or conn.awaiting or conn.splitter.pending or not is_one_frame(data):
            return False
        conn.served += 1
        conn.junk_mark = conn.splitter.discarded
        conn.partial_since = None
        reply = self._dispatch(data)
        if reply:
            conn.outbuf += reply
            if self._send(conn) and conn.outbuf:
                self._set_events(conn, selectors.EVENT_READ | selectors.EVENT_WRITE)
        return True

    def _pump(self, conn: _Connection) -> None:
        """Answer one request that has arrived and send what is owed; queue the connection for the next
        turn if another complete request is waiting; read it again only while it is within its bounds.

        A client that sends requests without reading the answers fills our output buffer, and one that
        pipelines fills the queue of requests: past ``_MAX_PENDING_OUTPUT`` bytes or ``_MAX_QUEUED``
        requests the server stops reading that client until it has caught up, so that no client can
        make the server buffer without end.
        """
        if conn.handshake is not None:
            self._tls_step(conn)
            return
        if not self._process(conn) or not self._send(conn):
            return
        full = len(conn.outbuf) >= _MAX_PENDING_OUTPUT or len(conn.frames) >= _MAX_QUEUED
        if full and conn.events & selectors.EVENT_READ:
            self.counters.held_back += 1
        events = (0 if full else selectors.EVENT_READ) | (selectors.EVENT_WRITE if conn.outbuf else 0)
        self._set_events(conn, events)
        waiting = conn.frames or conn.splitter.error or conn.splitter.discarded - conn.junk_mark > _MAX_JUNK
        if waiting and not conn.awaiting and len(conn.outbuf) < _MAX_PENDING_OUTPUT:
            self._backlog[conn.fd] = conn

    def _process(self, conn: _Connection) -> bool:
        """Answer the first complete request, if there is one and the connection's bounds allow.

        The connection's splitter has cut the requests (Modbus/TCP by the MBAP length, RTU by length and
        CRC, ASCII by its delimiters).  Returns False if the connection was closed because its bytes are
        not Modbus.
        """
        splitter = conn.splitter
        if conn.frames and not conn.awaiting and len(conn.outbuf) < _MAX_PENDING_OUTPUT:
            frame = conn.frames.popleft()
            conn.served += 1
            if self._implemented(frame):  # junk that happens to pass a CRC check does not count
                conn.junk_mark = splitter.discarded
            refused = self._tls_authorize(conn, frame)  # Modbus/TCP Security: the client's role decides
            if refused:
                conn.outbuf += refused
            elif self._submit is not None:
                self._hand_over(conn, frame)
            else:
                reply = self._dispatch(frame) if self.framing == "tcp" else self._dispatch_serial(frame)
                if reply:
                    conn.outbuf += reply
        elif not conn.frames and (splitter.error or splitter.discarded - conn.junk_mark > _MAX_JUNK):
            # a header that is not Modbus/TCP, or a stream of bytes that never make a frame
            self.counters.bad_frames += 1
            junk = splitter.discarded - conn.junk_mark
            why = splitter.error or f"{junk} bytes that make no {self.framing.upper()} frame"
            if self._send(conn):  # the answers to the good frames before it, as far as they go
                self._drop(conn, f"not Modbus: {why}")
            return False
        # Modbus/TCP: bytes of a request start its clock, a whole one stops it (RTU and ASCII: _cut)
        if self.framing == "tcp":
            if not splitter.pending or conn.frames:
                conn.partial_since = None
            elif conn.partial_since is None:
                conn.partial_since = time.monotonic()
                self._earliest = min(self._earliest, self._deadlines(conn))
        return True

    def _implemented(self, frame: bytes) -> bool:
        """Whether a request's function code is one the library implements (RTU and ASCII over TCP: one
        in a thousand junk bytes starts something whose CRC checks out, with an unknown function)."""
        if self.framing == "tcp":
            return True
        try:
            function = frame[1] if self.framing == "rtu" else int(frame[3:5], 16)
        except ValueError:
            return False
        return function in REQUEST_CLASSES
    def _send(self, conn: _Connection) -> bool:
        """Send as much of the output buffer as the socket takes. False if the connection died."""
        if conn.outbuf:
            try:
                sent = conn.sock.send(conn.outbuf)
            except WOULD_BLOCK:
                sent = 0
            except OSError as exc:
                self._drop(conn, f"send failed: {exc.strerror or exc}")
                return False
            del conn.outbuf[:sent]
        return True
