"""One transaction written once, run two ways: blocking (``master.read_holding_registers``) or awaited
(``await master.aread_holding_registers``).

The master's transaction (:meth:`~modbus_edu.master.Master.execute`: the turnaround delay, the stale
frames, the request, the wait for the answer, the retries) is written as a generator of *steps*: each
time it needs the wire to wait, it yields what it needs and gets the answer back:

``(RECEIVE, timeout)``
    the next frame within ``timeout`` seconds, or ``None``;
``(SLEEP, seconds)``
    nothing: just let the time pass (the turnaround delay);
``(FLUSH, None)``
    let what was sent leave the line (after a broadcast).

:func:`run_steps` performs them by calling the link (``link.receive``, ``clock.sleep``, ``link.flush``):
that is every link of the library, on its own clock. :func:`arun_steps` performs them with ``await``
where the link offers it (``link.areceive``, ``link.asleep``, ``link.aflush``) and falls back on the
blocking calls where it does not (a loopback link never waits for real).

Why both: a link whose bytes come through the kernel's own message loop - the browser's serial port,
:mod:`modbus_edu.links.browser_serial` - cannot be waited for by blocking, because blocking stops the
very loop that would bring the bytes. Awaiting lets the loop run while the transaction waits.
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any

from . import pdu as _pdu

__all__ = ["FLUSH", "RECEIVE", "SLEEP", "AsyncCalls", "Steps", "arun_steps", "run_steps"]

RECEIVE = "receive"
SLEEP = "sleep"
FLUSH = "flush"

Steps = Generator[tuple[str, Any], Any, Any]
"""A transaction as steps: yields ``(kind, argument)``, is sent each step's result, returns its own."""


def _perform(link: Any, kind: str, argument: Any) -> Any:
    if kind == RECEIVE:
        return link.receive(argument)
    if kind == SLEEP:
        link.clock.sleep(argument)
        return None
    link.flush()
    return None


async def _aperform(link: Any, kind: str, argument: Any) -> Any:
    waiter = getattr(link, "a" + kind, None)
    if waiter is None:  # a link that never waits for real (loopback) or has no awaitable form
        return _perform(link, kind, argument)
    return await (waiter(argument) if kind != FLUSH else waiter())


def run_steps(link: Any, steps: Steps) -> Any:
    """Run ``steps`` to their end, each wait a blocking call on ``link``; return what they return.

    An error raised by the link is thrown into the steps, so that their ``finally`` clauses run in order
    (the master notes when the transaction ended) before it reaches the caller. A link that cannot be
    waited for by blocking here (``link.check_blocking``: the browser's port inside a kernel) says so
    before anything is sent."""
    check = getattr(link, "check_blocking", None)
    if check is not None:
        check()
    try:
        step = next(steps)
        while True:
            try:
                result = _perform(link, *step)
            except Exception as exc:  # noqa: BLE001 - handed to the steps, which re-raise it
                step = steps.throw(exc)
            else:
                step = steps.send(result)
    except StopIteration as stop:
        return stop.value


async def arun_steps(link: Any, steps: Steps) -> Any:
    """Run ``steps`` to their end, awaiting each wait: the event loop runs (and brings the link's bytes)
    while the transaction waits."""
    try:
        step = next(steps)
        while True:
            try:
                result = await _aperform(link, *step)
            except Exception as exc:  # noqa: BLE001 - handed to the steps, which re-raise it
                step = steps.throw(exc)
            else:
                step = steps.send(result)
    except StopIteration as stop:
        return stop.value


class AsyncCalls:
    """The master's functions to ``await``: in a notebook cell, ``await master.aread_holding_registers(
    unit=1, address=0, count=2)``. Each does exactly what its blocking twin does (the same steps,
    counted in the same ``stats`` and ``log``); only the waiting differs. A link that needs them (the
    browser's serial port) says so with ``link.needs_await``."""

    link: Any

    def execute_steps(self, unit: int, request: Any, check: bool) -> Steps:  # pragma: no cover - Master's
        raise NotImplementedError

    def read_steps(self, function: int, unit: int, address: int, count: int) -> Steps:  # pragma: no cover
        raise NotImplementedError

    async def aexecute(self, unit: int, request: Any, *, check: bool = True) -> Any:
        """:meth:`~modbus_edu.master.Master.execute`, awaited."""
        return await arun_steps(self.link, self.execute_steps(unit, request, check))

    async def aread_once(self, function: int, unit: int, address: int, count: int) -> list:
        """One read with function 1, 2, 3 or 4, awaited."""
        return await arun_steps(self.link, self.read_steps(function, unit, address, count))

    async def aread_coils(self, unit: int, address: int, count: int) -> list[bool]:
        """FC 1, awaited: ``count`` coils from ``address``."""
        return await self.aread_once(1, unit, address, count)

    async def aread_discrete_inputs(self, unit: int, address: int, count: int) -> list[bool]:
        """FC 2, awaited: ``count`` discrete inputs from ``address``."""
        return await self.aread_once(2, unit, address, count)

    async def aread_holding_registers(self, unit: int, address: int, count: int) -> list[int]:
        """FC 3, awaited: ``count`` holding registers from ``address``."""
        return await self.aread_once(3, unit, address, count)

    async def aread_input_registers(self, unit: int, address: int, count: int) -> list[int]:
        """FC 4, awaited: ``count`` input registers from ``address``."""
        return await self.aread_once(4, unit, address, count)

    async def awrite_single_coil(self, unit: int, address: int, value: bool) -> None:
        """FC 5, awaited."""
        await self.aexecute(unit, _pdu.WriteSingleCoilRequest(address=address, value=value))

    async def awrite_single_register(self, unit: int, address: int, value: int) -> None:
        """FC 6, awaited."""
        await self.aexecute(unit, _pdu.WriteSingleRegisterRequest(address=address, value=value))

    async def awrite_multiple_coils(self, unit: int, address: int, values: Any) -> None:
        """FC 15, awaited."""
        await self.aexecute(unit, _pdu.WriteMultipleCoilsRequest(address=address, values=values))

    async def awrite_multiple_registers(self, unit: int, address: int, values: Any) -> None:
        """FC 16, awaited."""
        await self.aexecute(unit, _pdu.WriteMultipleRegistersRequest(address=address, values=values))
