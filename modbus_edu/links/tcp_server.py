"""Modbus/TCP on real sockets, the server side: :class:`TcpServer` serves the course's slaves.

Modbus/TCP wraps each PDU in a seven-byte *MBAP header* (:class:`~modbus_edu.framing.TcpFrame` shows its
fields). TCP is a byte *stream*: a request can arrive split over several reads, or two in one read; the
header's length field tells where a frame ends - there is no CRC and no silence to go by.

:class:`TcpServer` serves one or several :class:`~modbus_edu.slave.Slave` objects (selected by the unit
id of each request, see :func:`~.routing.route_unit`) from a background thread; the client's side is
:func:`~modbus_edu.links.tcp_client.tcp_link` (:mod:`modbus_edu.links.tcp_client`).

The unit identifier on TCP: the IP address already chose the device, so a device reached directly does
not need the unit id. The *Modbus Messaging on TCP/IP Implementation Guide* (V1.0b, section 4.4.1.2,
page 23) says: "On TCP/IP, the MODBUS server is addressed using its IP address; therefore, the MODBUS
Unit Identifier is useless. The value 0xFF has to be used", and "the value 0 is also accepted to
communicate directly to a MODBUS/TCP device". There is **no broadcast on TCP**: unit 0 is a broadcast on
a serial line only. The unit id matters to a *gateway*, which forwards the request to the serial slave
with that address - and 0xFF is recommended because no serial slave has it (248..255 are reserved), so a
gateway that takes the place of a device at the same IP address refuses the request instead of writing
to whichever serial slave happens to have the number.

Modbus/TCP has no authentication and no encryption: anybody who can reach the port can read and write
every register. That is why the server binds to the loopback address 127.0.0.1 unless told otherwise,
and logs a warning when it is told otherwise.

``tls=`` (an ``ssl.SSLContext`` from :mod:`modbus_edu.security`) turns the server into *Modbus/TCP
Security*: the same frames inside mutual TLS, each client known by its certificate and its role, and
``authorization=`` deciding what each role may do (:mod:`modbus_edu.links.tls` holds the handshakes).
"""

from __future__ import annotations

import errno
import logging
import selectors
import socket
import threading
import time
from collections import deque
from typing import Any

from ..clock import RealClock
from ..codes import MBAP_HEADER_SIZE
from ..errors import ConfigError, LinkError, guard_numbers, shown
from ..framing import TcpSplitter, splitter_for
from ..framing.tcp import is_one_frame
from ..pdu import REQUEST_CLASSES
from ..platform import require_sockets
from ..security import load_x509, role_of
from .routing import (
    SERVER_DEVICE_FAILURE,
    _units_text,
    dispatch,
    exception_reply,
    normalize_slaves,
)
from .sockets import FRAMINGS, _check_host, _close_socket, _is_int, _positive_seconds, is_loopback_host
from .tcp_connection import TcpServerCounters, _Connection
from .tls import WOULD_BLOCK, ServerHandshake, TlsRefused, check_context, pending

__all__ = ["TcpServer", "TcpServerCounters"]


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

_log = logging.getLogger("modbus_edu.tcp")


class TcpServer:
    """A Modbus/TCP server for the course's slaves, running in a background thread.

    ``slaves`` is one :class:`~modbus_edu.slave.Slave`, a list of them, or a dict unit -> Slave. Each
    request goes to the slave chosen by the unit id in its MBAP header (:func:`~.routing.route_unit`);
    that slave's ``handle(frame, "tcp")`` does all the protocol work (decoding, the data bank, exception
    responses), so the server only cuts the byte stream into frames and routes them. Every response
    carries the request's transaction id and unit id.

    Unit ids, after the *Modbus Messaging on TCP/IP Implementation Guide* (V1.0b, section 4.4.1.2):

    * serving **one slave**, the server is the device, reached by its IP address: unit **0xFF** (the
      guide's recommended value) and unit **0** (also accepted, "to communicate directly to a MODBUS/TCP
      device") reach it, as does its own unit. Unit 0 is *not* a broadcast: Modbus/TCP has none, so the
      device answers.
    * serving **several slaves**, the server behaves like a Modbus/TCP-to-serial gateway and routes by
      unit id. Unit 0 is refused (on the serial line behind a real gateway it would be a broadcast,
      which nobody answers - but a TCP client waits for an answer); so is 0xFF, unless a slave owns it.

    A request that finds no slave is answered with exception code **0x0B, gateway target device failed
    to respond** - what a gateway answers when nobody on its serial line replies - and counted in
    ``counters.unknown_unit``. (A lone device might answer 0x0B or nothing at all; 0x0B tells the client
    at once instead of letting it time out.) Broadcasts (unit 0) remain a serial-line matter:
    :class:`~modbus_edu.links.serial.SerialServer` and the virtual serial line carry them out.

    Defences, because a TCP port is open to whatever connects to it:

    * every MBAP header is checked (by a strict :class:`~modbus_edu.framing.TcpSplitter`): protocol id
      must be 0 and the length field 2..254; a client that sends anything else is not speaking
      Modbus/TCP and its connection is closed (``bad_frames``); other clients are not affected.
    * a connection silent for ``idle_timeout`` seconds (``None``: never) is closed.
    * a request must arrive whole within ``request_timeout`` s of its first byte (RTU, ASCII: the first
      after the last request, junk included), or it is closed (``slow_closed``): slowloris holds nothing.
    * at most ``max_connections`` clients at a time; when a new one comes, the connection that has been
      idle longest is closed to make room (``evicted``), so idle clients cannot lock others out.
    * the server is fair: each turn it answers at most one request per connection, so a client that
      pipelines thousands of requests does not delay the others.
    * every connection's input and output are bounded: the server stops reading a client that has
      :data:`_MAX_QUEUED` whole requests waiting or :data:`_MAX_PENDING_OUTPUT` bytes of answers it
      has not read, and reads at most :data:`_READ_SIZE` bytes at a time; TCP's flow control then
      holds the client back.  A client that pipelines without reading costs a few kilobytes, not
      memory without end (``held_back``).
    * RTU and ASCII over TCP: a connection whose bytes never make a frame (:data:`_MAX_JUNK` bytes of
      junk since its last request) is closed (``bad_frames``); an RTU frame whose length its bytes do
      not say (an unknown function code, FC 8 Return Query Data) ends where its CRC checks out, and
      an unfinished one ends after ``quiet_gap`` seconds without a byte (a socket has no silence of
      3.5 characters, but a short quiet gap works the same way).
    * when the server is full, it closes an unfinished TLS handshake, else a connection never served (the
      oldest), else the longest idle one: a flood of new or broken connections cannot push out the served.
    * when ``accept()`` fails (out of file descriptors), the server stops accepting for a moment instead
      of spinning; refusal and failure warnings are rate-limited.

    The server is a context manager: ``with TcpServer(slave) as server: ... server.address``. It starts
    on ``__enter__`` (or :meth:`start`) and :meth:`close` stops it: listening socket and every client
    connection closed, background thread joined. :meth:`serve_forever` runs it in the calling thread
    instead (for a command line).

    Binding to an address other than the loopback (``host="0.0.0.0"`` to listen on every interface)
    must be asked for explicitly and logs a warning: Modbus/TCP has no authentication at all.

    The server answers as soon as the slave has: a slave's ``processing_time`` / ``response_delay``
    shapes timing on the virtual links and on :class:`~modbus_edu.links.serial.SerialServer`, not
    here (one slow answer would hold up every client of this single-threaded server).

    ``lock`` is held while a slave handles a request: hold it too (``with server.lock:``) to change
    several registers of a served bank at once without a client seeing half of the change.

    Settings of the wrong kind (``host=5``, ``port="502"``, ``idle_timeout="x"``, ...) raise
    :class:`~modbus_edu.errors.ConfigError` at once, saying what was expected.
    """

    @guard_numbers
    def __init__(
        self,
        slaves: Any,
        host: str = "127.0.0.1",
        port: int = 0,
        *,
        idle_timeout: float | None = 60.0,
        max_connections: int = 32,
        request_timeout: float = 5.0,
        logger: logging.Logger | None = None,
        framing: str = "tcp",
        quiet_gap: float = 0.03,
        tls: Any = None,
        handshake_timeout: float | None = None,
        authorization: Any = None,
    ) -> None:
        require_sockets("a Modbus/TCP server (TcpServer)")
        self.slaves = normalize_slaves(slaves)
        if framing not in FRAMINGS:
            raise ConfigError(
                f"framing must be one of {', '.join(FRAMINGS)} (tcp: MBAP; rtu/ascii: serial frames over "
                f"TCP, as a serial device server speaks them), got {shown(framing)}"
            )
        self.framing = framing
        _check_host(host, "listen on", "\"127.0.0.1\" (this computer only) or \"0.0.0.0\" (every interface)")
        if not _is_int(port) or not 0 <= port <= 65535:
            raise ConfigError(
                f"TCP port must be an integer 0..65535 (0: let the system choose), got {shown(port)}"
            )
        if idle_timeout is not None:
            idle_timeout = _positive_seconds(
                "idle_timeout", idle_timeout, "or None to keep silent clients connected forever"
            )
        request_timeout = _positive_seconds(
            "request_timeout", request_timeout, "(the time a request may take to arrive whole)")
        if not _is_int(max_connections) or max_connections < 1:
            raise ConfigError(
                "max_connections must be a whole number >= 1 (the clients served at once), "
                f"got {shown(max_connections)}"
            )
        if logger is not None and not isinstance(logger, (logging.Logger, logging.LoggerAdapter)):
            raise ConfigError(f"logger must be a logging.Logger or None, got {type(logger).__name__}")
        clock = RealClock()
        for slave in self.slaves.values():
            if getattr(slave, "clock", None) is None:
                slave.clock = clock  # time stamps for the slave's traffic log
        self.host = host
        self.port = port
        self.idle_timeout = idle_timeout
        self.max_connections = max_connections
        self.request_timeout = request_timeout
        self.quiet_gap = _positive_seconds("quiet_gap", quiet_gap,
                                           "(the pause that ends an RTU frame on TCP)")
        self.log = logger if logger is not None else _log
        # an asynchronous slave (a gateway) answers from its own thread: submit(frame, mode, reply)
        only = next(iter(self.slaves.values())) if len(self.slaves) == 1 else None
        self._submit = getattr(only, "submit", None)
        self._replies: deque[tuple[_Connection, bytes | None]] = deque()
        self.counters = TcpServerCounters()
        self._tls_setup(tls, handshake_timeout, authorization, framing, request_timeout)
        self._direct = framing == "tcp" and not (tls or authorization or self._submit)  # see _answer_directly
        self.lock = threading.RLock()
        self._listener: socket.socket | None = None
        self._selector: selectors.BaseSelector | None = None
        self._connections: dict[int, _Connection] = {}
        self._wake_r: socket.socket | None = None
        self._wake_w: socket.socket | None = None
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._closed = False
        self._backlog: dict[int, _Connection] = {}  # connections with a complete request still waiting
        self._accept_paused_until = 0.0
        self._accept_backoff = 0.0
        # at most the earliest connection deadline: lowered wherever one can move earlier (a connection, a
        # request begun, an answer delivered), so that _expire scans them all only once it is reached
        self._earliest = float("inf")
        self._warned: dict[str, tuple[float, int]] = {}  # key -> (last warning time, suppressed since)
        self.address: tuple[str, int] | None = None

    # ---------------------------------------------------------------- life cycle
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

    def start(self) -> TcpServer:
        """Bind the listening socket and serve from a background (daemon) thread. Returns self."""
        if self._closed:
            raise LinkError("this TcpServer was closed; create a new one to serve again")
        if self._thread is not None:
            return self
        self._bind()
        self._thread = threading.Thread(
            target=self._serve, name=f"modbus_edu TcpServer {self.address[0]}:{self.address[1]}", daemon=True
        )
        self._thread.start()
        return self

    def serve_forever(self) -> None:
        """Serve in the calling thread until :meth:`close` is called from another thread (or Ctrl-C)."""
        if self._thread is not None:
            raise LinkError("this TcpServer is already serving")
        self._bind()
        self._thread = threading.current_thread()  # so that close() from elsewhere waits for us
        try:
            self._serve()
        finally:
            self.close()

    def close(self) -> None:
        """Stop serving: close the listening socket and every connection, join the thread. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        self._wake()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=5.0)
            if thread.is_alive():  # pragma: no cover - only if a slave callback hangs
                self.log.error("TcpServer thread did not stop within 5 s")
        if thread is None or not thread.is_alive():
            self._cleanup()

    def __enter__(self) -> TcpServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __del__(self) -> None:  # pragma: no cover - best effort only
        try:
            if not self._closed and self._listener is not None and self._thread is None:
                self._cleanup()
        except Exception:
            pass

    @property
    def running(self) -> bool:
        """True while the server thread is serving."""
        return self._thread is not None and self._thread.is_alive() and not self._stop.is_set()

    @property
    def connection_count(self) -> int:
        """Number of clients connected right now."""
        return len(self._connections)

    @property
    def buffered_bytes(self) -> int:
        """Bytes the server holds for its clients right now: requests read and not yet answered (whole or
        in part) and answers not yet sent.  Bounded per connection, whatever the clients do."""
        return sum(len(c.outbuf) + len(c.splitter.pending) + sum(map(len, c.frames))
                   for c in list(self._connections.values()))

    #: The most :attr:`buffered_bytes` one connection can account for.
    MAX_BUFFERED_PER_CONNECTION = _MAX_PENDING_OUTPUT + _MAX_QUEUED * 260 + 3 * _READ_SIZE

    def __repr__(self) -> str:
        if self.address:
            where = f"{self.address[0]}:{self.address[1]}"
        else:
            where = f"{self.host}:{self.port} (not bound)"
        state = "running" if self.running else ("closed" if self._closed else "stopped")
        return f"<TcpServer {where} units={_units_text(self.slaves)} {state}>"

    def _wake(self) -> None:
        wake_w = self._wake_w  # the server thread may be closing it right now
        if wake_w is not None:
            try:
                wake_w.send(b"\0")
            except OSError:
                pass

    def _cleanup(self) -> None:
        for conn in list(self._connections.values()):
            self._drop(conn, None)
        if self._selector is not None:
            try:
                self._selector.close()
            except Exception:  # pragma: no cover
                pass
            self._selector = None
        for sock in (self._listener, self._wake_r, self._wake_w):
            if sock is not None:
                try:
                    sock.close()
                except OSError:  # pragma: no cover
                    pass
        self._listener = self._wake_r = self._wake_w = None

    # ---------------------------------------------------------------- the event loop
    def _serve(self) -> None:
        selector = self._selector
        assert selector is not None
        listener = self._listener
        wake_r = self._wake_r
        try:
            while not self._stop.is_set():
                timeout = 0.0 if self._backlog else self._next_deadline()
                for key, mask in selector.select(timeout):
                    sock = key.fileobj
                    if sock is listener:
                        self._accept()
                    elif sock is wake_r:
                        try:
                            wake_r.recv(4096)
                        except OSError:
                            pass
                        self._deliver_replies()
                    else:
                        conn = key.data
                        if mask & selectors.EVENT_WRITE and self._connections.get(conn.fd) is conn:
                            self._pump(conn)
                        if mask & selectors.EVENT_READ and self._connections.get(conn.fd) is conn:
                            self._read(conn)
                # one more request from each connection that has more waiting: a fair turn
                for fd, conn in list(self._backlog.items()):
                    del self._backlog[fd]
                    if self._connections.get(fd) is conn:
                        self._pump(conn)
                self._expire()
        except Exception:  # pragma: no cover - a bug: log it rather than die silently
            self.log.exception("Modbus/TCP server stopped by an unexpected error")
        finally:
            self._cleanup()

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

    # ---------------------------------------------------------------- asynchronous slaves (a gateway)
    def _hand_over(self, conn: _Connection, frame: bytes) -> None:
        """Give ``frame`` to the asynchronous slave; its reply comes back through :meth:`_reply_later`,
        from whatever thread it likes.  The connection's next request waits for it (answers keep the
        order of their requests)."""
        self.counters.requests += 1
        conn.awaiting = True

        def reply(data: bytes | None) -> None:
            self._replies.append((conn, data))
            self._wake()

        try:
            self._submit(frame, self.framing, reply)
        except Exception:
            self.log.exception("asynchronous slave failed on request %s", frame.hex(" "))
            conn.awaiting = False
            if self.framing == "tcp":
                conn.outbuf += exception_reply(frame, SERVER_DEVICE_FAILURE) or b""

    def _deliver_replies(self) -> None:
        """Hand the asynchronous slave's answers to their connections (dropped if the client has gone)."""
        while self._replies:
            conn, data = self._replies.popleft()
            if self._connections.get(conn.fd) is not conn:
                self.counters.late_replies += 1
                continue
            conn.awaiting = False
            conn.last_activity = time.monotonic()
            self._earliest = min(self._earliest, self._deadlines(conn))
            if data:
                self.counters.responses += 1
                conn.outbuf += data
            self._pump(conn)

    def _dispatch_serial(self, frame: bytes) -> bytes | None:
        """One RTU/ASCII request to the slave(s) it is for: a broadcast (unit 0) reaches all and is not
        answered; a unit nobody serves gets silence, as on a serial line (no 0x0B: no gateway here)."""
        self.counters.requests += 1
        unit = frame[0] if self.framing == "rtu" else int(frame[1:3], 16)
        owner = self.slaves.get(unit) or self.slaves.get(None)
        targets = list(self.slaves.values()) if unit == 0 else [owner]
        reply = None
        for slave in targets:
            if slave is None:
                self.counters.unknown_unit += 1
                continue
            try:
                with self.lock:
                    reply = slave.handle(frame, self.framing) or reply
            except Exception:
                self.log.exception("slave for unit %d failed on request %s", unit, frame.hex(" "))
        if unit == 0:
            return None
        if reply:
            self.counters.responses += 1
        return reply

    def _dispatch(self, frame: bytes) -> bytes | None:
        """One Modbus/TCP request to the slave it is for (:func:`~.routing.dispatch`); the reply."""
        self.counters.requests += 1
        reply, found = dispatch(self.slaves, frame, self.lock, self.log)
        if not found:
            self.counters.unknown_unit += 1
        if reply:
            self.counters.responses += 1
        return reply

    # ---------------------------------------------------------------- Modbus/TCP Security (tls=)
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
