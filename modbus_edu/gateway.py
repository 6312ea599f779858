"""A Modbus/TCP-to-serial gateway: a role built from the two others.

In front, a :class:`~modbus_edu.links.tcp.TcpServer` accepts Modbus/TCP clients; behind, a
:class:`~modbus_edu.master.Master` polls the slaves on a serial ``link`` (a ``loopback_serial`` bus or a
real ``serial_link``). Each request's unit id chooses the serial slave; the PDU is forwarded unchanged
and the response goes back with the request's **transaction id** and unit id.

What the client sees when the serial side fails (*Modbus Application Protocol* V1.1b3, section 7):

* **0x0B gateway target device failed to respond** - the slave stayed silent (or only garbled
  answers came back) for the gateway's ``timeout`` on each of its ``retries + 1`` attempts;
* **0x0A gateway path unavailable** - no path to that unit: unit 0 (a serial broadcast, which nobody
  answers while the TCP client waits for an answer; nothing is sent, so it is not 0x0B: no device was
  asked and failed to respond), units 248-255 (reserved on a serial line), the
  serial port itself failing, or the gateway **overloaded**: more requests wait for the bus than it
  keeps (``max_queued_per_unit`` for one unit, ``max_queued`` in all), the case the *Modbus Messaging
  on TCP/IP Implementation Guide* (section 7) names for 0x0A; the client may ask again later.

**The timeout starts when the request has left**, as a serial-line master's response timeout does:
a silent unit costs the request's characters on the line plus ``timeout`` (at 9600 baud 8N1, an 8-byte
request takes 8.33 ms, so a 200 ms timeout ends 208.33 ms after the request began). Over a pyserial URL
such as ``socket://`` the bytes travel at network speed, with no line timing: there the timeout starts
when the request is written.

**One bus, many clients.** The serial bus carries one transaction at a time. The TCP server keeps
accepting and reading while the bus is busy: each request goes into its unit's queue, and one bus
thread serves the queues in turn, one request per unit per turn (round-robin). After a unit has failed
to answer, the next turn goes to a unit that answers, if one is waiting: however many clients wait on a
dead unit, a client of a live unit is served after at most about one ``timeout`` plus its own
transaction. Time one transaction yourself: request characters + 3.5 characters of silence + the
slave's processing + response characters + 3.5 characters, at the bus's character time
(:mod:`modbus_edu.links.wire`).

**A response reaches only the request that asked for it.** RTU and ASCII carry no transaction id: a
slave that answers after the gateway gave up on it would, on a bus that moved on, seem to answer the next
request to the same unit with the same function. So after a unit has timed out, the gateway sends it
nothing for ``late_window`` seconds (the gateway's ``timeout`` unless told otherwise) while the other
units' requests go first, and drops whatever comes in that window; and (on a line with timing) a
frame that arrives whole before the request it would answer has left the line is not taken for its
answer. Each dropped frame is counted in ``counters["late"]``. A slave slower than
``timeout + late_window`` still cannot be told apart from a prompt one: make the timeout longer than the
slowest answer on the bus.

**A lost line is reopened.** When the serial port fails (a ``socket://`` device server that went away,
a USB adapter unplugged), the gateway answers 0x0A and reopens the port when a request comes, with a
back-off (:data:`REOPEN_FIRST` seconds, doubling up to :data:`REOPEN_MAX`); meanwhile requests are
answered 0x0A at once. A link that reconnects by itself (``tcp_link(..., framing="rtu")``) is simply
tried again after the back-off; a link closed by its owner stays unavailable.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from .errors import (
    AddressRangeError,
    ConfigError,
    LinkError,
    ModbusError,
    ModbusTimeoutError,
    TransactionMismatchError,
    UnknownFunctionError,
    shown,
)
from .framing import TcpFrame, encode_frame
from .links.base import Link
from .links.routing import SERVER_DEVICE_FAILURE, exception_reply
from .links.tcp_server import TcpServer
from .master import Master
from .pdu import ExceptionResponse
from .platform import require_sockets

__all__ = ["GATEWAY_PATH_UNAVAILABLE", "GATEWAY_TARGET_FAILED", "TcpGateway"]

#: Exception code 0x0A: the gateway has no path to the target (or is overloaded: its queues are full).
GATEWAY_PATH_UNAVAILABLE = 0x0A
#: Exception code 0x0B: the target device behind the gateway failed to respond.
GATEWAY_TARGET_FAILED = 0x0B
#: Seconds before the first attempt to reopen a lost serial line; doubled after each failure ...
REOPEN_FIRST = 0.1
#: ... up to this many.
REOPEN_MAX = 2.0
_log = logging.getLogger("modbus_edu.gateway")
#: The longest the bus thread listens without looking at its queues (waiting out a late window).
_LISTEN_STEP = 0.01

Reply = Callable[[bytes | None], None]


class _Job:
    """One client's request waiting for the bus."""

    __slots__ = ("frame", "request", "unit", "reply", "queued_at")

    def __init__(self, frame: bytes, request: TcpFrame, reply: Reply, queued_at: float) -> None:
        self.frame = frame
        self.request = request
        self.unit = frame[6]
        self.reply = reply
        self.queued_at = queued_at


class _Forwarder:
    """What the TCP server sees as its one slave for every unit: an asynchronous slave (``submit``) that
    queues each request for its unit and answers from the bus thread."""

    unit = None  # answers any unit (see route_unit)

    def __init__(self, link: Link, *, timeout: float, retries: int, late_window: float,
                 max_queued_per_unit: int, max_queued: int) -> None:
        self.link = link
        self.line = _Line(link)
        self.master = Master(self.line, timeout=timeout, retries=retries)
        self.clock = link.clock
        self.timeout = self.master.timeout
        self.late_window = late_window
        self.max_queued_per_unit = max_queued_per_unit
        self.max_queued = max_queued
        self._cv = threading.Condition()
        self._queues: dict[int, deque[_Job]] = {}
        self._turns: deque[int] = deque()  # units with requests waiting, in the order of their turns
        self._queued = 0
        self._quiet_until: dict[int, float] = {}  # a unit that timed out gets nothing before this
        self._answering: set[int] = set()  # units whose latest transaction got an answer
        self._after_silence = False  # the latest transaction got no answer: an answering unit goes next
        self._line_down = False
        self._reopen_at = 0.0
        self._backoff = REOPEN_FIRST
        self._stop = False
        self._thread: threading.Thread | None = None
        self.forwarded = 0
        self.no_response = 0
        self.path_unavailable = 0
        self.overloaded = 0
        self.late = 0
        self.reopened = 0
        self.worst_wait: dict[int, float] = {}

    # ---------------------------------------------------------------- the server's side
    def submit(self, frame: bytes, mode: str, reply: Reply) -> None:
        """Take one Modbus/TCP request; ``reply`` is called once with its answer, from any thread."""
        unit = frame[6]
        if unit == 0 or unit > 247:
            self.path_unavailable += 1
            reply(exception_reply(frame, GATEWAY_PATH_UNAVAILABLE))
            return
        try:
            request = TcpFrame.decode(frame, role="request")
        except UnknownFunctionError:
            reply(exception_reply(frame, 0x01))
            return
        except AddressRangeError:
            reply(exception_reply(frame, 0x02))
            return
        except ModbusError:
            reply(exception_reply(frame, 0x03))
            return
        with self._cv:
            if self._line_down and time.monotonic() < self._reopen_at:
                self.path_unavailable += 1
                answer = exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
            elif (self._queued >= self.max_queued
                  or len(self._queues.get(unit, ())) >= self.max_queued_per_unit):
                self.overloaded += 1
                answer = exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
            else:
                queue = self._queues.get(unit)
                if queue is None:
                    queue = self._queues[unit] = deque()
                    self._turns.append(unit)
                queue.append(_Job(frame, request, reply, self.clock.now))
                self._queued += 1
                self._cv.notify()
                return
        reply(answer)

    def handle(self, frame: bytes, mode: str = "tcp") -> bytes | None:
        """The same, waiting for the answer (for a caller without ``submit``); None if none came within
        the time every queued request could take."""
        done = threading.Event()
        answer: list[bytes | None] = []

        def reply(data: bytes | None) -> None:
            answer.append(data)
            done.set()

        self.submit(frame, mode, reply)
        done.wait((self.timeout + self.late_window) * (self.master.retries + 1) * (self.max_queued + 1) + 5.0)
        return answer[0] if answer else None

    # ---------------------------------------------------------------- the bus thread
    def start(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(target=self._run, name="modbus_edu gateway bus", daemon=True)
            self._thread.start()

    def stop(self) -> None:
        with self._cv:
            self._stop = True
            self._cv.notify()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=(self.timeout + self.late_window) * (self.master.retries + 1) + 5.0)
        with self._cv:  # whatever is still queued gets no answer (the server has closed)
            jobs = [job for queue in self._queues.values() for job in queue]
            self._queues.clear()
            self._turns.clear()
            self._queued = 0
        for job in jobs:
            job.reply(None)

    def _run(self) -> None:
        while True:
            with self._cv:
                while not self._stop and not self._turns:
                    self._cv.wait()
                if self._stop:
                    return
                job, quiet_until = self._next_job()
            if job is None:
                self._listen_until(quiet_until)
            else:
                self._serve(job)

    def _next_job(self) -> tuple[_Job | None, float]:
        """The request whose turn it is (under the lock), or None and when the first late window ends.

        Round-robin: the first unit in ``_turns`` whose late window is over, except that after a
        transaction that got no answer a unit that answers goes first, if one is waiting."""
        now = self.clock.now
        ready = [u for u in self._turns if self._quiet_until.get(u, now) <= now]
        if not ready:
            return None, min(self._quiet_until[u] for u in self._turns)
        unit = ready[0]
        if self._after_silence:
            unit = next((u for u in ready if u in self._answering), unit)
        self._turns.remove(unit)
        queue = self._queues[unit]
        job = queue.popleft()
        self._queued -= 1
        if queue:
            self._turns.append(unit)
        else:
            del self._queues[unit]
        wait = now - job.queued_at
        if wait >= self.worst_wait.get(unit, 0.0):
            self.worst_wait[unit] = wait
        return job, now

    def _listen_until(self, until: float) -> None:
        """Nothing may be sent before ``until`` (a late window): listen to the line meanwhile, a short
        step at a time (a request for another unit may come), and drop what arrives."""
        step = min(max(0.0, until - self.clock.now), _LISTEN_STEP)
        try:
            if self.link.receive(step) is not None:
                self.late += 1
        except LinkError:
            self._lost()

    def _serve(self, job: _Job) -> None:
        """One transaction on the bus for ``job``, and its answer to the client (exception 04, server
        device failure, if the transaction failed in a way it should not: the bus thread carries on)."""
        try:
            answer = self._transact(job)
        except Exception:
            _log.exception("gateway failed on request %s", job.frame.hex(" "))
            answer = exception_reply(job.frame, SERVER_DEVICE_FAILURE)
        job.reply(answer)

    def _transact(self, job: _Job) -> bytes | None:
        frame, unit, request = job.frame, job.unit, job.request.pdu
        if self._line_down and not self._reopen():
            self.path_unavailable += 1
            return exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
        master, link, line = self.master, self.link, self.line
        stats = master.stats
        before = stats.mismatches + getattr(link, "stale", 0) + line.early
        # the timeout runs from the moment the request has left: its characters first, then the wait
        master.timeout = self.timeout + line.airtime(len(encode_frame(link.mode, unit, request)))
        self.forwarded += 1
        try:
            response = master.execute(unit, request, check=False)
        except LinkError:
            self._lost()
            self.path_unavailable += 1
            return exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
        except ModbusError as exc:  # timeout, CRC errors, mismatches on every attempt
            self.no_response += 1
            self._answering.discard(unit)
            self._after_silence = True
            if isinstance(exc, (ModbusTimeoutError, TransactionMismatchError)):
                # the answer may still come: nothing more to this unit until the late window is over
                self._quiet_until[unit] = self.clock.now + self.late_window
            return exception_reply(frame, GATEWAY_TARGET_FAILED)
        finally:
            self.late += stats.mismatches + getattr(link, "stale", 0) + line.early - before
        self._answering.add(unit)
        self._after_silence = False
        if response is None:  # pragma: no cover - unit 0 is refused in submit
            return None
        if (
            not isinstance(response, ExceptionResponse)
            and response.function_code != request.function_code
        ):
            return exception_reply(frame, GATEWAY_TARGET_FAILED)
        return TcpFrame(transaction_id=job.request.transaction_id, unit=unit, pdu=response).encode()

    # ---------------------------------------------------------------- a lost line
    def _lost(self) -> None:
        """The serial port failed: answer 0x0A to everything waiting, and reopen it after a back-off."""
        with self._cv:
            if not self._line_down:
                self._line_down = True
                self._backoff = REOPEN_FIRST
            self._reopen_at = time.monotonic() + self._backoff
            jobs = [job for queue in self._queues.values() for job in queue]
            self._queues.clear()
            self._turns.clear()
            self._queued = 0
        for job in jobs:
            self.path_unavailable += 1
            job.reply(exception_reply(job.frame, GATEWAY_PATH_UNAVAILABLE))

    def _reopen(self) -> bool:
        """Try to open the lost line again (if its back-off is over); True if it may carry a request."""
        if time.monotonic() < self._reopen_at or self.link.closed:
            return False
        port = getattr(self.link, "port", None)
        ok = True
        if port is not None and hasattr(port, "open"):  # a pyserial port: close it, open it again
            try:
                port.close()
            except Exception:  # pragma: no cover - closing a broken port is best effort
                pass
            try:
                port.open()
            except Exception:
                ok = False
        with self._cv:
            if ok:
                self._line_down = False
                self.reopened += 1
            else:
                self._backoff = min(REOPEN_MAX, 2 * self._backoff)
                self._reopen_at = time.monotonic() + self._backoff
        return ok


class _Line(Link):
    """The serial link as the gateway's Master uses it: a frame that arrives whole before the request
    sent last has left the line cannot be its answer, and is dropped (``early``)."""

    def __init__(self, link: Link) -> None:
        self.link = link
        self.mode = link.mode
        self.clock = link.clock
        self.left_at = float("-inf")
        self.early = 0

    def airtime(self, size: int) -> float:
        """Seconds ``size`` characters take to leave the line: 0 on a link without line timing (TCP,
        and pyserial's URLs such as ``socket://``, where bytes travel at network speed)."""
        timing = getattr(self.link, "timing", None)
        port = getattr(self.link, "port", None)
        if timing is None or type(port).__module__.startswith("serial.urlhandler."):
            return 0.0
        return size * timing.char_time

    def send(self, frame: bytes) -> None:
        self.link.send(frame)
        self.left_at = self.clock.now + self.airtime(len(frame))

    def receive(self, timeout: float) -> bytes | None:
        clock = self.clock
        deadline = clock.now + timeout
        while True:
            data = self.link.receive(max(0.0, deadline - clock.now))
            if data is None or clock.now >= self.left_at:
                return data
            self.early += 1

    def flush(self) -> None:
        self.link.flush()

    @property
    def closed(self) -> bool:  # type: ignore[override]
        return self.link.closed

    @property
    def description(self) -> str:
        return self.link.description


class TcpGateway:
    """Serve Modbus/TCP on ``host:port`` and forward each request to the slaves behind ``link``.

    ``timeout`` is how long the gateway waits for a serial slave once the request has left the line
    (seconds on the link's clock), and ``retries`` how often it asks again before answering 0x0B.
    ``late_window`` (default: ``timeout``) is how long a unit that did not answer is left alone while
    its answer may still come; ``max_queued_per_unit`` and ``max_queued`` bound the requests waiting for
    the bus (beyond them: exception 0x0A, the gateway overloaded). A context manager with ``.address``::

        bus = mb.loopback_serial([meter, arduino], baudrate=9600)
        with mb.TcpGateway(bus, timeout=0.1) as gw:
            with mb.tcp_link(*gw.address) as tcp:
                mb.Master(tcp).read_holding_registers(unit=2, address=0, count=2)
    """

    def __init__(
        self,
        link: Link,
        host: str = "127.0.0.1",
        port: int = 0,
        *,
        timeout: float = 0.5,
        retries: int = 0,
        late_window: float | None = None,
        max_queued_per_unit: int = 8,
        max_queued: int = 64,
        **server_options: Any,
    ) -> None:
        require_sockets("a Modbus gateway (TcpGateway)")
        for name, value in (("max_queued_per_unit", max_queued_per_unit), ("max_queued", max_queued)):
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ConfigError(f"{name} must be a whole number >= 1 (requests waiting for the bus), "
                                  f"got {shown(value)}")
        if late_window is not None and (isinstance(late_window, bool)
                                        or not isinstance(late_window, (int, float))
                                        or not 0 <= late_window < float("inf")):
            raise ConfigError(f"late_window must be a number of seconds >= 0 (or None: the timeout), "
                              f"got {shown(late_window)}")
        self.link = link
        self._forwarder = _Forwarder(
            link, timeout=timeout, retries=retries, max_queued_per_unit=max_queued_per_unit,
            max_queued=max_queued, late_window=float(timeout if late_window is None else late_window),
        )
        self.master = self._forwarder.master
        self.server = TcpServer(self._forwarder, host=host, port=port, **server_options)

    @property
    def address(self) -> tuple[str, int] | None:
        """The (host, port) the gateway listens on (after :meth:`start`)."""
        return self.server.address

    @property
    def counters(self) -> dict[str, int]:
        """Requests ``forwarded`` to the bus; answered 0x0B (``no_response``), 0x0A for want of a path
        (``path_unavailable``) and 0x0A because the queues were full (``overloaded``); frames from the bus
        that answered no request waiting for them and were dropped (``late``); times the lost serial line
        was ``reopened``."""
        f = self._forwarder
        return {
            "forwarded": f.forwarded,
            "no_response": f.no_response,
            "path_unavailable": f.path_unavailable,
            "overloaded": f.overloaded,
            "late": f.late,
            "reopened": f.reopened,
        }

    @property
    def worst_wait(self) -> dict[int, float]:
        """For each unit, the longest a request waited in its queue before its transaction began
        (seconds on the link's clock)."""
        return dict(self._forwarder.worst_wait)

    def start(self) -> TcpGateway:
        self._forwarder.start()
        self.server.start()
        return self

    def close(self) -> None:
        self.server.close()
        self._forwarder.stop()

    def __enter__(self) -> TcpGateway:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<TcpGateway {self.address} -> {self.link.description}>"
