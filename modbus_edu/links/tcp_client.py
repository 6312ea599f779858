"""Modbus/TCP on real sockets, the client side: :func:`tcp_link` opens a
:class:`~modbus_edu.links.base.Link` to any Modbus/TCP server, for a :class:`~modbus_edu.master.Master`
to drive.

The frames are those :mod:`modbus_edu.links.tcp_server` describes (the MBAP header, the unit identifier
on TCP); ``tls=`` (a client context from :mod:`modbus_edu.security`) makes the link *Modbus/TCP
Security*, the handshake done by :func:`~modbus_edu.links.tls.client_handshake`.
"""

from __future__ import annotations

import select
import socket
import time
from collections import deque
from typing import Any

from .. import platform
from ..clock import Clock, RealClock
from ..errors import ConfigError, LinkError, guard_numbers, shown
from ..framing import splitter_for
from ..platform import require_sockets
from .base import READ_CHUNK, Link
from .in_page import in_page_link
from .sockets import FRAMINGS, _check_host, _close_socket, _is_int, _positive_seconds
from .tls import WOULD_BLOCK, SSLError, check_context, client_handshake, pending, tls_failure

__all__ = ["TcpLink", "tcp_link"]

#: The longest a request spends dropping stale input before it is sent.
DRAIN_SECONDS = 0.1
_DRAIN_SIZE = 1 << 16
_DRAIN_PAUSE = 0.001


class TcpLink(Link):
    """A :class:`~modbus_edu.links.base.Link` to a Modbus/TCP server over a real socket.

    Made by :func:`tcp_link`. Frames received are cut out of the TCP stream by the MBAP length field
    (:class:`~modbus_edu.framing.TcpSplitter`); matching a response to its request by transaction id
    is the master's job. If the server closes the connection (idle timeout, too many clients, a frame
    it could not parse), :meth:`receive` says so with a :class:`~modbus_edu.errors.LinkError`, and the
    next :meth:`send` connects again (counted in :attr:`reconnects`).

    With ``tls=`` (a client context, :func:`modbus_edu.security.client_context`) each connection is
    Modbus/TCP Security: TLS is negotiated right after connecting, within the connect ``timeout``.
    """

    mode = "tcp"

    def __init__(
        self,
        host: str,
        port: int = 502,
        *,
        timeout: float = 3.0,
        clock: Clock | None = None,
        framing: str = "tcp",
        tls: Any = None,
    ) -> None:
        self.tls = check_context(tls, "client")
        if framing not in FRAMINGS:
            raise ConfigError(f"framing must be one of {', '.join(FRAMINGS)}, got {shown(framing)}")
        self.mode = framing
        _check_host(host, "connect to", "\"192.168.1.50\" (a device's IP address) or \"localhost\"")
        if not _is_int(port) or not 1 <= port <= 65535:
            raise ConfigError(f"TCP port must be an integer 1..65535 (Modbus/TCP's own is 502), got "
                              f"{shown(port)}")
        timeout = _positive_seconds("connect timeout", timeout, "(how long to wait for the server)")
        self.host = host
        self.port = port
        self.timeout = timeout
        self.clock = clock if clock is not None else RealClock()
        self.reconnects = 0
        self.stale_bytes = 0
        """Bytes that arrived outside a transaction and were dropped before a request."""
        self.closed = False
        self._sock: socket.socket | None = None
        self._splitter = splitter_for(framing, "response")
        self._frames: deque[bytes] = deque()
        self._connect()

    @property
    def description(self) -> str:
        if self.mode != "tcp":
            return f"{self.mode.upper()} over TCP to {self.host}:{self.port}"
        if self.tls is not None:
            return f"Modbus/TCP Security (TLS) to {self.host}:{self.port}"
        return f"Modbus/TCP to {self.host}:{self.port}"

    @property
    def connected(self) -> bool:
        """True while the socket is open (the server may still close it at any moment)."""
        return self._sock is not None

    @property
    def local_address(self) -> tuple[str, int] | None:
        """This end's (host, port), or None when not connected."""
        return self._sock.getsockname()[:2] if self._sock is not None else None

    @property
    def discarded(self) -> int:
        """Bytes received that could not be part of a Modbus/TCP frame (bad MBAP header)."""
        return self._splitter.discarded

    def _connect(self) -> None:
        where = f"{self.host}:{self.port}"
        try:
            sock = socket.create_connection((self.host, self.port), timeout=self.timeout)
        except ConnectionRefusedError as exc:
            raise LinkError(
                f"cannot connect to {where}: connection refused - is a Modbus/TCP server listening there? "
                "(check the port: Modbus/TCP's own is 502, test servers often use 5020)"
            ) from exc
        except socket.gaierror as exc:
            raise LinkError(
                f"cannot connect to {where}: unknown host {self.host!r} ({exc.strerror}) - check the name "
                "or use an IP address"
            ) from exc
        except TimeoutError as exc:
            raise LinkError(
                f"cannot connect to {where}: no answer within {self.timeout:g} s - is the address right, "
                "is the device on, is a firewall in the way?"
            ) from exc
        except OSError as exc:
            raise LinkError(f"cannot connect to {where}: {exc.strerror or exc}") from exc
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        if self.tls is not None:
            sock = client_handshake(self.tls, sock, self.host, self.timeout)
        self._sock = sock
        self._splitter.reset()
        self._frames.clear()

    def _lost(self, why: str) -> LinkError:
        if self._sock is not None:
            _close_socket(self._sock)
            self._sock = None
        return LinkError(
            f"connection to {self.host}:{self.port} lost: {why} - a server closes a connection that "
            "stays idle too long, sends a malformed frame, or exceeds its client limit; the next "
            "request connects again"
        )

    def _refused(self, exc: OSError) -> LinkError:
        """The error for a TLS alert after the handshake: the server refused our certificate."""
        self._lost("")
        return LinkError(f"{self.host}:{self.port} refused this TLS connection: {_why(exc)}")

    def _drop_stale(self) -> None:
        """Throw away what arrived before this request: frames already cut, and the bytes waiting in
        the socket, read in large chunks without parsing them.  After a flood there may be megabytes
        queued; they go in milliseconds, so a request does not wait behind them.  A peer still sending
        after :data:`DRAIN_SECONDS` is not waited out: the rest is skipped while the request waits.
        A connection the server closed meanwhile is made again by :meth:`send`."""
        self._frames.clear()
        sock = self._sock
        if sock is None or not (pending(sock) or select.select([sock], [], [], 0)[0]):
            return
        self._splitter.reset()
        end = time.monotonic() + DRAIN_SECONDS
        try:
            sock.settimeout(0)
            # a short wait between chunks: on a busy connection more is usually already on its way
            while pending(sock) or select.select([sock], [], [], _DRAIN_PAUSE)[0]:
                data = sock.recv(_DRAIN_SIZE)
                if not data:  # the server closed the connection
                    break
                self.stale_bytes += len(data)
                if time.monotonic() >= end:
                    return
            else:
                return
        except WOULD_BLOCK:  # TLS: a record that held no data (a session ticket)
            return
        except SSLError as exc:  # an alert: the server refused this connection (do not try again)
            raise self._refused(exc) from exc
        except OSError:
            pass
        _close_socket(sock)
        self._sock = None

    def send(self, frame: bytes) -> None:
        """Send one frame; stale input is dropped first, and a connection the server had closed is made
        again."""
        self._check_open()
        self._drop_stale()
        if self._sock is None:
            self._connect()
            self.reconnects += 1
        assert self._sock is not None
        try:
            self._sock.settimeout(self.timeout)
            self._sock.sendall(frame)
        except OSError as exc:
            raise self._lost(f"sending failed ({_why(exc)})") from exc

    def receive(self, timeout: float) -> bytes | None:
        """The next complete frame from the server, or None if none is complete within ``timeout`` s."""
        self._check_open()
        frames = self._frames
        if frames:
            return frames.popleft()
        if self._sock is None:
            return None  # not connected: nothing can arrive (the next send connects again)
        sock = self._sock
        deadline = time.monotonic() + max(0.0, timeout)
        looked = False
        while True:
            remaining = deadline - time.monotonic()
            try:
                if remaining > 0:
                    sock.settimeout(remaining)
                elif looked or not (pending(sock) or select.select([sock], [], [], 0)[0]):
                    return None  # time is up (one last look was taken), whatever is still arriving
                else:
                    looked = True
                    sock.settimeout(0)  # TLS: what is readable may be a record without data (a ticket)
                data = sock.recv(READ_CHUNK)  # cut a little at a time: the deadline is looked at between
            except (TimeoutError, *WOULD_BLOCK):
                return None
            except SSLError as exc:  # TLS 1.3: the server refuses our certificate after the handshake
                raise self._refused(exc) from exc
            except OSError as exc:
                raise self._lost(f"receiving failed ({_why(exc)})") from exc
            if not data:
                if remaining <= 0:  # a look for stale frames: the next send() reconnects quietly
                    _close_socket(sock)
                    self._sock = None
                    return None
                raise self._lost("the server closed the connection")
            frames.extend(self._splitter.feed(data))
            if frames:
                return frames.popleft()

    def close(self) -> None:
        """Close the socket. Closing twice is harmless."""
        if self._sock is not None:
            _close_socket(self._sock)
            self._sock = None
        self.closed = True


@guard_numbers
def tcp_link(host: str, port: int = 502, *, timeout: float = 3.0, framing: str = "tcp", tls: Any = None
             ) -> TcpLink:
    """Connect to a Modbus/TCP server and return a :class:`TcpLink` (mode ``"tcp"``, real clock).

    ``timeout`` bounds the connection attempt; each request's own timeout is the master's.
    ``host`` is a name or an IP address as text (``5`` or ``None`` raise
    :class:`~modbus_edu.errors.ConfigError`, like any bad setting).
    A server that cannot be reached raises :class:`~modbus_edu.errors.LinkError` saying why::

        with mb.tcp_link("127.0.0.1", 5020) as link:
            master = mb.Master(link)
            master.read_holding_registers(unit=1, address=0, count=2)

    On TCP the IP address chooses the device: a device reached directly usually answers unit 0xFF (the
    recommended value), 0, or its own number; behind a gateway the unit is the serial slave's address.

    ``tls``: a client context (:func:`modbus_edu.security.client_context`) for Modbus/TCP Security
    (port 802 by convention); a handshake that fails (the server's certificate expired, another
    authority's, another host's; ours refused) raises :class:`~modbus_edu.errors.LinkError` saying why.
    """
    if platform.IN_BROWSER:  # the server of a role of this page, or a one-line BrowserError
        return in_page_link(host, port, framing=framing, tls=tls)
    require_sockets("a link to a Modbus/TCP device (tcp_link)")
    return TcpLink(host, port, timeout=timeout, framing=framing, tls=tls)


def _why(exc: OSError) -> str:
    """What a failed send or receive means; a TLS failure in words (:func:`tls_failure`)."""
    if isinstance(exc, SSLError):
        return tls_failure(exc, "our", "the server")
    return str(exc.strerror or exc)
