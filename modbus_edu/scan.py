"""Scanning: who answers on a bus, at which unit ids and with which line settings.

:func:`scan` asks every unit id (1..247 by default) one harmless question - read holding register 0 -
under each line setting to try (baud rate, parity). Any answer, a normal response **or an exception
response** (02 illegal data address is common: the device has no register 0), proves a device is
there; silence (a timeout) or 0x0A/0x0B from a gateway means nobody. The scan is bounded in time:
``budget`` seconds on the link's clock, after which it stops and says how far it got.

The progress bar is tqdm's (the course uses tqdm: one small pure-Python dependency that works in a
terminal and in Jupyter alike).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from ._optional import load_tqdm
from .errors import (
    ConfigError,
    LinkError,
    ModbusError,
    ModbusExceptionError,
    ModbusTimeoutError,
    TransactionMismatchError,
    shown,
)
from .links.base import Link
from .master import Master
from .master_steps import Steps, arun_steps, run_steps

__all__ = ["ScanHit", "ScanReport", "ascan", "scan"]


@dataclass(frozen=True)
class ScanHit:
    """A device that answered: its ``unit``, the line ``settings`` it answered with, and what it said."""

    unit: int
    settings: dict[str, Any]
    answer: str


@dataclass
class ScanReport:
    """What a scan found (``hits``), how many questions it asked, and whether it ran out of time."""

    hits: list[ScanHit] = field(default_factory=list)
    asked: int = 0
    complete: bool = True
    elapsed: float = 0.0
    interrupted: bool = False
    late: int = 0
    """Answers that came after their question had timed out (another transaction's): not counted as
    units found, but a sign that the timeout is shorter than the device's (or the gateway's) answer."""

    def __iter__(self):
        return iter(self.hits)

    def __len__(self) -> int:
        return len(self.hits)


def _probe(master: Master, unit: int) -> Steps:
    """One unit's question, as steps (:mod:`modbus_edu.master_steps`): what it answered, or None."""
    try:
        regs = yield from master.read_steps(3, unit, 0, 1)
    except ModbusExceptionError as exc:
        if exc.code in (0x0A, 0x0B):  # a gateway saying: nobody there
            return None
        return f"exception {exc.code:02X} ({exc.meaning})"
    except (ModbusTimeoutError, LinkError, TransactionMismatchError):
        # TransactionMismatchError: only frames for other requests came (a late answer of the unit asked
        # before, through a gateway): that says nothing about this unit
        return None
    except ModbusError as exc:  # a garbled answer: something is there, maybe at other settings
        return f"garbled answer: {exc}"
    return f"register 0 = {regs[0]}"


def _scan_setting(master: Master, units: list[int], setting: dict[str, Any], budget: float,
                  report: ScanReport, bar: Any) -> Steps:
    """Every unit under one line setting, as steps; False once the budget is spent."""
    clock = master.link.clock
    start = clock.now
    try:
        for unit in units:
            if report.elapsed + (clock.now - start) >= budget:
                report.complete = False
                return False
            before = master.stats.mismatches
            answer = yield from _probe(master, unit)
            report.late += master.stats.mismatches - before
            report.asked += 1
            bar.update(1)
            if answer is not None:
                report.hits.append(ScanHit(unit, dict(setting), answer))
                bar.set_postfix(found=len(report.hits))
    finally:
        report.elapsed += clock.now - start
    return True


def scan(
    link: Link | Callable[..., Link],
    units: Iterable[int] = range(1, 248),
    *,
    settings: Sequence[dict[str, Any]] | None = None,
    timeout: float = 0.1,
    budget: float = 60.0,
    progress: bool = False,
    log: Any = None,
) -> ScanReport:
    """Ask every unit in ``units`` under every line setting; return who answered.

    ``link`` is a Link, or, to try line settings, a function called as ``link(**setting)`` for each
    dict in ``settings`` (e.g. ``lambda **s: mb.serial_link("/dev/ttyUSB0", **s)`` with
    ``settings=[{"baudrate": 9600, "parity": "N"}, {"baudrate": 19200, "parity": "E"}]``).
    ``timeout`` is each question's wait; ``budget`` bounds the whole scan (seconds on the link's clock).
    ``log``: a :class:`~modbus_edu.traffic.TrafficLog` that records every question and answer.
    A KeyboardInterrupt (Ctrl-C) ends the scan early: the report keeps what was found, with
    ``complete`` False and ``interrupted`` True.
    """
    units, settings, tqdm = _check(link, units, settings, timeout, budget)
    report = ScanReport()
    with _scanning(report, tqdm(total=len(units) * len(settings), disable=not progress, file=sys.stderr,
                                unit="unit")) as bar:
        for setting in settings:
            with _opened(link, setting) as current:
                if not run_steps(current, _scan_setting(_master(current, timeout, log), units, setting,
                                                        budget, report, bar)):
                    break
    return report


async def ascan(
    link: Link | Callable[..., Link],
    units: Iterable[int] = range(1, 248),
    *,
    settings: Sequence[dict[str, Any]] | None = None,
    timeout: float = 0.1,
    budget: float = 60.0,
    progress: bool = False,
    log: Any = None,
) -> ScanReport:
    """:func:`scan`, awaited: for a link whose bytes come through the event loop (the browser's serial
    port: ``await mb.ascan(port, range(1, 11))`` in a notebook cell). The same questions, the same
    report."""
    units, settings, tqdm = _check(link, units, settings, timeout, budget)
    report = ScanReport()
    with _scanning(report, tqdm(total=len(units) * len(settings), disable=not progress, file=sys.stderr,
                                unit="unit")) as bar:
        for setting in settings:
            with _opened(link, setting) as current:
                if not await arun_steps(current, _scan_setting(_master(current, timeout, log), units, setting,
                                                              budget, report, bar)):
                    break
    return report


@contextmanager
def _scanning(report: ScanReport, bar: Any) -> Iterator[Any]:
    """The progress bar while a scan runs; a KeyboardInterrupt (Ctrl-C) ends the scan keeping what it
    found (``complete`` False, ``interrupted`` True)."""
    try:
        yield bar
    except KeyboardInterrupt:
        report.complete = False
        report.interrupted = True
    finally:
        bar.close()


@contextmanager
def _opened(link: Link | Callable[..., Link], setting: dict[str, Any]) -> Iterator[Link]:
    """The link for one line setting: the given Link, or one opened for the setting and closed after."""
    current = link if isinstance(link, Link) else link(**setting)
    try:
        yield current
    finally:
        if current is not link:
            current.close()


def _master(link: Link, timeout: float, log: Any) -> Master:
    """The scan's master on one link, recording into ``log`` where one is given."""
    master = Master(link, timeout=timeout)
    if log is not None:
        master.log = log
    return master


def _check(link: Any, units: Iterable[int], settings: Sequence[dict[str, Any]] | None, timeout: float,
           budget: float) -> tuple[list[int], Sequence[dict[str, Any]], Any]:
    """The scan's settings, checked: (units, settings, tqdm)."""
    units = list(units)
    for u in units:
        if isinstance(u, bool) or not isinstance(u, int) or not 1 <= u <= 247:
            raise ConfigError(f"scan units must be 1..247 (0 is broadcast, nobody answers it), got "
                              f"{shown(u)}")
    if settings is None:
        settings = [{}]
    if isinstance(link, Link) and settings != [{}]:
        raise ConfigError("to try line settings, pass a function that opens a link for each setting")
    if not units:
        raise ConfigError("no unit ids to scan: give at least one, e.g. range(1, 248)")
    for name, value in (("timeout", timeout), ("budget", budget)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < math.inf:
            raise ConfigError(f"{name} must be a number of seconds above 0 (and finite), got {shown(value)}")
    return units, settings, load_tqdm()
