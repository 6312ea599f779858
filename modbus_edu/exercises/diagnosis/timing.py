"""The serial line's timing as the value exercises ask for it: a transaction's time in milliseconds, the
transactions a line carries in a second, and the silence t3.5 itself.

Each is the shared procedure of :data:`.procedures.TRANSACTION_TIME` (or :data:`T35`) seen through one
more step (:func:`derived`): every perturbation of the transaction's time (10 bits a character with
parity, the silences left out, 3 characters for t3.5 ...) reads the same in 06.1, 06.3, 08.2 and 15.1,
whatever unit the exercise asks in; the slips of that unit (seconds for milliseconds, a time for a rate)
are the derived procedure's forms, tried on their own and on every perturbation.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...links.wire import SerialTiming
from .procedure import NOT_APPLICABLE, Perturbation, Procedure
from .procedures import TRANSACTION_TIME


def near(mine: Any, got: Any, rel: float = 2e-3) -> bool:
    """A learner's number (rounded as they like) is the procedure's, to ``rel``."""
    return (isinstance(got, (int, float)) and not isinstance(got, bool) and isinstance(mine, (int, float))
            and abs(mine - got) <= max(rel * abs(mine), 1e-12))


def derived(procedure: Procedure, concept: str, transform: Callable[[float], float],
            forms: tuple[Perturbation, ...] = ()) -> Procedure:
    """``procedure`` (a transaction's time) with ``transform`` applied to its answer and to every
    perturbation's, compared to 0.2 % (a learner rounds), with the slips of form ``forms``; and a frame
    counted one byte short, which gives what 3 characters for t3.5 gives (a verdict then names both)."""

    def through(compute: Callable[..., Any]) -> Callable[..., Any]:
        def changed(*args: Any) -> Any:
            value = compute(*args)
            return None if value is None or value is NOT_APPLICABLE else transform(value)
        return changed

    counted = (  # a frame of the question counted one byte short: the same total as 3 characters for t3.5
        Perturbation("response-one-short", "a response one byte short (a byte of it left out of the count)",
                     None, lambda b, p, s, q, r: procedure.right(b, p, s, q, r - 1)),
        Perturbation("request-one-short", "a request one byte short (a byte of it left out of the count)",
                     None, lambda b, p, s, q, r: procedure.right(b, p, s, q - 1, r)))
    return Procedure(
        concept, through(procedure.right),
        tuple(Perturbation(item.key, item.step, item.misconception, through(item.compute), item.fields,
                           item.also) for item in (*procedure.perturbations, *counted)),
        same=near, forms=forms)


TRANSACTION_MS = derived(
    TRANSACTION_TIME, "a transaction's time in milliseconds", lambda seconds: 1000 * seconds,
    forms=(Perturbation("seconds", "the time in seconds", "seconds-for-milliseconds", lambda ms: ms / 1000),
           Perturbation("microseconds", "the time in microseconds", "microseconds-for-milliseconds",
                        lambda ms: ms * 1000)))
"""A transaction's time in ms: (baudrate, parity, stopbits, request bytes, response bytes)."""

RATE = derived(
    TRANSACTION_TIME, "the most transactions per second", lambda seconds: 1 / seconds,
    forms=(Perturbation("time", "the time of one transaction, in seconds", "time-for-rate",
                        lambda rate: 1 / rate),
           Perturbation("time-ms", "the time of one transaction, in milliseconds", "time-for-rate",
                        lambda rate: 1000 / rate)))
"""Transactions per second on a line: (baudrate, parity, stopbits, request bytes, response bytes)."""


def _char(baudrate: int, parity: str, stopbits: int, bits: int | None = None) -> float:
    return (1 + 8 + (parity != "N") + stopbits if bits is None else bits) / baudrate


def _t35(chars: float, bits: int | None = None) -> Callable[..., float | None]:
    return lambda b, p, s: chars * _char(b, p, s, bits) if b <= 19200 else None


T35 = Procedure(
    "the silence t3.5",
    lambda b, p, s: SerialTiming(baudrate=b, parity=p, stopbits=s).t35,
    (
        Perturbation("parity-forgotten", "10 bits a character whatever the parity", "parity-bit-forgotten",
                     _t35(3.5, 10)),
        Perturbation("eight-bits", "8 bits a character (no start and stop bits)", "start-stop-forgotten",
                     _t35(3.5, 8)),
        Perturbation("one-character", "one character time", "one-character-for-t35", _t35(1)),
        Perturbation("t15", "1.5 characters (t1.5)", "t15-for-t35", _t35(1.5)),
        Perturbation("three-characters", "3 characters", "three-characters-for-t35", _t35(3)),
        Perturbation("fixed-below-19200", "the fixed 1.75 ms, which applies only above 19200 baud", None,
                     lambda b, p, s: 0.00175 if b < 19200 else None),
        Perturbation("fixed-at-19200", "the fixed 1.75 ms already at 19200 baud", "fixed-silence-at-19200",
                     lambda b, p, s: 0.00175 if b == 19200 else None),
        Perturbation("no-fixed-silence", "3.5 characters above 19200 baud", "fixed-silence-ignored",
                     lambda b, p, s: 3.5 * _char(b, p, s) if b > 19200 else None),
        Perturbation("t15-fixed", "t1.5's fixed 0.75 ms above 19200 baud", "t15-for-t35",
                     lambda b, p, s: 0.00075 if b > 19200 else None),
    ),
    same=near,
    forms=(Perturbation("milliseconds", "the silence in milliseconds", "milliseconds-for-seconds",
                        lambda seconds: 1000 * seconds),),
)
"""The silence that ends an RTU frame, in seconds: (baudrate, parity, stopbits)."""
