"""The Arduino Uno slave of the Arduino slave paper: a sparse register bank, simulated inputs, a main loop.

The paper: J. D. S. Simões, A. M. Fernandes, E. A. R. de Seabra, "Use Arduino as a Modbus slave over RTU".

Source 002 turns an Arduino Uno into a Modbus RTU slave with a library whose register bank is
declared element by element, with reference numbers: ``regBank.add(40001)`` makes holding register
40001 exist, ``regBank.set(40001, 1234)`` writes it, ``regBank.get(40001)`` reads it; anything not
added does not exist (a master that asks for it gets **exception 02, illegal data address**).  The
slave id, baud rate, parity and stop bits are configurable and all eight everyday functions
(1, 2, 3, 4, 5, 6, 15, 16) work.  Potentiometers, switches and LEDs stand for real sensors and
actuators.  :class:`ArduinoSlave` is that board, in Python.

The main loop, and the Arduino slave paper's finding
--------------------------------
An Arduino runs one ``loop()`` over and over.  The Modbus library only looks at the serial buffer
when ``loop()`` calls it, once per turn.  A request that arrives while the rest of the loop body runs
(reading sensors, writing the LCD, a ``delay(1500)``...) waits in the buffer until the next turn::

    loop:  |--- sketch body ----|--- sketch body ----|--- sketch body ----|
                 ^ request arrives            ^ seen and answered here (the next loop boundary)
                 <------ wait --------------->

So the answer comes ``wait`` seconds late, where ``wait`` is anything from 0 to one loop time,
depending on when the request arrived.  A master waits ``timeout`` seconds for an answer and then
gives up.  When the loop time ``L`` is longer than the timeout ``T``, the requests that arrive early
in a loop are answered too late: about ``(T - t_reply) / L`` of them are answered in time, where
``t_reply`` is the time the reply takes on the wire.  Source 002 saw "only about 60%" of requests
answered with QModMaster, and 100% after removing the ``delay`` from the sketch.
:func:`loop_time_experiment` reproduces that: with the course's documented parameters
(:data:`SLOW_LOOP` = 1.65 s, :data:`FAST_LOOP` = 0.01 s, :data:`EXPERIMENT_TIMEOUT` = 1.0 s, 9600 baud
8N1), about 60% then 100%.

The model: loop boundaries fall at ``phase, phase + L1, phase + L1 + L2, ...`` where ``phase`` is a
seeded random start in ``[0, L)`` and each loop time ``Lk`` is ``loop_time`` times ``1 +- jitter``
(seeded, uniform).  :meth:`ArduinoSlave.response_delay` -- the hook the loopback wire asks -- is the
time from a request's arrival to the next boundary.  ``loop_time=0`` is an ideal, instant slave.

The default sketch (``sketch=True``)
------------------------------------
===========  ============================  ===============================================
reference    what                          who writes it
===========  ============================  ===============================================
00001-00003  LEDs 1-3 (coils)              the master (FC 5, 15); ``.leds`` reads them back
00010        alarm LED (coil)              the sketch: on while pot A0 > threshold (40001)
10001, 10002 switches 1, 2 (discrete in.)  the sketch, from the simulated switches
10005        switch 3 (discrete input)     the sketch (10003 and 10004 are skipped, as 002 allows)
30001, 30002 potentiometers A0, A1 (0-1023)  the sketch, from the simulated potentiometers
30010        loop counter                  the sketch: loops run so far, modulo 65536
40001        alarm threshold (default 700)  the master (FC 6, 16) or the sketch
40002        LCD value                     the master; ``.lcd`` shows it
===========  ============================  ===============================================

The inputs come from seeded generators of :mod:`modbus_edu.devices.generators` as a function of the
clock the slave is attached to (a loopback link sets ``slave.clock``); they are refreshed at the loop
boundary that serves each request, as a sketch reads its inputs at the top of ``loop()``.
``sketch=False`` gives an empty sparse bank to ``add`` to, like a fresh sketch.
"""

from __future__ import annotations

import math
import random
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from ..datamodel import DataBank, Reference, ReferenceLike, parse_reference
from ..errors import ConfigError, ModbusTimeoutError, shown
from ..links.loopback import loopback_serial
from ..master import Master
from ..pdu import Pdu
from ..slave import Slave
from .generators import Noise, Sine, Uniform

__all__ = [
    "ArduinoSlave",
    "LoopTrial",
    "loop_time_experiment",
    "loop_time_trial",
    "expected_answered_fraction",
    "reply_time",
    "SLOW_LOOP",
    "FAST_LOOP",
    "EXPERIMENT_TIMEOUT",
    "EXPERIMENT_REQUESTS",
    "EXPERIMENT_SEED",
    "EXPERIMENT_JITTER",
    "LED_COILS",
    "ALARM_COIL",
    "SWITCH_INPUTS",
    "POT_REGISTERS",
    "LOOP_COUNTER",
    "THRESHOLD",
    "LCD",
]

#: References of the default sketch.
LED_COILS: tuple[str, ...] = ("00001", "00002", "00003")
ALARM_COIL = "00010"
SWITCH_INPUTS: tuple[str, ...] = ("10001", "10002", "10005")
POT_REGISTERS: tuple[str, ...] = ("30001", "30002")
LOOP_COUNTER = "30010"
THRESHOLD = "40001"
LCD = "40002"

#: The course's parameters for the Arduino slave paper's experiment (see :func:`loop_time_experiment`).
SLOW_LOOP = 1.65
"""A sketch with ``delay(1500)`` and ~150 ms of sensor and LCD work: about 60% answered in 1 s."""
FAST_LOOP = 0.01
"""The same sketch without the delay: a 10 ms loop, every request answered."""
EXPERIMENT_TIMEOUT = 1.0
"""The master's response timeout, seconds."""
EXPERIMENT_REQUESTS = 200
EXPERIMENT_SEED = 0
EXPERIMENT_JITTER = 0.1

_PARITIES = {"N": "N", "NONE": "N", "E": "E", "EVEN": "E", "O": "O", "ODD": "O"}
_ADC_MAX = 1023  # the Uno's 10-bit analog inputs


def _check_number(name: str, value: Any, low: float = 0.0) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"{name} must be a number of seconds, got {shown(value)}")
    if value < low:
        raise ConfigError(f"{name} must be >= {low:g}, got {shown(value)}")
    return float(value)


def check_serial_settings(baudrate: Any, parity: Any, stopbits: Any) -> tuple[int, str, int]:
    """Validate serial settings; return ``(baudrate, "N" | "E" | "O", 1 | 2)`` or raise ConfigError."""
    if isinstance(baudrate, bool) or not isinstance(baudrate, int) or not 50 <= baudrate <= 4_000_000:
        raise ConfigError(f"baud rate must be a whole number such as 9600 or 19200, got {shown(baudrate)}")
    key = parity.strip().upper() if isinstance(parity, str) else None
    if key not in _PARITIES:
        raise ConfigError(f"parity must be 'N' (none), 'E' (even) or 'O' (odd), got {shown(parity)}")
    if stopbits not in (1, 2) or isinstance(stopbits, bool):
        raise ConfigError(f"stop bits must be 1 or 2, got {shown(stopbits)}")
    return baudrate, _PARITIES[key], int(stopbits)


def reply_time(byte_count: int, baudrate: int = 9600, parity: str = "N", stopbits: int = 1) -> float:
    """Seconds ``byte_count`` RTU characters take on the wire (start + 8 data + parity + stop bits)."""
    bits = 1 + 8 + (0 if _PARITIES.get(parity.upper(), "N") == "N" else 1) + stopbits
    return byte_count * bits / baudrate


class ArduinoSlave(Slave):
    """The Arduino slave paper's Arduino Uno slave: ``ArduinoSlave(unit=1, baudrate=9600, parity="N",
    stopbits=1, loop_time=0.0, seed=0)``.

    A :class:`~modbus_edu.slave.Slave` with a **sparse** bank declared by reference numbers
    (:meth:`add`, :meth:`set`, :meth:`get`, as the Arduino slave paper's ``regBank``), the default sketch of
    the module docstring (``sketch=False`` for an empty bank), simulated potentiometers and switches (seeded
    by ``seed``; ``simulate_inputs=False`` keeps whatever you ``set``), and a main loop of ``loop_time``
    seconds (``jitter``: each loop lasts ``loop_time x (1 +- jitter)``) during which requests wait.

    ``baudrate``, ``parity`` and ``stopbits`` are the board's settings; the wire must match them::

        board = ArduinoSlave(unit=1, loop_time=1.65)
        link = loopback_serial(board, **board.serial_settings)

    A loopback wire reads them (:attr:`serial_settings`) for every frame: on a line with another baud
    rate or parity the board's UART assembles garbage, its CRC check fails, and it never answers, as a
    real board would (see :class:`~modbus_edu.links.loopback.LoopbackSerialLink`).
    """

    def __init__(
        self,
        unit: int = 1,
        baudrate: int = 9600,
        parity: str = "N",
        stopbits: int = 1,
        loop_time: float = 0.0,
        seed: int = 0,
        *,
        jitter: float = 0.0,
        sketch: bool = True,
        simulate_inputs: bool = True,
        **kwargs: Any,
    ) -> None:
        if isinstance(unit, bool) or not isinstance(unit, int) or not 1 <= unit <= 247:
            raise ConfigError(f"an Arduino slave's id must be 1..247 (0 is broadcast), got {shown(unit)}")
        self.baudrate, self.parity, self.stopbits = check_serial_settings(baudrate, parity, stopbits)
        self.loop_time = _check_number("loop_time", loop_time)
        self.jitter = _check_number("jitter", jitter)
        if self.jitter >= 1:
            raise ConfigError(f"jitter is a fraction of the loop time, 0 <= jitter < 1; got {shown(jitter)}")
        if isinstance(seed, bool) or not isinstance(seed, int):
            raise ConfigError(f"seed must be an int, got {shown(seed)}")
        self.seed = seed
        self.simulate_inputs = bool(simulate_inputs)
        kwargs.setdefault("name", f"arduino {unit}")
        super().__init__(unit, DataBank(sparse=True), **kwargs)
        self.sketch = bool(sketch)
        self._phase = random.Random(f"arduino-phase:{seed}").random() * self.loop_time
        # where the last search ended: (index k, time of boundary k, time of boundary k - 1)
        self._cursor: tuple[int, float, float] = (0, self._phase, -math.inf)
        self._waiting_until = -math.inf
        self.overruns = 0
        """Requests that arrived while an earlier one was still waiting in the buffer (dropped)."""
        self.last_wait: float | None = None
        """How long the last request waited for the loop, seconds."""
        self.loops_run = 0
        """How many loops the sketch has run by the last request (``30010`` holds it modulo 65536)."""
        if sketch:
            self._declare_sketch()
            self._pots = [
                Noise(Sine(512, 380, 23.0 + 6 * i, phase=self._unit_phase(f"pot{i}")), sigma=3.0,
                      seed=seed * 31 + i)
                for i in range(len(POT_REGISTERS))
            ]
            self._switches = Uniform(0, 1, seed=seed, period=7.0)

    @property
    def waiting_until(self) -> float:
        """The loop boundary at which the latest request is (or was) seen; -inf before any request."""
        return self._waiting_until

    def _unit_phase(self, key: str) -> float:
        return 2 * math.pi * random.Random(f"arduino-{key}:{self.seed}").random()

    def _declare_sketch(self) -> None:
        for ref in LED_COILS:
            self.add(ref, False)
        self.add(ALARM_COIL, False)
        for ref in SWITCH_INPUTS:
            self.add(ref, False)
        for ref in POT_REGISTERS:
            self.add(ref, 0)
        self.add(LOOP_COUNTER, 0)
        self.add(THRESHOLD, 700)
        self.add(LCD, 0)

    def __repr__(self) -> str:
        return (
            f"<ArduinoSlave unit={self.unit} {self.baudrate} {8}{self.parity}{self.stopbits} "
            f"loop_time={self.loop_time:g} s {self.counters.as_dict()}>"
        )

    @property
    def serial_settings(self) -> dict[str, Any]:
        """``{"baudrate": ..., "parity": ..., "stopbits": ...}``: pass to a wire with ``**``.

        The loopback wire reads this to decide how the board's UART hears the line.
        """
        return {"baudrate": self.baudrate, "parity": self.parity, "stopbits": self.stopbits}

    # -- the Arduino slave paper's regBank ------------------------------------------------------------
    def add(self, reference: ReferenceLike, value: Any = 0) -> Reference:
        """Declare an element by reference number (``add(40001)``, ``add("00308")``) and set it."""
        return self.bank.add(reference, value)

    def set(self, reference: ReferenceLike, value: Any) -> None:
        """Write an element by reference number: ``set(40001, 1234)``, ``set("00001", True)``."""
        self.bank.set(reference, value)

    def get(self, reference: ReferenceLike) -> Any:
        """Read an element by reference number: ``get(30001)``."""
        return self.bank.get(reference)

    # -- the board's view -------------------------------------------------------------------------
    @property
    def leds(self) -> tuple[bool, ...]:
        """The LEDs the master switches (coils 00001-00003), as they are lit now."""
        return tuple(self._get_if(ref, False) for ref in LED_COILS)

    @property
    def alarm_led(self) -> bool:
        """The alarm LED (coil 00010): on while potentiometer A0 is above the threshold (40001)."""
        return bool(self._get_if(ALARM_COIL, False))

    @property
    def switches(self) -> tuple[bool, ...]:
        """The switches (discrete inputs 10001, 10002, 10005)."""
        return tuple(self._get_if(ref, False) for ref in SWITCH_INPUTS)

    @property
    def pots(self) -> tuple[int, ...]:
        """The potentiometers A0 and A1 (input registers 30001, 30002), 0..1023."""
        return tuple(self._get_if(ref, 0) for ref in POT_REGISTERS)

    @property
    def lcd(self) -> str:
        """What the LCD shows: the value in holding register 40002."""
        return f"LCD: {self._get_if(LCD, 0)}"

    def _get_if(self, ref: str, default: Any) -> Any:
        r = parse_reference(ref)
        table = self.bank.table(r.kind)
        return table[r.address] if table.is_declared(r.address) else default

    # -- the main loop ----------------------------------------------------------------------------
    def _duration(self, k: int) -> float:
        """How long loop number ``k`` takes (seeded jitter)."""
        if not self.jitter:
            return self.loop_time
        u = random.Random(f"arduino-loop:{self.seed}:{k}").random()
        return self.loop_time * (1.0 + self.jitter * (2.0 * u - 1.0))

    def _boundary_at_or_after(self, t: float) -> tuple[int, float]:
        """``(k, time)`` of the first loop boundary at or after ``t`` (k = loops completed by then)."""
        if self.loop_time == 0:
            return 0, t
        k, b, before = self._cursor
        if t <= before:  # earlier than where the last search ended: start over from the first loop
            k, b, before = 0, self._phase, -math.inf
        while b < t:
            before = b
            b += self._duration(k)
            k += 1
        self._cursor = (k, b, before)
        return k, b

    def next_loop_boundary(self, t: float) -> float:
        """When the sketch next looks at its serial buffer, at or after time ``t`` (seconds)."""
        return self._boundary_at_or_after(t)[1]

    def response_delay(self, arrival_time: float) -> float:
        """The request waits for the next loop boundary, then takes ``processing_time``."""
        boundary = self.next_loop_boundary(arrival_time)
        self.last_wait = boundary - arrival_time
        return self.last_wait + self.processing_time

    def run_sketch(self, t: float) -> None:
        """One turn of the default sketch at time ``t``: read the inputs, drive the alarm LED, count."""
        if not self.sketch:
            return
        # an instant board (loop_time 0) runs one loop per request
        k = self._boundary_at_or_after(t)[0] if self.loop_time else self.loops_run + 1
        self.loops_run = k
        if self.simulate_inputs:
            for i, ref in enumerate(POT_REGISTERS):
                if self._declared(ref):
                    self.set(ref, min(self._pots[i].value(t), _ADC_MAX))
            for i, ref in enumerate(SWITCH_INPUTS):
                if self._declared(ref):
                    self.set(ref, self._switches.value(t, i) == 1)
        if self._declared(LOOP_COUNTER):
            self.set(LOOP_COUNTER, k & 0xFFFF)
        if self._declared(ALARM_COIL) and self._declared(THRESHOLD) and self._declared(POT_REGISTERS[0]):
            self.set(ALARM_COIL, self.get(POT_REGISTERS[0]) > self.get(THRESHOLD))

    def _declared(self, ref: str) -> bool:
        r = parse_reference(ref)
        return self.bank.table(r.kind).is_declared(r.address)

    # -- the slave --------------------------------------------------------------------------------
    def handle(self, frame: bytes, mode: str = "rtu") -> bytes | None:
        """Like :meth:`Slave.handle`, with the buffer of a board that reads it once per loop.

        A request that arrives while an earlier one still waits for the loop finds the buffer not
        empty: the library reads both as one garbled message, so the later one is never answered
        (counted in :attr:`overruns`).  The master should not send before the previous answer or
        its timeout: on a half-duplex line the two would collide anyway.
        """
        now = self._now()
        if self.loop_time and now < self._waiting_until:
            self.overruns += 1
            self.log.add(now, "rx", mode, bytes(frame), source=self.sender, dest=self.name, role="request",
                         note="dropped: an earlier request is still waiting in the buffer")
            return None
        if self.loop_time:
            self._waiting_until = self.next_loop_boundary(now)
        return super().handle(frame, mode)

    def process(self, request: Pdu) -> Pdu:
        """Run the sketch at the loop boundary that serves the request, then carry the request out."""
        now = self._now()
        self.run_sketch(self.next_loop_boundary(now) if self.loop_time else now)
        return super().process(request)


# --------------------------------------------------------------------------------------------------
# The Arduino slave paper's experiment: response rate against loop time
# --------------------------------------------------------------------------------------------------
@dataclass
class LoopTrial:
    """What one run of the experiment saw, for one loop time.

    ``requests`` sent; ``answered`` in time; ``timeouts``; ``late_replies`` that arrived after the
    master had given up (discarded from the receive buffer before the next request, never counted as
    an answer); ``overlaps``: requests sent while a late reply could still be on its way (0 with the
    default poll period: the experiment is then free of mix-ups); ``period``: the shortest time between
    two polls; ``spread``: the width of the seeded random extra added to each gap (0: a fixed period);
    ``send_times``: when each request was sent, seconds of the wire's clock.
    """

    loop_time: float
    timeout: float
    requests: int
    answered: int = 0
    timeouts: int = 0
    late_replies: int = 0
    overlaps: int = 0
    period: float = 0.0
    spread: float = 0.0
    waits: list[float] = field(default_factory=list, repr=False)
    send_times: list[float] = field(default_factory=list, repr=False)
    master_stats: Any = field(default=None, repr=False)

    @property
    def answered_fraction(self) -> float:
        return self.answered / self.requests if self.requests else 0.0


def expected_answered_fraction(loop_time: float, timeout: float, reply: float = 0.0) -> float:
    """The fraction a random arrival time gives: ``min(1, (timeout - reply) / loop_time)``.

    ``reply`` is how long the reply takes to arrive once the loop has seen the request (its time on
    the wire, see :func:`reply_time`).
    """
    if loop_time <= 0:
        return 1.0 if timeout >= reply else 0.0
    return max(0.0, min(1.0, (timeout - reply) / loop_time))


def loop_time_trial(
    loop_time: float,
    timeout: float = EXPERIMENT_TIMEOUT,
    requests: int = EXPERIMENT_REQUESTS,
    seed: int = EXPERIMENT_SEED,
    *,
    jitter: float = EXPERIMENT_JITTER,
    baudrate: int = 9600,
    parity: str = "N",
    stopbits: int = 1,
    period: float | None = None,
    spread: float | None = None,
    unit: int = 1,
) -> LoopTrial:
    """Poll an :class:`ArduinoSlave` with a :class:`~modbus_edu.master.Master` over a loopback wire.

    The master reads the two potentiometers (FC 04, 30001-30002) ``requests`` times and waits
    ``timeout`` seconds for each answer.  Before each request the master empties its receive buffer
    (as the power-meter paper's master does): a reply that comes after the timeout is counted in
    ``late_replies`` and thrown away, never taken for the answer to the next request.

    **When the polls go out.**  Two polls are ``period`` seconds apart plus a seeded random extra,
    uniform in ``[0, spread)``.  ``period`` defaults to the longest possible loop plus the timeout plus
    a margin, so every late reply has arrived before the next request (``overlaps`` stays 0): on RTU
    nothing else could tell a late reply to the same unit and function from the answer to the next
    request.  ``spread`` defaults to one loop time, which makes the moment a request lands in the loop
    uniformly random, the assumption behind :func:`expected_answered_fraction`.  A *fixed* period
    (``spread=0``) can fall into step with the loop: with a period close to a whole number of loop times
    every request lands at nearly the same point of the loop, and the measured fraction says more about
    that point than about the loop (a 1.25 s loop polled every 2.475 s: 0.655 answered, against 0.78
    predicted).  The extra is drawn from ``random.Random(f"arduino-poll:{seed}")``: the same ``seed``
    gives the same polls.  Everything runs on the wire's virtual clock: no real waiting.
    """
    if isinstance(requests, bool) or not isinstance(requests, int) or requests < 1:
        raise ConfigError(f"requests must be a whole number >= 1, got {shown(requests)}")
    timeout = _check_number("timeout", timeout)
    if timeout <= 0:
        raise ConfigError("timeout must be more than 0 s")
    board = ArduinoSlave(unit, baudrate, parity, stopbits, loop_time=loop_time, seed=seed, jitter=jitter)
    longest_loop = board.loop_time * (1 + board.jitter)
    if period is None:  # the longest wait for a reply, the timeout, and 0.1 s for the wire and margin
        period = round(longest_loop + timeout + 0.1, 3)
    period = _check_number("period", period)
    if period <= 0:
        raise ConfigError("period must be more than 0 s")
    spread = board.loop_time if spread is None else _check_number("spread", spread)
    trial = LoopTrial(loop_time=board.loop_time, timeout=timeout, requests=requests, period=period,
                      spread=spread)
    link = loopback_serial(board, **board.serial_settings)
    master = Master(link, timeout=timeout)
    clock = link.clock
    rng = random.Random(f"arduino-poll:{seed}")
    due = clock.now
    for k in range(requests):
        if k:
            due += period + (rng.random() * spread if spread else 0.0)
        clock.run_until(due)
        trial.send_times.append(clock.now)
        # Honesty check: is an earlier request still waiting for the loop, or a reply still on the line?
        if board.waiting_until > clock.now or link.bus.free_at > clock.now:
            trial.overlaps += 1
        try:
            # The master itself throws away frames that arrived after their request timed out
            # (stats.mismatches): a late reply is never taken for the answer to this request.
            master.read_input_registers(unit=unit, address=0, count=2)
        except ModbusTimeoutError:
            trial.timeouts += 1
        else:
            trial.answered += 1
        if board.last_wait is not None:
            trial.waits.append(board.last_wait)
    clock.run_until(clock.now + longest_loop + 1.0)  # let the last late reply land
    while link.receive(0) is not None:
        master.stats.mismatches += 1
    trial.late_replies = master.stats.mismatches
    trial.master_stats = master.stats
    link.close()
    return trial


def loop_time_experiment(
    loop_times: Iterable[float] | float = (FAST_LOOP, SLOW_LOOP),
    timeout: float = EXPERIMENT_TIMEOUT,
    requests: int = EXPERIMENT_REQUESTS,
    seed: int = EXPERIMENT_SEED,
    **options: Any,
) -> list[tuple[float, float]]:
    """The Arduino slave paper's experiment: ``[(loop_time, answered_fraction), ...]``, one
    :func:`loop_time_trial` each.

    With the defaults (a 1.0 s timeout, 200 requests, 9600 baud 8N1, loop jitter 10%, seed 0)::

        >>> loop_time_experiment([FAST_LOOP, SLOW_LOOP])         # doctest: +SKIP
        [(0.01, 1.0), (1.65, 0.615)]

    A 10 ms loop answers everything; a 1.65 s loop (a sketch with ``delay(1500)``) about 60%, as 002
    saw.  Plot the fraction against the loop time for a range of loop times: 1 up to about the
    timeout, then falling like ``timeout / loop_time`` (:func:`expected_answered_fraction`).
    ``options`` go to :func:`loop_time_trial` (jitter, baudrate, parity, stopbits, period, spread, unit).
    """
    if isinstance(loop_times, (int, float)):
        loop_times = [loop_times]
    return [
        (trial.loop_time, trial.answered_fraction)
        for trial in (loop_time_trial(lt, timeout, requests, seed, **options) for lt in loop_times)
    ]
