"""Clocks: virtual time for the loopback links, real time for real ports and sockets.

A serial line is slow: one character at 9600 baud takes about a millisecond, and a Modbus RTU frame
ends with 3.5 character times of silence.  To *show* those timings exactly, and to replay ten minutes
of polling in a fraction of a second, the loopback links run on a :class:`VirtualClock`: an event
scheduler whose time only moves when someone asks it to.  Nothing sleeps for real on it.

The scheduler keeps a heap of ``(time, seq, timer, callback, args)`` entries.  ``seq`` is a counter, so
two events due at the same instant always run in the order they were scheduled: every run is the same.
(The heap holds plain tuples, which Python compares in C, and :meth:`VirtualClock.schedule` skips the
:class:`Timer` of a call nobody will cancel: a simulation runs tens of thousands of events a second.)

Both clocks offer ``now`` (seconds) and ``sleep(seconds)``; code that only needs those two (the master,
for its timeouts and its turnaround delay) works with either.

>>> clock = VirtualClock()
>>> seen = []
>>> _ = clock.call_later(0.002, seen.append, "second")
>>> _ = clock.call_later(0.001, seen.append, "first")
>>> clock.run_until(0.005)
False
>>> seen, clock.now
(['first', 'second'], 0.005)
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from heapq import heappop, heappush
from typing import Any, Protocol, runtime_checkable

from .errors import ConfigError, guard_numbers, shown

__all__ = ["Clock", "RealClock", "Timer", "VirtualClock"]


@runtime_checkable
class Clock(Protocol):
    """What the master and the links need from a clock: the time, and a way to let time pass."""

    @property
    def now(self) -> float: ...

    def sleep(self, seconds: float) -> None: ...


@dataclass(order=True, slots=True)
class Timer:
    """One scheduled call on a :class:`VirtualClock` (returned by ``call_at`` / ``call_later``).

    ``cancel()`` it to stop it from running.  Timers compare by ``(time, seq)``: the heap order.
    """

    time: float
    seq: int
    callback: Callable[..., Any] = field(compare=False)
    args: tuple = field(default=(), compare=False)
    cancelled: bool = field(default=False, compare=False)

    def cancel(self) -> None:
        """Do not run this call (it stays in the heap and is skipped when its time comes)."""
        self.cancelled = True


class VirtualClock:
    """Virtual time and an event scheduler, for deterministic simulation.

    ``now`` only advances inside :meth:`run_until`, :meth:`run_until_idle`, :meth:`step`,
    :meth:`advance` and :meth:`sleep`, and it jumps from event to event: a 1-second wait costs no real
    time at all.  Events due at the same virtual instant run in the order they were scheduled.
    """

    @guard_numbers
    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)
        self._heap: list[tuple[float, int, Timer | None, Callable[..., Any] | None, tuple]] = []
        self._seq = itertools.count()
        self.events_run = 0
        """How many callbacks have run (a cheap measure of simulation work)."""

    # -- reading the time ---------------------------------------------------------------------
    @property
    def now(self) -> float:
        """The current virtual time, in seconds since the clock was created (or ``start``)."""
        return self._now

    def __repr__(self) -> str:
        return f"VirtualClock(now={self._now:.6f} s, pending={self.pending})"

    # -- scheduling ---------------------------------------------------------------------------
    def call_at(self, when: float, callback: Callable[..., Any], *args: Any) -> Timer:
        """Run ``callback(*args)`` at virtual time ``when``.

        A time in the past is treated as "now": the call runs at the next opportunity, after the
        calls already due now.
        """
        if when.__class__ is not float:
            when = float(when)
        if when != when:  # NaN
            raise ConfigError("call_at: the time is NaN")
        if when < self._now:
            when = self._now
        seq = next(self._seq)
        timer = Timer(when, seq, callback, args)
        heappush(self._heap, (when, seq, timer, None, ()))
        return timer

    def schedule(self, when: float, callback: Callable[..., Any], *args: Any) -> None:
        """Like :meth:`call_at`, for a call that will never be cancelled: it returns no :class:`Timer`.

        What the virtual wire uses for its many events (cheaper: no object to build).  ``when`` is in
        seconds, like ``now``; a time in the past is treated as "now".
        """
        if when != when:  # NaN
            raise ConfigError("schedule: the time is NaN")
        if when < self._now:
            when = self._now
        heappush(self._heap, (when, next(self._seq), None, callback, args))

    def call_later(self, delay: float, callback: Callable[..., Any], *args: Any) -> Timer:
        """Run ``callback(*args)`` ``delay`` seconds from now (``delay`` >= 0)."""
        if delay < 0:
            raise ConfigError(f"call_later: the delay must be >= 0 s, got {shown(delay)}")
        return self.call_at(self._now + delay, callback, *args)

    def cancel(self, timer: Timer | None) -> None:
        """Cancel a scheduled call (``None`` and already-run timers are ignored)."""
        if timer is not None:
            timer.cancel()

    # -- inspecting ---------------------------------------------------------------------------
    def _prune(self) -> None:
        heap = self._heap
        while heap and heap[0][2] is not None and heap[0][2].cancelled:
            heappop(heap)

    @property
    def pending(self) -> int:
        """How many calls are scheduled and not cancelled."""
        return sum(1 for entry in self._heap if entry[2] is None or not entry[2].cancelled)

    @property
    def next_time(self) -> float | None:
        """The time of the next scheduled call, or ``None`` when nothing is scheduled."""
        self._prune()
        return self._heap[0][0] if self._heap else None

    # -- running ------------------------------------------------------------------------------
    def step(self) -> bool:
        """Run the next scheduled call, moving ``now`` to its time.  False when there was none."""
        self._prune()
        if not self._heap:
            return False
        when, _, timer, callback, args = heappop(self._heap)
        self._now = when
        self.events_run += 1
        if timer is None:
            callback(*args)  # type: ignore[misc]
        else:
            timer.callback(*timer.args)
        return True

    def run_until(self, when: float, stop: Callable[[], bool] | None = None) -> bool:
        """Run every call due at or before ``when``, then set ``now`` to ``when``.

        With ``stop``, check ``stop()`` before each call and after it: as soon as it is true, return
        True at once (``now`` is then the time of the last call run).  Returns False when ``when`` was
        reached.  A ``when`` in the past does nothing (time never goes backwards).
        """
        heap = self._heap
        if stop is not None and stop():
            return True
        while heap:
            due, _, timer, callback, args = heap[0]
            if timer is not None and timer.cancelled:
                heappop(heap)
                continue
            if due > when:
                break
            heappop(heap)
            self._now = due
            self.events_run += 1
            if timer is None:
                callback(*args)  # type: ignore[misc]
            else:
                timer.callback(*timer.args)
            if stop is not None and stop():
                return True
        if when > self._now:
            self._now = float(when)
        return False

    def run_until_idle(self, limit: float | None = None, max_events: int = 10_000_000) -> int:
        """Run calls until none is left (or the next is later than ``limit``); return how many ran.

        ``max_events`` guards against a callback that keeps rescheduling itself forever.
        """
        count = 0
        while count < max_events:
            nxt = self.next_time
            if nxt is None or (limit is not None and nxt > limit):
                break
            self.step()
            count += 1
        else:
            raise ConfigError(
                f"run_until_idle: still busy after {max_events} events (a callback that keeps "
                "rescheduling itself?); pass a time limit"
            )
        return count

    def advance(self, seconds: float) -> None:
        """Let ``seconds`` of virtual time pass, running whatever falls due."""
        if seconds < 0:
            raise ConfigError(f"advance: cannot go back in time ({shown(seconds)} s)")
        self.run_until(self._now + seconds)

    def sleep(self, seconds: float) -> None:
        """The same as :meth:`advance`: on a virtual clock, sleeping means letting events run."""
        if seconds > 0:
            self.advance(seconds)


class RealClock:
    """Wall time, for real serial ports and sockets: ``now`` is ``time.monotonic()`` since creation."""

    def __init__(self) -> None:
        self._start = time.monotonic()

    @property
    def now(self) -> float:
        """Seconds since this clock was created (monotonic: never jumps back)."""
        return time.monotonic() - self._start

    def sleep(self, seconds: float) -> None:
        """Really sleep (``time.sleep``)."""
        if seconds > 0:
            time.sleep(seconds)

    def __repr__(self) -> str:
        return f"RealClock(now={self.now:.6f} s)"
