"""Modbus/TCP between the roles of one notebook in a browser: an in-page server and its client links.

A web page cannot listen on a socket nor open one (JupyterLite runs the kernel on Pyodide, in the page).
But a notebook that starts a :class:`~modbus_edu.links.tcp_server.TcpServer` on 127.0.0.1 and points a
:func:`~modbus_edu.links.tcp_client.tcp_link` (or a test tool) at it only needs the two to meet inside
the same kernel.  So, in a browser (:data:`~modbus_edu.platform.IN_BROWSER`):

* ``TcpServer(slaves, host="127.0.0.1", port=0)`` gives an :class:`InPageTcpServer`: it "listens" on a
  port of this kernel's own table (port 0 picks the next free one from 49152, as a system would); its
  ``address``, ``counters``, ``lock``, ``start``/``close`` and context manager are the server's;
* ``tcp_link("127.0.0.1", port)`` to such a port gives an :class:`InPageTcpLink`: the in-memory loopback
  (:class:`~modbus_edu.links.loopback.LoopbackTcpLink`, on its virtual clock) to that server's slaves,
  routed by unit id as the server routes them, counted in the server's counters;
* what cannot work still refuses in one line (:class:`~modbus_edu.errors.BrowserError`): a server on
  another address than the loopback, a link to a real host, TLS, RTU or ASCII over TCP.  A loopback port
  where nothing listens is refused as a socket would be (:class:`~modbus_edu.errors.LinkError`).

The port table belongs to the kernel: two notebooks (two kernels) do not see each other's servers, as two
computers would not see each other's 127.0.0.1.
"""

from __future__ import annotations

import threading
from typing import Any

from ..clock import RealClock
from ..errors import BrowserError, ConfigError, LinkError, shown
from ..platform import BINDER
from .loopback import LoopbackTcpLink
from .routing import _units_text, normalize_slaves
from .sockets import _check_host, _is_int, is_loopback_host
from .tcp_connection import TcpServerCounters

__all__ = ["InPageTcpLink", "InPageTcpServer", "in_page_link", "in_page_server"]

#: The first port that ``port=0`` gives (the start of the dynamic ports, RFC 6335).
FIRST_FREE_PORT = 49152
_LISTENING: dict[int, InPageTcpServer] = {}
"""This kernel's port table: port -> the in-page server that listens there."""


def _refuse(what: str, why: str) -> BrowserError:
    return BrowserError(f"{what} needs a local Python or Binder ({BINDER}): this notebook runs in a web "
                        f"browser, where {why}")


def _check_in_page(what: str, host: Any, port: Any, framing: str, tls: Any) -> None:
    """What an in-page role can be: Modbus/TCP, no TLS, on a loopback address, a port 0..65535."""
    _check_host(host, "reach", "\"127.0.0.1\"")
    if not is_loopback_host(host):
        raise _refuse(what, f"only the roles of this page meet (on 127.0.0.1), not {host}: a web page "
                            "cannot listen on a socket or open a TCP connection to a device")
    if not _is_int(port) or not 0 <= port <= 65535:
        raise ConfigError(f"TCP port must be an integer 0..65535 (0: let the system choose), "
                          f"got {shown(port)}")
    if tls is not None:
        raise _refuse(what + " with TLS", "Python has no TLS to give (Modbus/TCP Security)")
    if framing != "tcp":
        raise _refuse(f"{what} with framing={framing!r}", "the roles of one page speak Modbus/TCP only")


class InPageTcpServer:
    """A Modbus/TCP server inside this browser tab's kernel (what ``TcpServer`` gives in a browser).

    It holds the slaves and a port of the kernel's table; the clients are :class:`InPageTcpLink`
    objects that :func:`in_page_link` connects to it.  The settings that only shape real sockets
    (``idle_timeout``, ``max_connections``, ``request_timeout``, ...) are accepted and have nothing to do.
    """

    def __init__(self, slaves: Any, host: str = "127.0.0.1", port: int = 0, *, framing: str = "tcp",
                 tls: Any = None, authorization: Any = None, **socket_settings: Any) -> None:
        what = "a Modbus/TCP server (TcpServer)"
        _check_in_page(what, host, port, framing, tls)
        if authorization is not None:
            raise _refuse(what + " with authorization=", "roles come from TLS certificates")
        self.slaves = normalize_slaves(slaves)
        clock = RealClock()
        for slave in self.slaves.values():
            if getattr(slave, "clock", None) is None:
                slave.clock = clock  # time stamps for the slave's traffic log, as TcpServer gives them
        self.host, self.port, self.framing = host, port, framing
        self.tls = None
        self.counters = TcpServerCounters()
        self.lock = threading.RLock()
        self.address: tuple[str, int] | None = None
        self._links: list[InPageTcpLink] = []
        self._closed = False

    def start(self) -> InPageTcpServer:
        """Take the port in this kernel's table (port 0: the next free one). Returns self."""
        if self._closed:
            raise LinkError("this TcpServer was closed; create a new one to serve again")
        if self.address is None:
            port = self.port or next(p for p in range(FIRST_FREE_PORT, 65536) if p not in _LISTENING)
            if port in _LISTENING:
                raise LinkError(f"cannot listen on {self.host}:{port}: another server of this page already "
                                "listens there; pick another port (port=0 picks a free one)")
            _LISTENING[port] = self
            self.address = (self.host if self.host != "localhost" else "127.0.0.1", port)
        return self

    def serve_forever(self) -> None:
        raise _refuse("serving forever (serve_forever)", "a cell that never ends would stop the page")

    def close(self) -> None:
        """Give the port back and reset every client's connection. Idempotent."""
        if self._closed:
            return
        self._closed = True
        if self.address is not None and _LISTENING.get(self.address[1]) is self:
            del _LISTENING[self.address[1]]
        for link in self._links:
            link.close()
        self._links.clear()

    def __enter__(self) -> InPageTcpServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    @property
    def running(self) -> bool:
        return self.address is not None and not self._closed

    @property
    def connection_count(self) -> int:
        return sum(not link.closed for link in self._links)

    def __repr__(self) -> str:
        where = (f"{self.address[0]}:{self.address[1]}" if self.address
                 else f"{self.host}:{self.port} (not bound)")
        state = "running" if self.running else ("closed" if self._closed else "stopped")
        return f"<TcpServer {where} in this page units={_units_text(self.slaves)} {state}>"

    def _connect(self) -> InPageTcpLink:
        link = InPageTcpLink(self)
        self._links = [old for old in self._links if not old.closed] + [link]
        self.counters.connections += 1
        return link


class InPageTcpLink(LoopbackTcpLink):
    """A client's connection to an :class:`InPageTcpServer`: the in-memory Modbus/TCP loopback to its
    slaves, on a virtual clock; requests and responses counted in the server's ``counters``."""

    def __init__(self, server: InPageTcpServer) -> None:
        super().__init__(list(server.slaves.values()))
        self.server = server
        self.peer = server.address

    def send(self, frame: bytes) -> None:
        if self.server._closed and not self.closed:
            self.close()
            raise LinkError(f"{self.description}: the server closed the connection")
        super().send(frame)

    def _serve(self, frame: bytes) -> None:
        self.server.counters.requests += 1
        with self.server.lock:
            super()._serve(frame)

    def _server_sends(self, answer: bytes, name: str) -> None:
        self.server.counters.responses += 1
        super()._server_sends(answer, name)

    @property
    def description(self) -> str:
        host, port = self.peer or ("?", 0)
        return f"Modbus/TCP to {host}:{port} inside this page (in memory, on a virtual clock)"


def in_page_server(slaves: Any = None, host: str = "127.0.0.1", port: int = 0, **settings: Any
                   ) -> InPageTcpServer:
    """What ``TcpServer(...)`` gives in a browser: an :class:`InPageTcpServer`, or a one-line refusal."""
    return InPageTcpServer(slaves, host, port, **settings)


def in_page_link(host: str, port: int = 502, *, framing: str = "tcp", tls: Any = None, **_: Any
                 ) -> InPageTcpLink:
    """What ``tcp_link(host, port)`` gives in a browser: a connection to the in-page server on that port,
    a :class:`~modbus_edu.errors.LinkError` if none listens there, a one-line refusal for a real host."""
    _check_in_page("a link to a Modbus/TCP device (tcp_link)", host, port, framing, tls)
    server = _LISTENING.get(port)
    if server is None:
        raise LinkError(f"cannot connect to {host}:{port}: connection refused (no TcpServer of this page "
                        "listens there: start one first, mb.TcpServer(slave).start())")
    return server._connect()
