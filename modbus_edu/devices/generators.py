"""Dummy data for registers: the fill tools of a test tool's data grid, and signals that change in time.

The robot test-tool paper's test tool fills its data grid three ways -- *random fill*, *fill* with a start
value and an increment, and *auto fill* with random data every second -- and wishes for sensor simulation
(values that change incrementally or randomly) and noise on top of sensor values.  This module provides all of
that, with two rules that make a notebook's output the same on every run:

* **Seeded.** Every random value comes from ``random.Random(seed)``; the same seed gives the same data.
* **No wall clock, no threads.** A generator is a function of time, ``value(t)``; you (or a device, or
  :class:`AutoFill`) pass the time, usually ``link.clock.now`` of a virtual clock.

Every value is a register value, an int within 0..65535: ramps, sines and noise are rounded and
clamped (a ramp can wrap instead).  For a bit table (coils, discrete inputs) the fill functions give
bools, and :class:`AutoFill` writes the lowest bit of each value.  Signed or wide quantities: generate
the number yourself and convert it with :func:`modbus_edu.values.encode_value`.
"""

from __future__ import annotations

import math
import operator
import random
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..datamodel import Table
from ..errors import ConfigError, shown

__all__ = [
    "Generator",
    "Constant",
    "Ramp",
    "Sine",
    "Noise",
    "Uniform",
    "AutoFill",
    "random_fill",
    "increment_fill",
    "clamp_register",
]

REGISTER_MAX = 0xFFFF


def clamp_register(x: float) -> int:
    """Round ``x`` to the nearest int (halves to even) and clamp it to 0..65535."""
    if math.isnan(x):
        return 0
    if x <= 0:
        return 0
    if x >= REGISTER_MAX:
        return REGISTER_MAX
    return int(round(x))


def _steps(t: float, period: float) -> int:
    """How many whole periods fit in ``t``; rounded to 1e-9 first so that 0.1 * 30 counts as 3 periods."""
    return math.floor(round(t / period, 9))


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(f"{name} must be a number, got {type(value).__name__} {shown(value)}")
    if not math.isfinite(value):
        raise ConfigError(f"{name} must be finite, got {shown(value)}")
    return value


def _positive(name: str, value: Any) -> float:
    value = _number(name, value)
    if value <= 0:
        raise ConfigError(f"{name} must be more than 0 seconds, got {shown(value)}")
    return value


def _register_bound(name: str, value: Any) -> int:
    try:
        if isinstance(value, (bool, float)):
            raise TypeError
        v = operator.index(value)
    except TypeError:
        raise ConfigError(f"{name} must be a whole number 0..65535, got {shown(value)}") from None
    if not 0 <= v <= REGISTER_MAX:
        raise ConfigError(f"{name} must be within 0..65535 (a register), got {v}")
    return v


def _bounds(low: Any, high: Any) -> tuple[int, int]:
    low, high = _register_bound("low", low), _register_bound("high", high)
    if low > high:
        raise ConfigError(f"low ({low}) must not be above high ({high})")
    return low, high


def _rng(seed: Any) -> random.Random:
    if isinstance(seed, random.Random):
        return seed
    if seed is None or isinstance(seed, (bool, float)) or not isinstance(seed, (int, str, bytes)):
        raise ConfigError(
            f"seed must be an int (or str, or a random.Random), got {shown(seed)}: the same seed gives "
            f"the same data on every run"
        )
    return random.Random(seed)


def _keyed_rng(*key: Any) -> random.Random:
    """A Random seeded from ``key``: the same key gives the same numbers on every run and machine.

    (A str seed is hashed with SHA-512, independent of PYTHONHASHSEED.)
    """
    return random.Random(":".join(repr(k) for k in key))


class Generator:
    """A register value as a function of time: ``value(t, channel=0)`` -> int 0..65535.

    ``channel`` tells apart the addresses one generator feeds (``AutoFill`` passes 0, 1, 2, ...):
    random generators give each channel its own sequence, the others ignore it.  Subclasses implement
    :meth:`raw`, the unclamped signal.
    """

    def raw(self, t: float, channel: int = 0) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    def value(self, t: float, channel: int = 0) -> int:
        """The register value at time ``t`` (seconds): rounded, clamped to 0..65535."""
        return clamp_register(self.raw(_time(t), channel))

    def values(self, t: float, count: int) -> list[int]:
        """``count`` values at time ``t``, one per channel 0..count-1."""
        return [self.value(t, i) for i in range(count)]

    def __call__(self, t: float, channel: int = 0) -> int:
        return self.value(t, channel)


@dataclass(frozen=True)
class Constant(Generator):
    """Always ``level``."""

    level: float = 0

    def __post_init__(self) -> None:
        _number("level", self.level)

    def raw(self, t: float, channel: int = 0) -> float:
        return self.level


def _time(t: Any) -> float:
    """A time in seconds, checked: a finite number (the clocks' ``now``)."""
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not math.isfinite(t):
        raise ConfigError(f"a generator's time is a finite number of seconds (a clock's now), got {shown(t)}")
    return float(t)


@dataclass(frozen=True)
class Ramp(Generator):
    """A value that grows by ``step`` every ``period`` seconds: ``start + step * floor(t / period)``.

    It stays within ``low .. high``: clamped there (``wrap=False``, the default) or, with ``wrap=True``,
    starting again from ``low`` after ``high`` like a counter (with the defaults, modulo 65536).
    A negative ``step`` ramps down.
    """

    start: int = 0
    step: int = 1
    period: float = 1.0
    low: int = 0
    high: int = REGISTER_MAX
    wrap: bool = False

    def __post_init__(self) -> None:
        _number("start", self.start)
        _number("step", self.step)
        _positive("period", self.period)
        _bounds(self.low, self.high)

    def raw(self, t: float, channel: int = 0) -> float:
        v = self.start + self.step * _steps(t, self.period)
        if self.wrap:
            span = self.high - self.low + 1
            v = self.low + math.floor(v - self.low) % span
        return min(max(v, self.low), self.high)


@dataclass(frozen=True)
class Sine(Generator):
    """``base + amplitude * sin(2 pi t / period + phase)``: a mains-like or daily swing.

    ``Sine(base=2300, amplitude=50, period=60)`` swings a "x10" voltage between 225.0 and 235.0 V once a
    minute.  Values below 0 or above 65535 are clamped.
    """

    base: float = 32768
    amplitude: float = 1000
    period: float = 60.0
    phase: float = 0.0

    def __post_init__(self) -> None:
        _number("base", self.base)
        _number("amplitude", self.amplitude)
        _positive("period", self.period)
        _number("phase", self.phase)

    def raw(self, t: float, channel: int = 0) -> float:
        return self.base + self.amplitude * math.sin(2 * math.pi * t / self.period + self.phase)


@dataclass(frozen=True)
class Noise(Generator):
    """Gaussian noise of standard deviation ``sigma`` around ``base`` -- a number or another generator
    (``Noise(Sine(2300, 50, 60), sigma=3, seed=1)`` is a noisy sensor).

    ``value(t)`` depends only on ``seed``, ``channel`` and ``t``, never on how often or in which order
    you ask: asking twice for the same ``t`` gives the same value.
    """

    base: float | Generator = 32768
    sigma: float = 100.0
    seed: int = 0

    def __post_init__(self) -> None:
        if not isinstance(self.base, Generator):
            _number("base", self.base)
        if _number("sigma", self.sigma) < 0:
            raise ConfigError(f"sigma (the standard deviation) must not be negative, got {shown(self.sigma)}")
        _rng(self.seed)

    def raw(self, t: float, channel: int = 0) -> float:
        centre = self.base.raw(t, channel) if isinstance(self.base, Generator) else self.base
        return centre + _keyed_rng("noise", self.seed, channel, float(t)).gauss(0.0, self.sigma)


@dataclass(frozen=True)
class Uniform(Generator):
    """A new random value in ``low .. high`` every ``period`` seconds (the "auto fill" of the robot test-tool
    paper).

    The value for period ``k = floor(t / period)`` depends only on ``seed``, ``channel`` and ``k``.
    """

    low: int = 0
    high: int = REGISTER_MAX
    seed: int = 0
    period: float = 1.0

    def __post_init__(self) -> None:
        _bounds(self.low, self.high)
        _positive("period", self.period)
        _rng(self.seed)

    def raw(self, t: float, channel: int = 0) -> float:
        return _keyed_rng("uniform", self.seed, channel, _steps(t, self.period)).randint(self.low, self.high)


# --- grid fills -----------------------------------------------------------------------------------
def _check_table(table: Any) -> Table:
    if not isinstance(table, Table):
        raise ConfigError(
            f"expected a table such as bank.holding_registers, got {type(table).__name__} {shown(table)}"
        )
    return table


def _count(count: Any) -> int:
    if isinstance(count, bool) or not isinstance(count, int) or count < 0:
        raise ConfigError(f"count must be a whole number 0 or more, got {shown(count)}")
    return count


def random_fill(
    table: Table, address: int, count: int, seed: Any, low: int = 0, high: int = REGISTER_MAX
) -> list:
    """Fill ``count`` elements from ``address`` with random values and return them.

    Registers get uniform ints in ``low .. high``; bits get random bools (``low``/``high`` ignored).
    ``seed`` (an int, or a ``random.Random`` to continue its sequence) makes it reproducible:
    the same seed writes the same values.  Errors of the table (an undeclared address of a sparse
    bank, a range past 65535) propagate as they are, and then nothing is written.
    """
    table = _check_table(table)
    count = _count(count)
    low, high = _bounds(low, high)
    rng = _rng(seed)
    if table.is_bits:
        values: list = [rng.getrandbits(1) == 1 for _ in range(count)]
    else:
        values = [rng.randint(low, high) for _ in range(count)]
    table.write(address, values)
    return values


def increment_fill(table: Table, address: int, count: int, start: int = 0, step: int = 1) -> list:
    """Fill ``count`` elements from ``address`` with ``start, start+step, start+2*step, ...``.

    Values wrap modulo 65536 like a 16-bit counter: ``start=65534, step=1`` gives 65534, 65535, 0, 1...
    (and ``start=-1`` gives 65535, the int16 -1).  A bit table gets the lowest bit of each value
    (step 1: alternating False/True).  Returns the values written.
    """
    table = _check_table(table)
    count = _count(count)
    for name, v in (("start", start), ("step", step)):
        if isinstance(v, bool) or not isinstance(v, int):
            raise ConfigError(f"{name} must be a whole number, got {shown(v)}")
    raw = [(start + i * step) & REGISTER_MAX for i in range(count)]
    values: list = [bool(v & 1) for v in raw] if table.is_bits else raw
    table.write(address, values)
    return values


@dataclass
class AutoFill:
    """Refresh ``count`` elements from ``address`` with ``generator`` every ``interval`` seconds.

    Nothing runs by itself: call :meth:`update` with the current time (``clock.now``), for example
    from a device before it answers a request.  Ticks fall at ``first``, ``first + interval``, ...;
    when ``now`` has crossed one or more ticks since the last write, the values of the *latest* tick
    are written once (its time is passed to the generator, so the data do not depend on how often you
    call ``update``).  ``generator`` is one :class:`Generator` (channel ``i`` for the ``i``-th
    element) or a sequence of ``count`` generators.  :meth:`stop` and :meth:`start` are the robot test-tool
    paper's "Auto Fill stop/start".
    """

    table: Table
    address: int
    count: int
    generator: Generator | Sequence[Generator]
    interval: float = 1.0
    first: float = 0.0
    running: bool = True
    ticks: int = field(default=0, init=False)
    last_tick: float | None = field(default=None, init=False)
    last_values: list | None = field(default=None, init=False)
    _next_k: int = field(default=0, init=False, repr=False)

    def __post_init__(self) -> None:
        _check_table(self.table)
        if _count(self.count) == 0:
            raise ConfigError("count must be at least 1")
        _positive("interval", self.interval)
        _number("first", self.first)
        if isinstance(self.generator, Generator):
            pass
        elif isinstance(self.generator, Sequence) and all(isinstance(g, Generator) for g in self.generator):
            if len(self.generator) != self.count:
                raise ConfigError(
                    f"{len(self.generator)} generators for {self.count} elements: give one generator "
                    f"or exactly {self.count}"
                )
        else:
            raise ConfigError(
                f"generator must be a Generator (Ramp, Sine, Noise, Uniform, ...) or a list of them, "
                f"got {shown(self.generator)}"
            )
        self.table.read(self.address, self.count)  # the range must exist: fail now, not at the first tick

    def values_at(self, t: float) -> list:
        """The values the fill would write for time ``t`` (bools for a bit table)."""
        if isinstance(self.generator, Generator):
            raw = self.generator.values(t, self.count)
        else:
            raw = [g.value(t, i) for i, g in enumerate(self.generator)]
        return [bool(v & 1) for v in raw] if self.table.is_bits else raw

    def update(self, now: float) -> list | None:
        """Write the values of the latest tick at or before ``now`` if it was not written yet.

        Returns the values written, or ``None`` when nothing was due (or the fill is stopped).
        """
        now = _number("now", now)
        if not self.running:
            return None
        k = _steps(now - self.first, self.interval)
        if k < self._next_k:  # also before ``first``: k < 0
            return None
        tick = self.first + k * self.interval
        values = self.values_at(tick)
        self.table.write(self.address, values)
        self._next_k = k + 1
        self.ticks += 1
        self.last_tick = tick
        self.last_values = values
        return values

    def next_tick(self) -> float:
        """The time of the next tick that :meth:`update` will write."""
        return self.first + self._next_k * self.interval

    def start(self, now: float | None = None) -> None:
        """Resume the fill; with ``now``, ticks restart from ``now`` (an update at ``now`` writes)."""
        self.running = True
        if now is not None:
            self.first = _number("now", now)
            self._next_k = 0

    def stop(self) -> None:
        """Stop writing (the table keeps its last values) until :meth:`start`."""
        self.running = False
