"""Modbus RTU and ASCII over real serial lines, through pyserial.

:func:`serial_link` opens a :class:`~modbus_edu.links.base.Link` for a master; :class:`SerialServer`
lets the course's slaves answer on a line from a background thread. Both take a pyserial *URL*, so
the same code runs on

* a real port: ``"/dev/ttyUSB0"``, ``"COM3"`` (a USB-RS485 adapter, an RS-232 cable);
* ``"loop://"``: pyserial's loopback, where everything sent comes back (one end only);
* ``"socket://host:port"``: a serial line carried over TCP - a "serial device server" in raw TCP
  mode, or a test peer such as a pymodbus server started with the RTU framer.

**Where an RTU frame ends.** On the wire, an RTU frame ends with 3.5 character times of silence
(1.75 ms above 19200 baud). A PC rarely sees that silence as it was: a USB adapter and the operating
system deliver bytes in bursts, milliseconds late, and over ``socket://`` there is no line timing at
all. So the links cut a frame by its *expected length* as soon as it is complete (the function code
and byte count say how long it is, the CRC confirms it: :class:`~modbus_edu.framing.RtuSplitter`),
and use silence as the backstop: after ``frame_gap`` seconds without a byte, whatever is pending is
a frame if its CRC checks (a function this library does not know, which the slave then answers with
exception 01) and is thrown away otherwise (a broken frame). ``frame_gap`` is t3.5 plus an allowance
for latency: 20 ms on a real port, 100 ms over a URL such as ``socket://`` (``latency=`` sets it).
ASCII frames carry their own delimiters, ``:`` and CR LF; the spec allows up to one second between
their characters.

**The listening end of a TCP "serial cable".** pyserial's ``socket://`` can only *connect*. To let a
serial peer (say, a pymodbus client with the RTU framer) connect to *us*, :class:`TcpSerialPort` is a
pyserial-like port that listens on a TCP port and carries the bytes of whichever client connects::

    with SerialServer(slave, TcpSerialPort("127.0.0.1", 0), mode="rtu") as server:
        host, port = server.port.address        # give these to the client
"""

from __future__ import annotations

import logging
import select
import socket
import threading
import time
from collections import deque
from dataclasses import dataclass, fields
from typing import Any

from ..clock import RealClock
from ..crc import crc16
from ..errors import ConfigError, LinkError, guard_numbers, shown
from ..framing import ASCII_MAX_FRAME, RTU_MAX_FRAME, splitter_for
from .base import READ_CHUNK, Link
from .routing import normalize_slaves
from .sockets import is_loopback_host
from .wire import SerialTiming

__all__ = [
    "SerialLink",
    "SerialServer",
    "SerialServerCounters",
    "TcpSerialPort",
    "open_serial",
    "serial_link",
]

_log = logging.getLogger("modbus_edu.serial")

#: How long one blocking read waits at most: the resolution of timeouts and of stopping a server.
_POLL = 0.01
#: Default allowance for the latency of USB adapters and the OS when timing silence on a real port.
DEFAULT_LATENCY = 0.020
#: The same allowance over a network URL (socket://, rfc2217://) or a port object: no line timing there.
NETWORK_LATENCY = 0.100


def _is_network_url(url: str) -> bool:
    """True for pyserial URLs that carry no line timing (socket://, loop://, rfc2217://, ...)."""
    return "://" in url


def _timing(baudrate: Any, parity: Any, stopbits: Any, mode: Any, bytesize: Any) -> SerialTiming:
    if mode not in ("rtu", "ascii"):
        raise ConfigError(
            f"a serial line carries 'rtu' or 'ascii' frames, got mode {shown(mode)} (Modbus/TCP: "
            f"use tcp_link)"
        )
    if bytesize is None:
        bytesize = 8 if mode == "rtu" else 7
    return SerialTiming(baudrate=baudrate, parity=parity, stopbits=stopbits, bytesize=bytesize, mode=mode)


try:
    import termios

    _OS_REFUSALS: tuple[type[BaseException], ...] = (termios.error,)
except (ImportError, AttributeError):  # Windows has no termios; Pyodide's stand-in has no termios.error
    _OS_REFUSALS = ()

try:
    import serial  # pyserial
except (ImportError, AttributeError):  # pragma: no cover - a dependency; a browser (Pyodide) may lack it
    serial = None


def open_serial(url: str, timing: SerialTiming, *, write_timeout: float | None = 2.0) -> Any:
    """Open a pyserial port (or URL) with the settings of ``timing``; raise LinkError saying why not."""
    if serial is None:  # pragma: no cover - pyserial is a dependency
        raise LinkError("serial links need pyserial: pip install pyserial")
    try:
        port = serial.serial_for_url(
            url,
            baudrate=int(timing.baudrate),
            bytesize=timing.bytesize,
            parity=timing.parity,
            stopbits=timing.stopbits,
            timeout=_POLL,
            write_timeout=write_timeout,
            do_not_open=True,
        )
        if _under_reports(port):
            # socket:// empties its input when it opens, reading until the peer pauses: a peer that
            # never pauses would hold open() forever. Drop input for DRAIN_SECONDS at most instead.
            port.reset_input_buffer = lambda: _drain(port)
        port.open()
        return port
    except ValueError as exc:  # pyserial: a setting the port does not support
        raise ConfigError(f"serial port {shown(url)} rejects the settings {timing}: {exc}") from exc
    except _OS_REFUSALS as exc:  # termios.error: the driver refused a setting (a pty and 7 data bits)
        raise LinkError(f"the operating system refused the settings {timing} for {shown(url)}: {exc} - the "
                        "port or adapter may not support this number of data bits, parity or baud rate"
                        ) from exc
    except (serial.SerialException, OSError) as exc:
        hint = (
            "is a server listening there?" if url.startswith("socket://")
            else "is the name right (COM3, /dev/ttyUSB0), is the adapter plugged in, "
                 "is another program using the port, may you open it (on Linux: the dialout group)?"
        )
        raise LinkError(f"cannot open serial port {shown(url)}: {exc} - {hint}") from exc


#: The longest a request spends dropping stale input: a peer still streaming is not waited out.
DRAIN_SECONDS = 0.1
DRAIN_CHUNK = 1 << 16
_DRAIN_PAUSE = 0.001


def _under_reports(port: Any) -> bool:
    """pyserial's ``socket://`` says ``in_waiting == 1`` whatever is queued (it only asks select)."""
    return type(port).__module__.endswith("protocol_socket")


def _read_now(port: Any, size: int) -> bytes:
    """Up to ``size`` bytes that have already arrived, without waiting for more."""
    if not _under_reports(port):
        return port.read(size)
    timeout = port.timeout
    port.timeout = 0  # socket:// reads what is queued, up to size, and returns at once
    try:
        return port.read(size)
    finally:
        port.timeout = timeout


def _read_available(port: Any, budget: int = READ_CHUNK) -> bytes:
    """Wait up to the port's timeout for one byte, then take what else has already arrived, up to
    ``budget`` bytes.

    The budget is what keeps a caller's deadline: a peer that never stops sending (a babbling device,
    junk over ``socket://``) is read a chunk at a time, and the caller checks its clock between chunks.
    Bytes are gathered in a bytearray, so a long read costs time in proportion to its length.
    """
    waiting = port.in_waiting
    data = bytearray(port.read(min(waiting, budget) if waiting > 0 else 1))
    while data and len(data) < budget and port.in_waiting:
        more = _read_now(port, budget - len(data))
        if not more:
            break
        data += more
    return bytes(data)


def _input_waiting(port: Any) -> bool:
    """Has input arrived? Over ``socket://``, a millisecond's grace: after a flood, more is on its way."""
    if _under_reports(port):
        return bool(select.select([port.fileno()], [], [], _DRAIN_PAUSE)[0])
    return port.in_waiting > 0


def _drain(port: Any, seconds: float = DRAIN_SECONDS) -> int:
    """Drop the input that has already arrived, for at most ``seconds``; return how many bytes.

    pyserial's ``reset_input_buffer`` over ``socket://`` reads until the peer pauses, which a peer that
    never pauses turns into a wait without end; this stops after ``seconds``, and what is left is read
    and skipped as junk like any other input."""
    end = time.monotonic() + seconds
    dropped = 0
    while _input_waiting(port):
        chunk = _read_now(port, DRAIN_CHUNK)
        if not chunk:
            break
        dropped += len(chunk)
        if time.monotonic() >= end:
            break
    return dropped


class _FrameCutter:
    """Bytes in, frames out, for one direction of a serial line: a splitter plus the silence rule.

    ``burst`` holds the bytes heard since the last frame was cut (or the last silence): in RTU, what
    a real receiver would call "the frame" when the line goes quiet.
    """

    #: Frames cut but not yet taken: a peer that sends faster than they are answered loses the oldest.
    MAX_FRAMES = 64

    def __init__(self, mode: str, role: str, frame_gap: float) -> None:
        self.splitter = splitter_for(mode, role)
        self.frame_gap = frame_gap
        self.last_byte = 0.0
        self.frames: deque[bytes] = deque(maxlen=self.MAX_FRAMES)
        self.burst = bytearray()
        # a frame ends at a silence only if it fits in one frame: older bytes of a burst can never
        # belong to it, so the burst keeps at most one frame's worth (its length is bounded)
        self.burst_limit = RTU_MAX_FRAME if mode == "rtu" else ASCII_MAX_FRAME
        self.dropped = 0
        """Frames cut but dropped because more than :attr:`MAX_FRAMES` were waiting."""

    def feed(self, data: bytes, now: float) -> None:
        self.last_byte = now
        cut = self.splitter.feed(data)
        if cut:
            self.dropped += max(0, len(self.frames) + len(cut) - self.MAX_FRAMES)
            self.frames.extend(cut)
            self.burst[:] = self.splitter.pending[-self.burst_limit:]  # what follows the last frame cut
        else:
            self.burst += data
            if len(self.burst) > self.burst_limit:
                del self.burst[: len(self.burst) - self.burst_limit]

    def silence_deadline(self) -> float | None:
        """When the bytes heard since the last frame end as a frame by silence (None: nothing heard)."""
        if not self.burst:
            return None
        return self.last_byte + self.frame_gap

    def check_silence(self, now: float) -> None:
        """The line has been quiet since the last byte: if long enough, the pending frame is over."""
        deadline = self.silence_deadline()
        if deadline is None or now < deadline:
            return
        splitter = self.splitter
        burst = bytes(self.burst)
        self.burst.clear()
        if (
            splitter.mode == "rtu"
            and len(burst) >= 4
            and crc16(burst[:-2]) == int.from_bytes(burst[-2:], "little")
        ):
            # Everything between two silences, CRC correct: a frame, even one whose length could not
            # be known from its first bytes (a function code this library does not implement: the
            # slave answers it with exception 01, illegal function). The splitter had set those
            # bytes aside as junk; they were not.
            discarded = max(0, splitter.discarded - (len(burst) - len(splitter.pending)))
            splitter.reset()
            splitter.discarded = discarded
            self.frames.append(burst)
        else:
            self.frames.extend(splitter.flush())  # cut what can be cut, drop the rest

    def reset(self) -> None:
        self.splitter.reset()
        self.frames.clear()
        self.burst.clear()

    @property
    def discarded(self) -> int:
        return self.splitter.discarded


# --------------------------------------------------------------------------------------------------
# the master's link
# --------------------------------------------------------------------------------------------------
class _CutLink(Link):
    """A serial line's link: what it receives is cut into frames by ``self._cutter``, a
    :class:`_FrameCutter` (shared by :class:`SerialLink` and the browser's serial link)."""

    _cutter: _FrameCutter

    @property
    def frame_gap(self) -> float:
        """Seconds of silence after the last byte that end a frame (see :func:`serial_link`)."""
        return self._cutter.frame_gap

    @property
    def discarded(self) -> int:
        """Received bytes that could not be part of a frame (noise, a wrong baud rate, broken frames)."""
        return self._cutter.discarded


class SerialLink(_CutLink):
    """A :class:`~modbus_edu.links.base.Link` over a pyserial port (made by :func:`serial_link`).

    ``role`` is the role of the frames this link *receives*: ``"response"`` for a master (the
    default), ``"request"`` for a listener on the slave side. Before each :meth:`send` the link
    forgets any input not yet received: on a half-duplex line a frame that arrives after its request
    timed out must not be taken for the answer to the next request (counted in :attr:`stale`).
    """

    def __init__(
        self,
        port: Any,
        timing: SerialTiming,
        *,
        role: str = "response",
        frame_gap: float,
        name: str | None = None,
    ) -> None:
        self.port = port
        self.timing = timing
        self.mode = timing.mode
        self.clock = RealClock()
        self.closed = False
        self.stale = 0
        """Frames or bytes received outside a transaction and dropped before a new request."""
        self._name = name or getattr(port, "portstr", None) or getattr(port, "port", None) or "serial port"
        self._cutter = _FrameCutter(timing.mode, role, frame_gap)

    @property
    def description(self) -> str:
        return f"serial {self._name}, {self.timing}, {self.mode.upper()}"

    def send(self, frame: bytes) -> None:
        """Drop stale input, then write one frame."""
        self._check_open()
        cutter = self._cutter
        stale = len(cutter.frames) + (1 if cutter.splitter.pending else 0)
        try:
            if _drain(self.port):
                stale += 1
            cutter.reset()
            self.port.write(frame)
            self.port.flush()
        except Exception as exc:
            raise LinkError(f"{self.description}: cannot send: {exc}") from exc
        self.stale += stale

    def receive(self, timeout: float) -> bytes | None:
        """The next complete frame, or None if none is complete within ``timeout`` seconds."""
        self._check_open()
        cutter = self._cutter
        deadline = time.monotonic() + max(0.0, timeout)
        while True:
            if cutter.frames:
                return cutter.frames.popleft()
            now = time.monotonic()
            cutter.check_silence(now)
            if cutter.frames:
                return cutter.frames.popleft()
            try:
                if now >= deadline:  # time is up: one last look at what has already arrived
                    if self.port.in_waiting:
                        cutter.feed(_read_now(self.port, READ_CHUNK), now)
                    return cutter.frames.popleft() if cutter.frames else None
                data = _read_available(self.port)
            except Exception as exc:
                raise LinkError(f"{self.description}: the line was lost while receiving: {exc}") from exc
            if data:
                cutter.feed(data, time.monotonic())

    def flush(self) -> None:
        """Wait until the bytes sent have left (and, in RTU, the 3.5-character silence after them)."""
        self._check_open()
        try:
            self.port.flush()
        except Exception as exc:
            raise LinkError(f"{self.description}: {exc}") from exc
        if self.mode == "rtu":
            time.sleep(self.timing.t35)

    def close(self) -> None:
        """Close the port. Closing twice is harmless."""
        if not self.closed:
            self.closed = True
            try:
                self.port.close()
            except Exception:  # pragma: no cover - closing is best effort
                pass


@guard_numbers
def serial_link(
    url: str,
    baudrate: int = 9600,
    parity: str = "N",
    stopbits: float = 1,
    mode: str = "rtu",
    *,
    bytesize: int | None = None,
    timeout: float = 2.0,
    role: str = "response",
    latency: float | None = None,
) -> SerialLink:
    """Open a serial line with pyserial's ``serial_for_url`` and return it as a master's Link.

    ``url``: a port name (``"COM3"``, ``"/dev/ttyUSB0"``) or a pyserial URL (``"loop://"``,
    ``"socket://127.0.0.1:5020"``). ``baudrate``, ``parity`` (``"N"``, ``"E"``, ``"O"``), ``stopbits``
    and ``bytesize`` (default 8 for RTU, 7 for ASCII) must match the device's settings exactly - a
    mismatch shows as garbage or nothing at all. ``mode``: ``"rtu"`` or ``"ascii"``. ``timeout`` bounds
    a write (a port whose flow control blocks); each request's own timeout is the master's.
    ``latency``: allowance added to t3.5 before a silence ends a frame whose length is unknown, or
    drops a broken one (default 20 ms on a real port, 100 ms over ``socket://`` and other URLs).

    >>> link = serial_link("loop://", 19200, "E", 1)     # doctest: +SKIP
    """
    timing = _timing(baudrate, parity, stopbits, mode, bytesize)
    if not isinstance(url, str) or not url:
        raise ConfigError(f"url must be a port name or a pyserial URL such as 'loop://', got {shown(url)}")
    gap = _frame_gap(url, timing, latency)
    port = open_serial(url, timing, write_timeout=timeout)
    return SerialLink(port, timing, role=role, frame_gap=gap, name=url)


def _frame_gap(url: str | None, timing: SerialTiming, latency: float | None) -> float:
    """Seconds of silence after the last byte that end (or give up) a frame.

    ASCII: the specification's 1 s between characters. RTU: t3.5 plus an allowance for the
    latency between the wire and this program: ``latency`` if given, else 20 ms on a real port and
    100 ms over a URL (``socket://``: a network has no line timing at all; ``url=None``: an object
    such as :class:`TcpSerialPort`).
    """
    if timing.mode == "ascii":
        return timing.ascii_timeout
    if latency is None:
        allowance = NETWORK_LATENCY if url is None or _is_network_url(url) else DEFAULT_LATENCY
    else:
        allowance = float(latency)
        if not allowance >= 0:
            raise ConfigError(f"latency must be >= 0 s, got {shown(latency)}")
    return timing.t35 + allowance


# --------------------------------------------------------------------------------------------------
# the slave side
# --------------------------------------------------------------------------------------------------
@dataclass
class SerialServerCounters:
    """What a :class:`SerialServer` has seen: ``frames`` cut from the line, ``responses`` written,
    ``no_slave`` frames for a unit nobody here serves (on a bus: someone else's business, no answer),
    ``failures`` slaves that raised while handling a frame."""

    frames: int = 0
    responses: int = 0
    no_slave: int = 0
    failures: int = 0

    def as_dict(self) -> dict[str, int]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


class SerialServer:
    """Slaves answering on a serial line, from a background thread.

    ``slaves``: a Slave, a list, or a dict unit -> Slave (all on the same line, as on an RS-485 bus).
    ``port``: a pyserial URL or port name (opened with the given settings), or an already open
    pyserial-like object (anything with ``read``, ``write``, ``in_waiting``, ``close``; its timeout
    should be short, as :class:`TcpSerialPort`'s is). The server closes the port when it stops.

    Each frame cut from the line goes to the slave of its unit; that slave's ``handle(frame, mode)``
    does all the protocol work. A frame for a unit nobody serves gets no answer (on a shared bus it
    is for another device); a broadcast (unit 0) is carried out by every slave and answered by none.
    A slave's :meth:`~modbus_edu.slave.Slave.response_delay` is honoured (really slept), so a slow
    device can be imitated on a real line.

    Use it as a context manager (``with SerialServer(...) as server:``) or call :meth:`start` and
    :meth:`close`.
    """

    def __init__(
        self,
        slaves: Any,
        port: Any,
        baudrate: int = 9600,
        parity: str = "N",
        stopbits: float = 1,
        mode: str = "rtu",
        *,
        bytesize: int | None = None,
        latency: float | None = None,
        logger: logging.Logger | None = None,
    ) -> None:
        self.slaves = normalize_slaves(slaves)
        self._any_unit = self.slaves.get(None)
        self.timing = _timing(baudrate, parity, stopbits, mode, bytesize)
        self.mode = mode
        self.log = logger if logger is not None else _log
        self.counters = SerialServerCounters()
        self.lock = threading.RLock()
        """Held while a slave handles a frame: hold it to change a served bank atomically."""
        clock = RealClock()
        for slave in self.slaves.values():
            if getattr(slave, "clock", None) is None:
                slave.clock = clock
        if isinstance(port, str):
            self._url: str | None = port
            gap = _frame_gap(port, self.timing, latency)
            self.port = open_serial(port, self.timing)
        else:
            if not all(hasattr(port, name) for name in ("read", "write", "close")):
                raise ConfigError(
                    f"port must be a pyserial URL or an open pyserial-like object, got {type(port).__name__}"
                )
            self._url = None
            gap = _frame_gap(None, self.timing, latency)
            if hasattr(port, "timeout") and (port.timeout is None or port.timeout > 0.1):
                port.timeout = _POLL  # short reads, so that the thread notices close()
            self.port = port
        self._cutter = _FrameCutter(mode, "request", gap)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._closed = False
        self.error: BaseException | None = None
        """The error that stopped the server thread, if one did."""

    @property
    def discarded(self) -> int:
        """Bytes heard on the line that could not be part of a frame."""
        return self._cutter.discarded

    def start(self) -> SerialServer:
        """Serve from a background (daemon) thread. Returns self."""
        if self._closed:
            raise LinkError("this SerialServer was closed; create a new one to serve again")
        if self._thread is None:
            self._thread = threading.Thread(target=self._serve, name="modbus_edu SerialServer", daemon=True)
            self._thread.start()
        return self

    def close(self) -> None:
        """Stop the thread and close the port. Idempotent."""
        if self._closed:
            return
        self._closed = True
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5.0)
        try:
            self.port.close()
        except Exception:  # pragma: no cover - best effort
            pass

    def __enter__(self) -> SerialServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    def __repr__(self) -> str:
        where = self._url or type(self.port).__name__
        state = "running" if self.running else ("closed" if self._closed else "stopped")
        return f"<SerialServer {where} {self.timing} {self.mode.upper()} {state}>"

    def _serve(self) -> None:
        cutter = self._cutter
        port = self.port
        try:
            while not self._stop.is_set():
                data = _read_available(port)
                now = time.monotonic()
                if data:
                    cutter.feed(data, now)
                else:
                    cutter.check_silence(now)
                while cutter.frames and not self._stop.is_set():
                    self._answer(cutter.frames.popleft())
        except Exception as exc:
            if not self._stop.is_set():
                self.error = exc
                self.log.error("serial server stopped: %s", exc)

    def _unit(self, frame: bytes) -> int | None:
        if self.mode == "rtu":
            return frame[0]
        try:
            return int(frame[1:3], 16)
        except ValueError:
            return None  # not hex: every slave sees it and drops it (and counts it)

    def _answer(self, frame: bytes) -> None:
        self.counters.frames += 1
        unit = self._unit(frame)
        if unit is None or unit == 0:
            targets = list(self.slaves.values())
        else:
            slave = self.slaves.get(unit, self._any_unit)
            if slave is None:
                self.counters.no_slave += 1
                return
            targets = [slave]
        for slave in targets:
            try:
                with self.lock:
                    reply = slave.handle(frame, self.mode)
                    delay = slave.response_delay(time.monotonic()) if reply else 0.0
            except Exception:
                self.counters.failures += 1
                self.log.exception("slave %r failed on frame %s", slave, frame.hex(" "))
                continue
            if reply:
                if delay > 0:
                    self._stop.wait(delay)
                self.counters.responses += 1
                self.port.write(reply)


# --------------------------------------------------------------------------------------------------
# the listening end of a serial line carried over TCP
# --------------------------------------------------------------------------------------------------
class TcpSerialPort:
    """A pyserial-like port that *listens* on TCP: the other end of a ``socket://`` serial line.

    Raw bytes, no MBAP: this is a serial line (RTU or ASCII frames) tunnelled through TCP, as a serial
    device server in "raw TCP" mode does it. The socket is bound on construction (``address`` tells
    the port chosen with ``port=0``); the first client that connects becomes the far end of the line.
    When it disconnects, the port waits for the next one. Reads follow pyserial's rules: ``read(n)``
    waits until ``n`` bytes or ``timeout`` seconds.
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 0, *, timeout: float | None = _POLL) -> None:
        self.timeout = timeout
        self._listener = socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET, socket.SOCK_STREAM)
        try:
            self._listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            self._listener.bind((host, port))
            self._listener.listen(1)
        except OSError as exc:
            self._listener.close()
            raise LinkError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from exc
        self.address: tuple[str, int] = self._listener.getsockname()[:2]
        self.portstr = f"tcp-listen://{self.address[0]}:{self.address[1]}"
        if not is_loopback_host(host):
            _log.warning(
                "serial line over TCP listening on %s:%d, beyond this computer: anyone who can reach it "
                "can read and write the devices on it (Modbus has no authentication); bind 127.0.0.1 "
                "unless that is what you want", self.address[0], self.address[1])
        self._client: socket.socket | None = None
        self.is_open = True

    def __repr__(self) -> str:
        peer = "connected" if self._client is not None else "waiting for a client"
        return f"<TcpSerialPort {self.address[0]}:{self.address[1]} {peer}>"

    @property
    def connected(self) -> bool:
        return self._client is not None

    def _ensure_client(self, wait: float | None) -> socket.socket | None:
        if self._client is not None:
            return self._client
        if not self.is_open:
            raise LinkError("TcpSerialPort is closed")
        ready, _, _ = select.select([self._listener], [], [], wait)
        if not ready:
            return None
        client, _ = self._listener.accept()
        client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._client = client
        return client

    def _drop_client(self) -> None:
        if self._client is not None:
            try:
                self._client.close()
            except OSError:  # pragma: no cover
                pass
            self._client = None

    @property
    def in_waiting(self) -> int:
        """Bytes that can be read at once (0 when no client is connected)."""
        client = self._ensure_client(0)
        if client is None:
            return 0
        ready, _, _ = select.select([client], [], [], 0)
        if not ready:
            return 0
        try:
            peek = client.recv(65536, socket.MSG_PEEK)
        except OSError:
            self._drop_client()
            return 0
        if not peek:  # the client left: the line is idle until the next one connects
            self._drop_client()
            return 0
        return len(peek)

    def read(self, size: int = 1) -> bytes:
        """Up to ``size`` bytes: waits until all have come or ``timeout`` has passed."""
        deadline = None if self.timeout is None else time.monotonic() + self.timeout
        out = bytearray()
        while len(out) < size:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            client = self._ensure_client(left)
            if client is None:
                break
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            ready, _, _ = select.select([client], [], [], left)
            if not ready:
                break
            try:
                chunk = client.recv(size - len(out))
            except OSError:
                chunk = b""
            if not chunk:
                self._drop_client()
                break
            out += chunk
            if deadline is not None and time.monotonic() >= deadline:
                break
        return bytes(out)

    def write(self, data: bytes) -> int:
        """Send to the connected client (bytes sent while nobody is connected are lost, as on a line)."""
        client = self._ensure_client(0)
        if client is None:
            return 0
        try:
            client.sendall(data)
        except OSError:
            self._drop_client()
            return 0
        return len(data)

    def flush(self) -> None:
        """Nothing to do: ``write`` hands every byte to the socket."""

    def reset_input_buffer(self) -> None:
        """Throw away the bytes received and not read yet (for at most :data:`DRAIN_SECONDS` while a
        client keeps sending)."""
        _drain(self)

    def close(self) -> None:
        """Disconnect the client and stop listening."""
        self.is_open = False
        self._drop_client()
        try:
            self._listener.close()
        except OSError:  # pragma: no cover
            pass

    def __enter__(self) -> TcpSerialPort:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()
