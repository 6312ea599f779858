"""Modbus/UDP: the MBAP framing of Modbus/TCP, one datagram per ADU.

UDP keeps datagram boundaries, so there is no stream to cut: a datagram must be exactly one MBAP frame
(protocol identifier 0, a length field of 2..254 that counts the rest of the datagram), checked on its
bytes as :func:`~modbus_edu.framing.detect_mode` checks them; any other datagram is dropped and
counted, never half-used. UDP does not resend:
a lost request or response is simply never answered, and the master's timeout and retries
(``Master(link, retries=...)``) take care of it.

* :class:`UdpServer` serves slaves on a UDP port (a context manager with ``.address``);
* :func:`udp_link` is a :class:`~modbus_edu.links.base.Link` to a Modbus/UDP server.
"""

from __future__ import annotations

import logging
import select
import socket
import threading
import time
from collections import deque
from typing import Any

from ..clock import Clock, RealClock
from ..errors import ConfigError, LinkError, shown
from ..framing.modes import _looks_like_mbap
from ..platform import require_sockets
from .base import Link
from .routing import dispatch, normalize_slaves
from .sockets import _check_host, _is_int, _positive_seconds, is_loopback_host

__all__ = ["UdpLink", "UdpServer", "udp_link"]

#: The largest datagram read: an MBAP ADU is at most 260 bytes, so anything longer is not Modbus.
_DATAGRAM = 2048
#: Requests a :class:`UdpServer` holds per source address (host, port) while it is busy; one more from
#: the same source pushes out that source's oldest (a master that retried wants its newest answered).
QUEUE_PER_SOURCE = 4
#: Source addresses a :class:`UdpServer` holds requests for; a datagram from one more source is dropped.
MAX_SOURCES = 1024
#: Datagrams a :class:`UdpServer` takes from its socket between two requests it serves.
DRAIN_PER_TURN = 1024
#: The receive buffer a :class:`UdpServer` asks of the kernel (bytes; the kernel may grant less): it
#: holds a flood's datagrams while the server thread waits for a processor.
RECEIVE_BUFFER = 1 << 22


def _one_frame(data: bytes) -> bytes | None:
    """The single MBAP frame a datagram must be, or None (no valid header, or bytes missing or left over)."""
    return data if _looks_like_mbap(data) else None


class UdpServer:
    """A Modbus/UDP server for the course's slaves, in a background thread.

    Routing by unit id is :class:`~modbus_edu.links.tcp.TcpServer`'s
    (:func:`~modbus_edu.links.routing.route_unit`): a unit nobody serves is answered 0x0B.
    ``bad_datagrams`` counts datagrams that were not one MBAP frame.

    **Fair to every source.**  UDP has no connection to hold a client back: one source can send faster
    than any server answers.  Served first come, first served, a flood from one port (junk or valid
    requests) fills the socket's buffer, and the kernel drops a legitimate master's datagrams with the
    flood's.  So the server empties its socket between any two requests it serves (at most
    :data:`DRAIN_PER_TURN` datagrams, junk dropped at once), keeps at most :data:`QUEUE_PER_SOURCE`
    requests per source address (:data:`MAX_SOURCES` sources), and serves the sources in turn, one
    request each: a flooding source waits its turn like any other, and a master's request is answered
    after at most one request of each other source.  ``dropped_datagrams`` counts the valid requests
    pushed out of a full queue or refused for lack of room for one more source.

    It binds the loopback address 127.0.0.1 unless told otherwise, and logs a warning when told
    otherwise, as :class:`~modbus_edu.links.tcp.TcpServer` does: Modbus has no authentication, and UDP
    adds **amplification**.  UDP has no handshake, so a request's source address can be forged, and the
    response, many times larger, goes to whoever the forger names.  Measured on this server (a
    Modbus/UDP datagram sent to it on 127.0.0.1, the answer's length divided by the request's): the
    largest FC 3 read, 125 registers, is a 12-byte request (7 bytes of MBAP header and a 5-byte PDU)
    that draws a 259-byte response (7 + 2 + 250): **21.6 x** (7.2 x counting the 28 bytes of IPv4 and
    UDP headers each datagram carries).  FC 1 of 2000 coils is the same; functions with shorter
    requests go further: FC 43/14 with a 240-byte object 256 / 11 = 23.3 x, FC 17 with a 200-byte server
    ID 210 / 8 = 26.3 x.  A Modbus/UDP server belongs on a closed network.
    """

    def __init__(self, slaves: Any, host: str = "127.0.0.1", port: int = 0) -> None:
        require_sockets("a Modbus/UDP server (UdpServer)")
        _check_host(host, "listen on", '"127.0.0.1"')
        if not _is_int(port) or not 0 <= port <= 65535:
            raise ConfigError(f"UDP port must be an integer 0..65535 (0 = any free port), got {shown(port)}")
        self.slaves = normalize_slaves(slaves)
        self.log = logging.getLogger("modbus_edu.udp")
        self.lock = threading.Lock()
        self.requests = 0
        self.responses = 0
        self.bad_datagrams = 0
        self.dropped_datagrams = 0
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, RECEIVE_BUFFER)
            self._sock.bind((host, port))
        except OSError as exc:
            self._sock.close()
            raise LinkError(f"cannot listen on UDP {host}:{port}: {exc.strerror or exc}") from exc
        if not is_loopback_host(host):  # said once it really listens, never for a failed bind
            self.log.warning(
                "Modbus/UDP server listening on %s:%d, which is reachable from other computers: Modbus "
                "has no authentication - anyone who can reach this port can read and write every "
                "register - and a forged source address turns each small request into a response up "
                "to 21.6 times larger sent to someone else. Use 127.0.0.1 unless you mean it.",
                *self._sock.getsockname()[:2])
        self._sock.setblocking(False)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    @property
    def address(self) -> tuple[str, int]:
        """The (host, port) the server listens on."""
        return self._sock.getsockname()[:2]

    def start(self) -> UdpServer:
        """Start serving in a background thread (idempotent)."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._serve, name="modbus-udp", daemon=True)
            self._thread.start()
        return self

    def close(self) -> None:
        """Stop serving and release the port (waits at most 2 s for the thread)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
            self._thread = None
        self._sock.close()

    def __enter__(self) -> UdpServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def _serve(self) -> None:
        # source address -> its waiting requests; the dict's order is the round: served, a source with
        # more waiting goes to the back
        queues: dict[Any, deque[bytes]] = {}
        while not self._stop.is_set():
            if not queues:
                try:
                    select.select([self._sock], [], [], 0.1)
                except (OSError, ValueError):
                    return  # socket closed
            if not self._drain(queues):
                return
            if not queues:
                continue
            peer = next(iter(queues))
            waiting = queues.pop(peer)
            frame = waiting.popleft()
            if waiting:
                queues[peer] = waiting
            reply = self._dispatch(frame)
            if reply:
                try:
                    self._sock.sendto(reply, peer)
                except OSError as exc:  # pragma: no cover - peer vanished
                    self.log.warning("reply to %s failed: %s", peer, exc)

    def _drain(self, queues: dict[Any, deque[bytes]]) -> bool:
        """Take what the socket holds (at most DRAIN_PER_TURN datagrams) into the sources' queues;
        False once the socket is closed."""
        for _ in range(DRAIN_PER_TURN):
            try:
                data, peer = self._sock.recvfrom(_DATAGRAM)
            except (BlockingIOError, InterruptedError):
                return True
            except OSError:
                return False
            frame = _one_frame(data)
            if frame is None:
                self.bad_datagrams += 1
                continue
            waiting = queues.get(peer)
            if waiting is None:
                if len(queues) >= MAX_SOURCES:
                    self.dropped_datagrams += 1
                    continue
                waiting = queues[peer] = deque(maxlen=QUEUE_PER_SOURCE)
            elif len(waiting) == QUEUE_PER_SOURCE:
                self.dropped_datagrams += 1  # the oldest goes
            waiting.append(frame)
        return True

    def _dispatch(self, frame: bytes) -> bytes | None:
        self.requests += 1
        reply, _found = dispatch(self.slaves, frame, self.lock, self.log)
        if reply:
            self.responses += 1
        return reply


class UdpLink(Link):
    """A Link to a Modbus/UDP server: each frame one datagram, each datagram received one frame."""

    mode = "tcp"

    def __init__(self, host: str, port: int = 502, *, clock: Clock | None = None) -> None:
        _check_host(host, "send to", '"192.168.1.50" or "localhost"')
        if not _is_int(port) or not 1 <= port <= 65535:
            raise ConfigError(f"UDP port must be an integer 1..65535 (Modbus's own is 502), got "
                              f"{shown(port)}")
        self.host = host
        self.port = port
        self.clock = clock if clock is not None else RealClock()
        self.closed = False
        self.discarded = 0
        self._sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            self._sock.connect((host, port))
        except OSError as exc:
            self._sock.close()
            raise LinkError(f"cannot address UDP {host}:{port}: {exc.strerror or exc}") from exc

    @property
    def description(self) -> str:
        return f"Modbus/UDP to {self.host}:{self.port}"

    def send(self, frame: bytes) -> None:
        """Send one frame as one datagram."""
        self._check_open()
        try:
            self._sock.send(frame)
        except OSError as exc:
            raise LinkError(f"sending to UDP {self.host}:{self.port} failed: {exc.strerror or exc}") from exc

    def receive(self, timeout: float) -> bytes | None:
        """The next datagram that is one valid MBAP frame, or None within ``timeout`` seconds."""
        self._check_open()
        deadline = time.monotonic() + max(0.0, timeout)
        while True:
            remaining = deadline - time.monotonic()
            try:
                self._sock.settimeout(max(remaining, 1e-4))
                data = self._sock.recv(_DATAGRAM)
            except (TimeoutError, BlockingIOError, InterruptedError):
                return None
            except ConnectionRefusedError:
                # ICMP port unreachable from an earlier datagram: nobody listens; the request is lost
                if remaining <= 0:
                    return None
                continue
            except OSError as exc:
                raise LinkError(f"receiving from UDP {self.host}:{self.port} failed: {exc}") from exc
            frame = _one_frame(data)
            if frame is not None:
                return frame
            self.discarded += len(data)
            if remaining <= 0:
                return None

    def close(self) -> None:
        """Close the socket. Closing twice is harmless."""
        if not self.closed:
            self._sock.close()
        self.closed = True


def udp_link(host: str, port: int = 502, *, timeout: float = 3.0) -> UdpLink:
    """A :class:`UdpLink` to a Modbus/UDP server (mode ``"tcp"``: MBAP frames; real clock).

    ``timeout`` is accepted for symmetry with :func:`~modbus_edu.links.tcp.tcp_link` (UDP has no
    connection to wait for); each request's timeout is the master's, and its retries resend lost
    datagrams::

        with mb.udp_link("127.0.0.1", port) as link:
            mb.Master(link, retries=2).read_holding_registers(unit=1, address=0, count=2)
    """
    require_sockets("a link to a Modbus/UDP device (udp_link)")
    _positive_seconds("timeout", timeout, "(seconds)")
    return UdpLink(host, port)
