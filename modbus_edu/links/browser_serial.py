"""Modbus RTU and ASCII over the browser's serial port (the Web Serial API): a real device from a notebook
whose kernel runs on a server (Binder, a JupyterHub) or in the page (JupyterLite).

The kernel cannot see the learner's USB-RS-485 adapter: it is plugged into the laptop, and the kernel
runs somewhere else. The page can: in Chrome and Edge, ``navigator.serial.requestPort()`` asks the
learner for a port (a click is required), and the page reads and writes it. So the port is owned by the
page's JavaScript (a small widget, :class:`~modbus_edu.links.webserial_port.WebSerialPort`), and the
link in the kernel talks to that widget with the widget's messages::

    port = mb.browser_serial(baudrate=9600, parity="E")   # shows a "choose serial port" button
    port                                                  # (display it, click it, pick the adapter)
    master = mb.Master(port, timeout=1.0)
    await master.aread_holding_registers(unit=1, address=0, count=2)

**Where frames end.** The bytes come in bursts, as the adapter, the browser and the network deliver them,
with no line timing left in them. A frame is cut by its *expected length* (the function code and byte
count say how long it is, the CRC confirms it), by the library's own splitter
(:class:`~modbus_edu.links.serial._FrameCutter`, the one the pyserial link uses), and a silence of
``frame_gap`` seconds ends or drops whatever is left: t3.5 plus ``latency`` (default
:data:`BROWSER_LATENCY`, for the way from the adapter through the page and the network to the kernel).

**Why it is awaited (no deadlock).** The page's bytes reach the kernel as comm messages, and the kernel
handles messages on the same event loop that runs the learner's cells. A cell that *blocks* while it
waits for bytes stops that loop, so the bytes it waits for can never arrive: the cell would hang until
its timeout, every time. So the link waits by *awaiting* (:meth:`BrowserSerialLink.areceive`), and the
master has an awaitable form of every everyday call (``await master.aread_holding_registers(...)``,
:mod:`modbus_edu.master_steps`: the same transaction, only the waiting differs). While a cell awaits,
the loop goes on: ipykernel 7.4 dispatches ``comm_msg`` even while an async cell holds the shell
(``kernelbase.py``: "A running async cell may be waiting for a widget reply on this channel"), which is
what ipykernel issue #646 asked for; ipykernel 7.3 and older (the pin on Python 3.10) dispatch them only
between cells, so there an awaited call times out and its message says to poll from the test tool.
Polling in the background - the test tool's *start* and *read once*, tasks on the kernel's loop - works
on every kernel, since between polls the loop is free. A blocking call
(``master.read_holding_registers``) inside a kernel does not wait at all: it raises a
:class:`~modbus_edu.errors.LinkError` at once that says to ``await`` instead, rather than hang. Outside an
event loop (a script whose page side runs in another thread, as the tests' stand-in does), blocking
waits are allowed. Every wait ends at an absolute deadline.

**When things go wrong.** A port unplugged mid-frame: the page says so, and the wait ends at once with a
:class:`~modbus_edu.errors.LinkError` naming what had arrived. A wrong baud rate or parity: the device's
answers come garbled, no frame checks, the requests time out, and :meth:`BrowserSerialLink.summary`
says it in one line (timeouts, bytes that made no frame, the settings to check); the master's timeout
message carries the same hint. A browser without Web Serial (Firefox, Safari): the widget says so in
one line naming Chrome or Edge, and a request raises a one-line :class:`~modbus_edu.errors.LinkError`
that a notebook can print and go on.
"""

from __future__ import annotations

import asyncio
import html
import sys
import threading
import time
from collections import deque
from typing import Any

from .. import platform
from ..clock import RealClock
from ..errors import ConfigError, LinkError, guard_numbers, shown
from .serial import _CutLink, _FrameCutter, _timing
from .webserial_port import NO_WEB_SERIAL, make_port
from .wire import SerialTiming

__all__ = ["BROWSER_LATENCY", "BrowserSerialLink", "browser_serial"]

BROWSER_LATENCY = 0.25
"""Seconds added to t3.5 before a silence ends a frame whose length is unknown (or drops a broken one):
the way from the adapter through the browser and the network to a kernel on a server."""

MAX_TRANSCRIPT = 1000
"""The most entries :attr:`BrowserSerialLink.transcript` keeps (the newest)."""

#: The states the page reports, and what a request says in each when no port is open.
_NOT_OPEN = {
    "waiting": "no serial port chosen yet: press 'choose serial port' where the port is shown and pick "
               "the adapter (the browser's serial port needs Chrome or Edge)",
    "unavailable": NO_WEB_SERIAL,
    "lost": "the serial port was lost",
    "closed": "the serial port was closed: choose it again",
    "error": "the serial port could not be opened",
}


def _in_event_loop() -> bool:
    """True when this thread runs an asyncio loop (a Jupyter kernel's cells do): blocking here would
    stop the loop that brings the page's bytes."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return False
    return True


class BrowserSerialLink(_CutLink):
    """A :class:`~modbus_edu.links.base.Link` over the browser's serial port (made by
    :func:`browser_serial`).

    ``port`` is the page side: anything with ``write(data: bytes)`` and ``close()`` that hands what the
    page says to :meth:`deliver` (the widget does; the tests use a stand-in). The link's clock is real.
    """

    needs_await = True
    """Inside a Jupyter kernel, wait with ``await`` (``master.aread_holding_registers``, the test tool's
    polling): see the module's documentation."""

    def __init__(self, port: Any, timing: SerialTiming, *, frame_gap: float, role: str = "response") -> None:
        self.port = port
        self.timing = timing
        self.mode = timing.mode
        self.clock = RealClock()
        self.closed = False
        self.state = "waiting"
        """What the page says of its port: waiting, open, unavailable, lost, closed or error."""
        self.reason = ""
        """The page's own words for the last state (an error, a lost port), when it gave any."""
        self.port_info: dict[str, Any] = {}
        self.timeouts = 0
        """Waits that ended with no frame (each a request's timeout)."""
        self.stale = 0
        """Frames or bytes received outside a transaction and dropped before a new request."""
        self.bytes_in = 0
        self.bytes_out = 0
        self.transcript: deque[tuple[float, str, bytes]] = deque(maxlen=MAX_TRANSCRIPT)
        """(seconds since the link was made, "tx" or "rx", bytes): every write, and every burst of bytes
        as it came from the page."""
        self._start = time.monotonic()
        self._cutter = _FrameCutter(timing.mode, role, frame_gap)
        self._cond = threading.Condition()
        self._waiters: list[asyncio.Future[None]] = []

    # -- the page side -----------------------------------------------------------------------------------
    def deliver(self, content: dict[str, Any]) -> None:
        """What the page says: ``{"type": "data", "hex": "01 03 ..."}`` (bytes read from the port),
        ``"opened"``, ``"ready"``, ``"unavailable"``, ``"lost"``, ``"closed"``, ``"error"`` (with
        ``"reason"``). Called by the widget for each of its messages; safe from any thread."""
        if not isinstance(content, dict):
            return
        kind = content.get("type")
        with self._cond:
            if kind == "data":
                try:
                    data = bytes.fromhex(str(content.get("hex", "")))
                except ValueError:
                    return  # not bytes: nothing a port could have read
                now = time.monotonic()
                self.bytes_in += len(data)
                self.transcript.append((now - self._start, "rx", data))
                self._cutter.feed(data, now)
            elif kind in ("opened", "ready", "unavailable", "lost", "closed", "error"):
                self.state = {"opened": "open", "ready": "waiting"}.get(kind, kind)
                self.reason = str(content.get("reason", ""))[:300]
                if kind == "opened" and isinstance(content.get("info"), dict):
                    self.port_info = dict(content["info"])
            else:
                return
            self._cond.notify_all()
            waiters, self._waiters = self._waiters, []
        for waiter in waiters:
            waiter.get_loop().call_soon_threadsafe(_wake, waiter)

    # -- the master side ---------------------------------------------------------------------------------
    @property
    def description(self) -> str:
        return f"browser serial port, {self.timing}, {self.mode.upper()}"

    def _not_open(self) -> LinkError:
        why = _NOT_OPEN.get(self.state, f"the serial port is {self.state}")
        said = f" ({shown(self.reason, 160)})" if self.reason and self.state != "unavailable" else ""
        return LinkError(f"{why}{said}")

    def send(self, frame: bytes) -> None:
        """Drop stale input, then hand one frame to the page to write."""
        self._check_open()
        with self._cond:
            if self.state != "open":
                raise self._not_open()
            cutter = self._cutter
            self.stale += len(cutter.frames) + (1 if cutter.splitter.pending or cutter.burst else 0)
            cutter.reset()
            self.bytes_out += len(frame)
            self.transcript.append((time.monotonic() - self._start, "tx", bytes(frame)))
        try:
            self.port.write(bytes(frame))
        except Exception as exc:
            raise LinkError(f"{self.description}: cannot send: {exc}") from exc

    def _take(self, now: float) -> bytes | None:
        """A complete frame if there is one (the lock held); the port's loss raised once none is left."""
        cutter = self._cutter
        if not cutter.frames:
            cutter.check_silence(now)
        if cutter.frames:
            return cutter.frames.popleft()
        if self.state != "open":
            partial = bytes(cutter.burst)
            if partial:
                raise LinkError(
                    f"{self._not_open()} while a frame was arriving: {len(partial)} byte(s) had come "
                    f"({partial[:16].hex(' ')}{' ...' if len(partial) > 16 else ''}); plug the adapter "
                    "back in and choose the port again")
            raise self._not_open()
        return None

    def check_blocking(self) -> None:
        """Raise :class:`LinkError` if a blocking wait here would stop the loop that brings the page's
        bytes (this thread runs an event loop, as a kernel's cells do). The master asks before it sends."""
        if _in_event_loop():
            raise LinkError(
                "the browser's serial port cannot be waited for by a blocking call here: its bytes reach "
                "this kernel through the loop the call would block. Await the call instead, e.g. `await "
                "master.aread_holding_registers(unit=1, address=0, count=2)`, or poll from the test tool")

    def _gave_up(self, timeout: float) -> None:
        if timeout > 0:
            self.timeouts += 1

    def receive(self, timeout: float) -> bytes | None:
        """The next complete frame, or None if none is complete within ``timeout`` seconds.

        Inside an event loop (a kernel's cell) this cannot wait: the bytes come through that loop. Then a
        frame already cut is returned, and a wait raises :class:`LinkError` saying to ``await``."""
        self._check_open()
        deadline = time.monotonic() + max(0.0, timeout)
        with self._cond:
            while True:
                now = time.monotonic()
                frame = self._take(now)
                if frame is not None:
                    return frame
                if now >= deadline:
                    self._gave_up(timeout)
                    return None
                self.check_blocking()
                wake = deadline
                silence = self._cutter.silence_deadline()
                if silence is not None:
                    wake = min(wake, silence)
                self._cond.wait(max(0.0, wake - now))

    async def areceive(self, timeout: float) -> bytes | None:
        """:meth:`receive`, awaited: the event loop runs (and brings the page's bytes) while it waits.
        Ends at ``timeout`` seconds from now at the latest."""
        self._check_open()
        loop = asyncio.get_running_loop()
        deadline = time.monotonic() + max(0.0, timeout)
        while True:
            with self._cond:
                now = time.monotonic()
                frame = self._take(now)
                if frame is not None:
                    return frame
                if now >= deadline:
                    self._gave_up(timeout)
                    return None
                wake = deadline
                silence = self._cutter.silence_deadline()
                if silence is not None:
                    wake = min(wake, silence)
                waiter: asyncio.Future[None] = loop.create_future()
                self._waiters.append(waiter)
            try:
                await asyncio.wait((waiter,), timeout=max(0.0, wake - now))
            finally:
                with self._cond:
                    if waiter in self._waiters:
                        self._waiters.remove(waiter)
                waiter.cancel()

    async def asleep(self, seconds: float) -> None:
        """Let ``seconds`` pass without blocking the loop (the master's turnaround delay)."""
        await asyncio.sleep(max(0.0, seconds))

    def flush(self) -> None:
        """The page writes each frame at once; in RTU, let the 3.5-character silence after it pass."""
        self._check_open()
        if self.mode == "rtu" and not _in_event_loop():
            time.sleep(self.timing.t35)

    async def aflush(self) -> None:
        """:meth:`flush`, awaited."""
        self._check_open()
        if self.mode == "rtu":
            await asyncio.sleep(self.timing.t35)

    def silence_hint(self) -> str:
        """Why requests may go unanswered, in one clause ('' when nothing points anywhere)."""
        junk = self.discarded + len(self._cutter.burst)
        if junk:
            return (f"{junk} byte(s) came back that made no frame: the device answers, but not at "
                    f"{self.timing}; check the baud rate, parity and stop bits against the device's")
        if self.state == "open" and self.bytes_in == 0 and self.bytes_out:
            old = _kernel_without_comms_while_awaiting()
            if old:
                instead = (LITE_INSTEAD if old == PYODIDE_KERNEL else "use ipykernel 7.4 or later")
                return (f"nothing reached this kernel while the cell waited: {old} handles the page's "
                        f"messages only between cells; poll from the test tool, or {instead}")
            return ("nothing came back at all: check the unit id, the wiring (A/B, ground), the "
                    "adapter's direction control, and that the device is powered")
        return ""

    def summary(self) -> str:
        """One line: what went out, what came back, how many waits timed out, and what to check."""
        hint = self.silence_hint()
        return (f"{self.description}: {self.bytes_out} bytes sent, {self.bytes_in} received, "
                f"{self.timeouts} timeout{'' if self.timeouts == 1 else 's'}" + (f"; {hint}" if hint else ""))

    def close(self) -> None:
        """Ask the page to close the port. Closing twice is harmless."""
        if self.closed:
            return
        self.closed = True
        try:
            self.port.close()
        except Exception:  # noqa: BLE001 - closing is best effort
            pass
        self.deliver({"type": "closed"})

    # -- display: the port's button where the link is shown ----------------------------------------------
    @property
    def widget(self) -> Any:
        """The page's side, when it is a widget (what a notebook displays)."""
        return self.port

    def _repr_mimebundle_(self, **kwargs: Any) -> dict[str, Any]:
        """The widget's view where a page runs it; a still picture of its button (``text/html``) where
        none does (GitHub, a notebook opened without running it), and one line of text."""
        show = getattr(self.port, "_repr_mimebundle_", None)
        bundle = show(**kwargs) if show is not None else {}
        if isinstance(bundle, tuple):  # (data, metadata)
            bundle = bundle[0]
        bundle = dict(bundle or {})
        bundle["text/plain"] = f"{self.description}: {self.state}"
        bundle["text/html"] = (
            '<div class="mbe-webserial-picture"><button disabled>choose serial port</button> '
            f"<span>{html.escape(self.description)}: run this cell to use it, in Chrome or Edge</span></div>")
        return bundle


PYODIDE_KERNEL = "JupyterLite's Pyodide kernel"
LITE_INSTEAD = ("start the call as a task in one cell (task = asyncio.ensure_future(master.aread_...)) "
                "and read task.result() in the next")
"""What works in JupyterLite instead of a call awaited in one cell: the page's bytes arrive between cells."""


def _kernel_without_comms_while_awaiting() -> str:
    """'ipykernel X' when this runs in an ipykernel older than 7.4, which dispatches comm messages only
    between cells (not while a cell awaits); :data:`PYODIDE_KERNEL` in a browser (JupyterLite's kernel
    does the same: tests/test_lite.py sees it); '' otherwise (7.4 and later, another kernel, a script)."""
    if platform.IN_BROWSER:
        return PYODIDE_KERNEL
    kernel = sys.modules.get("ipykernel")
    version = str(getattr(kernel, "__version__", ""))
    parts = version.split(".")
    try:
        major, minor = int(parts[0]), int(parts[1])
    except (IndexError, ValueError):
        return ""
    return f"ipykernel {version}" if (major, minor) < (7, 4) else ""


def _wake(waiter: asyncio.Future[None]) -> None:
    if not waiter.done():
        waiter.set_result(None)


@guard_numbers
def browser_serial(
    baudrate: int = 9600,
    parity: str = "E",
    stopbits: float = 1,
    mode: str = "rtu",
    *,
    bytesize: int | None = None,
    latency: float | None = None,
    port: Any = None,
) -> BrowserSerialLink:
    """A master's Link over the browser's serial port (Chrome, Edge), with these line settings.

    Display the link in a notebook: it shows a *choose serial port* button; a click asks the browser for
    the port (the learner picks the adapter) and opens it at ``baudrate``, ``parity`` (``"N"``, ``"E"``,
    ``"O"``), ``stopbits`` and ``bytesize`` (default 8 for RTU, 7 for ASCII). ``mode`` is ``"rtu"`` or
    ``"ascii"``. Inside a kernel, wait with ``await``: ``await master.aread_holding_registers(...)``.
    ``latency`` is added to t3.5 before a silence ends a frame of unknown length (default
    :data:`BROWSER_LATENCY`). ``port`` replaces the page's widget (the tests' stand-in).
    """
    timing = _timing(baudrate, parity, stopbits, mode, bytesize)
    if latency is None:
        latency = BROWSER_LATENCY
    elif not float(latency) >= 0:
        raise ConfigError(f"latency must be >= 0 s, got {shown(latency)}")
    gap = timing.ascii_timeout if mode == "ascii" else timing.t35 + float(latency)
    page = port if port is not None else make_port(timing)
    link = BrowserSerialLink(page, timing, frame_gap=gap)
    listen = getattr(page, "listen", None)
    if listen is not None:
        listen(link.deliver)
    return link
