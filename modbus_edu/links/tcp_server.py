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

The server is one class over three rooms: :mod:`~modbus_edu.links.tcp_listener` (the listening socket:
bind, accept, evict), :mod:`~modbus_edu.links.tcp_requests` (each connection's bytes and deadlines) and
:mod:`~modbus_edu.links.tcp_server_tls` (Modbus/TCP Security); this module holds its settings, its life
cycle, its loop and where each request goes (a slave, or an asynchronous slave such as a gateway).
"""

from __future__ import annotations

import logging
import selectors
import socket
import threading
import time
from collections import deque
from typing import Any

from .. import platform
from ..clock import RealClock
from ..errors import ConfigError, LinkError, guard_numbers, shown
from ..platform import require_sockets
from .in_page import in_page_server
from .routing import (
    SERVER_DEVICE_FAILURE,
    _units_text,
    dispatch,
    exception_reply,
    normalize_slaves,
)
from .sockets import FRAMINGS, _check_host, _is_int, _positive_seconds
from .tcp_connection import TcpServerCounters, _Connection
from .tcp_listener import _Listener
from .tcp_requests import _MAX_PENDING_OUTPUT, _MAX_QUEUED, _READ_SIZE, _Requests
from .tcp_server_tls import _ServerTls

__all__ = ["TcpServer", "TcpServerCounters"]

_log = logging.getLogger("modbus_edu.tcp")


class TcpServer(_Listener, _Requests, _ServerTls):
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

    def __new__(cls, *args: Any, **kwargs: Any) -> Any:
        """In a browser, the server of one page's roles (:mod:`~modbus_edu.links.in_page`) on a loopback
        address, or a one-line :class:`~modbus_edu.errors.BrowserError` for what a page cannot do."""
        if platform.IN_BROWSER:
            return in_page_server(*args, **kwargs)
        return super().__new__(cls)

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
