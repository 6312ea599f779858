"""Redraw a panel at most every so often while events come, and once after the last (:class:`Throttle`).

A slave can answer hundreds of requests a second; a panel that shows it needs to be redrawn a few
times a second, and once more after the traffic stops, so that it shows the end state.  Nothing here
knows Modbus: the test tool gives its redraw as the action.
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Callable
from typing import Any

from .common import running_loop

__all__ = ["FOLLOW_INTERVAL", "Throttle"]

FOLLOW_INTERVAL = 0.2
"""Seconds between two redraws of a panel that follows traffic (five a second: the eye sees it move)."""

Schedule = Callable[[float, Callable[[], None]], Any]
"""``schedule(delay, callback)`` runs ``callback`` after ``delay`` seconds; returns a handle with
``cancel()``."""


class Throttle:
    """Run ``action`` on the first :meth:`poke`, then at most once every ``interval`` seconds, and once
    more ``interval`` after a burst (the trailing run), so the last poke is never lost.

    Pokes may come from any thread (a server's): they are handed to the asyncio loop that was running
    when the throttle was made (a Jupyter kernel's), and ``action`` always runs there.  Without a loop (a
    script, a headless test) nothing could run the trailing action later, so every poke runs it at once,
    as :class:`~modbus_edu.widgets.common.Typing` applies typing at once there.

    Deterministic for tests: ``clock`` (seconds, ``time.monotonic`` by default) and ``schedule``
    (``loop.call_later`` by default) can be given; :meth:`flush` runs a waiting trailing action now and
    :attr:`pending` says whether one waits.
    """

    def __init__(self, action: Callable[[], None], interval: float = FOLLOW_INTERVAL, *,
                 clock: Callable[[], float] = time.monotonic, schedule: Schedule | None = None) -> None:
        self.action = action
        self.interval = interval
        self.clock = clock
        self._loop = running_loop()
        self._schedule = schedule
        self._last = -math.inf
        self._timer: Any = None
        self.runs = 0
        """How many times the action ran (leading and trailing)."""

    @property
    def pending(self) -> bool:
        """True while a trailing action waits."""
        return self._timer is not None

    def poke(self) -> None:
        """Something changed: run the action now, or once the interval since the last run is over."""
        loop = self._loop
        if loop is not None and not loop.is_running():  # that loop has ended (a test's): none now
            loop = None
        if self._schedule is None and loop is not None and running_loop() is not loop:
            with contextlib.suppress(RuntimeError):  # the kernel's loop is closed: no one is watching
                loop.call_soon_threadsafe(self.poke)
            return
        if self._timer is not None:
            return  # the trailing run will show this change too
        schedule = self._schedule or (loop.call_later if loop is not None else None)
        wait = self._last + self.interval - self.clock()
        if wait <= 0 or schedule is None:
            self._run()
        else:
            self._timer = schedule(wait, self._fire)

    def _fire(self) -> None:
        self._timer = None
        self._run()

    def _run(self) -> None:
        self._last = self.clock()
        self.runs += 1
        self.action()

    def flush(self) -> bool:
        """Run a waiting trailing action now; returns whether one waited."""
        if self._timer is None:
            return False
        self.cancel()
        self._run()
        return True

    def cancel(self) -> None:
        """Forget a waiting trailing action."""
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
