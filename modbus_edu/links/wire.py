"""The virtual serial line: character timing, the silence that ends an RTU frame, a multidrop bus.

**One character** on an asynchronous serial line is a start bit, the data bits (8 in RTU, 7 or 8 in
ASCII), a parity bit if parity is even or odd, and 1 or 2 stop bits: 10 or 11 bits in RTU.  At ``B``
baud it takes ``bits / B`` seconds: 1.0417 ms for 8N1 at 9600 baud.

**RTU frames are delimited by silence.**  A frame ends when the line has been quiet for 3.5 character
times (``t3.5``); inside a frame the characters must follow each other with at most 1.5 character times
of silence (``t1.5``).  Above 19200 baud the serial line specification recommends fixed values,
``t1.5 = 0.750 ms`` and ``t3.5 = 1.750 ms`` (the character-based values would be too short for a PC's
timers), and this line uses them.

What the receivers of this virtual line do (the state machine of the serial line specification):

* a silence of **3.5 character times or more** after a byte ends the frame; the frame is handed to every
  other node on the bus at that moment (``last byte + t3.5``);
* a silence of **more than 1.5 but less than 3.5** character times inside a frame makes the frame
  *broken*: the receiver keeps taking the bytes that follow (they belong to the same frame, since the
  line never went quiet for 3.5), and when the 3.5 silence finally comes it **discards the whole
  frame**, both pieces.  Nobody receives it: a request broken this way gets no answer, a response broken
  this way never reaches the master.  Counted in ``stats.broken_frames``.
* a silence of **3.5 or more** inside what the sender meant as one frame simply cuts it in two frames;
  each piece is delivered on its own and fails its CRC check at the receiver.

**ASCII frames are delimited by characters**: ``:`` starts a frame (and restarts it if one was in
progress: the half frame is discarded), CR LF ends it, and it is delivered the moment the LF arrives.
Bytes outside a frame are discarded.  Inside a frame a silence of more than 1 second (configurable)
discards the frame.

**Who may talk.**  Each node transmits whole frames, byte after byte without pause (unless a fault
inserts one).  A node that wants to transmit while the line is busy waits until it is free (for RTU:
until the 3.5-character silence after the last frame has passed).  A real RS-485 bus would garble two
simultaneous transmissions instead; here they are queued, which keeps the simulation simple and makes
the timing of a well-behaved bus exact.  A node never hears itself; a node does not hear a frame that
started before its own transmission ended (half duplex: it was talking).

**Line settings that do not match.**  Every node's UART must use the line's baud rate, parity, stop bits
and data bits.  One that does not (a slave set to 19200 baud on a 9600 baud line, to even parity on a
line without parity) takes the same voltages apart at the wrong moments.  :func:`uart_receive` models
that bit by bit: the sender's characters become a waveform (line idle = 1; a start bit 0, the data bits
lowest first, the parity bit, the stop bits 1), and the receiver does what a UART does: it waits for a
falling edge (1 to 0), checks half a bit later that the line is still 0 (else it was a glitch), then
samples the middle of each of its own bit times: data bits, parity bit, first stop bit.  A stop bit
read as 0 is a **framing error**; a parity bit that disagrees with the data is a **parity error**.
The receiver then hunts for the next falling edge.  Like a microcontroller's serial driver (the
Arduino's, for one), it **drops a character with a parity error** and keeps one with a framing error
(its bits are garbage).  So at another baud rate the receiver assembles a different number of
characters, most with framing errors; with a parity mismatch it loses characters and the rest no longer
line up with their parity and stop bits; the frame's CRC (or LRC) fails and a slave never answers.  A
stop-bit difference alone is harmless, as on real lines: a receiver checks the first stop bit only.
The model is exact arithmetic (fractions of a second), with no randomness: the same bytes and settings
always give the same garbage.  Two simplifications: the frame boundaries are the line's (a receiver at
another speed would also time its 3.5-character silence differently), and a node that transmits with
its own settings does so in the line's character times (the bytes recorded by the monitor are what a
receiver with the line's settings assembles).
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, fields
from fractions import Fraction
from functools import cached_property, reduce
from itertools import repeat
from operator import add

from ..clock import Timer, VirtualClock
from ..errors import ConfigError, shown
from ..traffic import TrafficLog
from .faults import Faults

__all__ = ["SerialTiming", "SerialBus", "BusStats", "character_time", "UartChar", "UartReading",
           "uart_receive", "same_format"]

PARITIES = {"N": 0, "E": 1, "O": 1}
_EPS = 1e-9  # one nanosecond: tolerance when comparing silences computed in floating point


def _parity(parity: str) -> str:
    value = str(parity).upper()[:1] if not isinstance(parity, int) else ""  # no int is a parity
    if value not in PARITIES:
        raise ConfigError(f"parity must be 'N' (none), 'E' (even) or 'O' (odd), got {shown(parity)}")
    return value


MAX_BAUDRATE = 100_000_000
"""The fastest serial line the course models (real RS-485 stops near 10 Mbit/s)."""


@dataclass(frozen=True)
class SerialTiming:
    """The timing of a serial line: ``SerialTiming(9600, "N", 1, 8)``.

    >>> t = SerialTiming(baudrate=9600)
    >>> t.bits_per_char, round(t.char_time * 1000, 4), round(t.t35 * 1000, 4)
    (10, 1.0417, 3.6458)
    >>> SerialTiming(baudrate=115200).t35   # the recommended fixed value above 19200 baud
    0.00175
    """

    baudrate: int = 9600
    parity: str = "N"
    stopbits: float = 1
    bytesize: int = 8
    mode: str = "rtu"
    ascii_timeout: float = 1.0

    def __post_init__(self) -> None:
        baud = self.baudrate
        if isinstance(baud, bool) or not isinstance(baud, (int, float)) or not 0 < baud <= MAX_BAUDRATE:
            raise ConfigError(f"baudrate must be a number of bits per second, 1 to {MAX_BAUDRATE:,}, "
                              f"got {shown(self.baudrate)}")
        object.__setattr__(self, "parity", _parity(self.parity))
        if self.stopbits not in (1, 1.5, 2):
            raise ConfigError(f"stopbits must be 1, 1.5 or 2, got {shown(self.stopbits)}")
        if self.mode not in ("rtu", "ascii"):
            raise ConfigError(f"a serial line carries 'rtu' or 'ascii' frames, got mode {shown(self.mode)}")
        if self.bytesize not in (7, 8):
            raise ConfigError(f"bytesize must be 7 or 8 data bits, got {shown(self.bytesize)}")
        if self.mode == "rtu" and self.bytesize != 8:
            raise ConfigError("RTU needs 8 data bits: every byte of the frame is sent as it is")
        if not self.ascii_timeout > 0:
            raise ConfigError(f"ascii_timeout must be > 0 s, got {shown(self.ascii_timeout)}")

    @cached_property
    def bits_per_char(self) -> float:
        """Start bit + data bits + parity bit (E/O) + stop bits."""
        stop = self.stopbits
        return 1 + self.bytesize + PARITIES[self.parity] + (int(stop) if stop == int(stop) else stop)

    @cached_property
    def char_time(self) -> float:
        """Seconds one character occupies the line."""
        return self.bits_per_char / self.baudrate

    @cached_property
    def t15(self) -> float:
        """Longest allowed silence inside an RTU frame: 1.5 characters, or 0.750 ms above 19200 baud."""
        return 0.000750 if self.baudrate > 19200 else 1.5 * self.char_time

    @cached_property
    def t35(self) -> float:
        """Silence that ends an RTU frame: 3.5 characters, or 1.750 ms above 19200 baud."""
        return 0.001750 if self.baudrate > 19200 else 3.5 * self.char_time

    @cached_property
    def frame_gap(self) -> float:
        """Silence between two frames: ``t35`` in RTU, none in ASCII (its frames end with CR LF)."""
        return self.t35 if self.mode == "rtu" else 0.0

    def frame_time(self, nbytes: int) -> float:
        """Seconds ``nbytes`` characters take on the line, back to back."""
        return nbytes * self.char_time

    def transaction_time(
        self, request_bytes: int, response_bytes: int, processing_time: float = 0.0
    ) -> float:
        """One request and its response, until the next request may start.

        RTU: request + t3.5 + processing + response + t3.5 (the silence that ends the response is the one
        that must precede the next request: it is not counted twice).  ASCII: request + processing +
        response (the frames carry their own delimiters).
        """
        return (request_bytes + response_bytes) * self.char_time + 2 * self.frame_gap + processing_time

    def __str__(self) -> str:
        stop = f"{self.stopbits:g}"
        return f"{self.baudrate:g} baud {self.bytesize}{self.parity}{stop}"


def character_time(baudrate: int, parity: str = "N", stopbits: float = 1, bytesize: int = 8) -> float:
    """Seconds one character takes on a serial line: ``character_time(9600) == 10 / 9600``."""
    return SerialTiming(baudrate, parity, stopbits, bytesize, "rtu" if bytesize == 8 else "ascii").char_time


# --- a receiver whose settings differ from the sender's -----------------------------------------------
@dataclass(frozen=True)
class UartChar:
    """One character as a receiving UART assembled it: its data bits and the UART's two error flags."""

    value: int
    parity_error: bool = False
    framing_error: bool = False

    @property
    def ok(self) -> bool:
        return not (self.parity_error or self.framing_error)


@dataclass(frozen=True)
class UartReading:
    """What a receiver made of a transmission (see :func:`uart_receive`).

    ``chars`` every character it assembled, with its error flags; ``data`` the bytes its serial driver
    passes on: every character except those with a parity error (dropped).
    """

    chars: tuple[UartChar, ...]

    @property
    def data(self) -> bytes:
        return bytes(c.value for c in self.chars if not c.parity_error)

    @property
    def parity_errors(self) -> int:
        return sum(1 for c in self.chars if c.parity_error)

    @property
    def framing_errors(self) -> int:
        return sum(1 for c in self.chars if c.framing_error)

    def describe(self) -> str:
        """``"9 characters, 7 with a framing error, 2 with a parity error (dropped)"``."""
        n = len(self.chars)
        text = f"{n} character{'s' if n != 1 else ''}"
        errors = []
        if self.framing_errors:
            errors.append(f"{self.framing_errors} with a framing error")
        if self.parity_errors:
            errors.append(f"{self.parity_errors} with a parity error (dropped)")
        return text + (", " + ", ".join(errors) if errors else "")


def same_format(a: SerialTiming, b: SerialTiming) -> bool:
    """True when two UARTs agree on baud rate, parity, stop bits and data bits."""
    return (a.baudrate == b.baudrate and a.parity == b.parity and a.stopbits == b.stopbits
            and a.bytesize == b.bytesize)


def _parity_bit(value: int, parity: str) -> int:
    """The parity bit that goes with ``value``'s data bits: even parity makes the count of 1s even."""
    ones = bin(value).count("1") & 1
    return ones if parity == "E" else ones ^ 1


def uart_receive(data: bytes, sent: SerialTiming, heard: SerialTiming, *,
                 inverted: bool = False) -> UartReading:
    """What a UART set to ``heard`` assembles from ``data`` sent back to back with ``sent``'s settings.

    Bit-level and exact (times are fractions): the sender's characters become a waveform, and the
    receiver waits for a falling edge, checks the start bit half a bit later, and samples the middle of
    each of its own bit times (data bits lowest first, the parity bit, the first stop bit).  A stop bit
    read as 0 is a framing error, a parity bit that disagrees a parity error; then the receiver hunts
    for the next falling edge.  With equal settings the bytes come back unchanged, without errors.

    ``inverted``: the receiver sees every level the other way round, as a transceiver whose A and B
    wires are swapped does (the pair's voltage difference changes sign).  The idle line then reads 0,
    each start bit 1 and each stop bit 0: the receiver starts characters on the sender's 0-to-1 edges
    and assembles garbage, mostly with framing errors.

    >>> line, fast = SerialTiming(9600), SerialTiming(19200)
    >>> uart_receive(bytes.fromhex("01 03"), line, line).data.hex(" ")
    '01 03'
    >>> uart_receive(bytes.fromhex("01 03 00 00 00 01 84 0A"), line, fast).describe()
    '9 characters, 7 with a framing error'
    """
    # the sender's waveform: level changes (start time, level), idle (1) before and after
    bit = 1 / Fraction(sent.baudrate)
    stop = Fraction(sent.stopbits) * bit
    mask = (1 << sent.bytesize) - 1
    starts: list[Fraction] = []
    levels: list[int] = []
    t = Fraction(0)
    level = 1
    for byte in data:
        byte &= mask
        bits = [0] + [byte >> k & 1 for k in range(sent.bytesize)]
        if sent.parity != "N":
            bits.append(_parity_bit(byte, sent.parity))
        for b in bits:
            if b != level:
                starts.append(t)
                levels.append(b)
                level = b
            t += bit
        if level != 1:
            starts.append(t)
            levels.append(1)
            level = 1
        t += stop
    end = t
    edges = [s for s, lv in zip(starts, levels) if lv == 0]

    idle = 1
    if inverted:  # A and B swapped: every level the other way round, the idle line included
        levels = [1 - lv for lv in levels]
        edges = [s for s, lv in zip(starts, levels) if lv == 0]
        idle = 0

    def line_at(when: Fraction) -> int:
        if when < 0 or when >= end:
            return idle
        index = bisect_right(starts, when) - 1
        return levels[index] if index >= 0 else idle

    # the receiver
    rbit = 1 / Fraction(heard.baudrate)
    half = rbit / 2
    n = heard.bytesize
    has_parity = heard.parity != "N"
    chars: list[UartChar] = []
    hunt_from = Fraction(0)
    j = 0
    while True:
        j = bisect_left(edges, hunt_from, j)
        if j >= len(edges):
            break
        edge = edges[j]
        if line_at(edge + half):
            hunt_from = edge + half  # back to 1 already: a glitch, not a start bit
            continue
        value = 0
        for k in range(n):
            if line_at(edge + half + (k + 1) * rbit):
                value |= 1 << k
        parity_error = False
        at = edge + half + (n + 1) * rbit
        if has_parity:
            parity_error = line_at(at) != _parity_bit(value, heard.parity)
            at += rbit
        framing_error = line_at(at) == 0
        chars.append(UartChar(value, parity_error, framing_error))
        hunt_from = at  # the middle of the first stop bit: hunt for the next start bit from here
    return UartReading(tuple(chars))


@dataclass
class BusStats:
    """What the line itself saw.

    ``frames``            frames delivered to the receivers
    ``broken_frames``     RTU frames discarded because of a silence of more than 1.5 characters inside
    ``discarded_frames``  ASCII frames discarded (restarted by ':', inter-character timeout, too long)
    ``junk_bytes``        ASCII bytes outside any frame
    ``ignored_frames``    frames a node did not hear because it was transmitting (half duplex)
    ``waits``             transmissions that had to wait for the line to be free
    """

    frames: int = 0
    broken_frames: int = 0
    discarded_frames: int = 0
    junk_bytes: int = 0
    ignored_frames: int = 0
    waits: int = 0

    def reset(self) -> None:
        for f in fields(self):
            setattr(self, f.name, 0)

    def as_dict(self) -> dict[str, int]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


class Node:
    """One transceiver on the bus.  ``on_frame(frame, time)`` receives each complete frame (``time``: when
    it was complete; the bus's ``current_sender`` is then the node that sent it)."""

    def __init__(self, bus: SerialBus, name: str, is_master: bool,
                 on_frame: Callable[[bytes, float], None]) -> None:
        self.bus = bus
        self.name = name
        self.is_master = is_master
        self.on_frame = on_frame
        self.tx_end = float("-inf")
        """When this node's latest transmission leaves the line (its last bit)."""

    def transmit(self, data: bytes, dest: str = "", uart: SerialTiming | None = None) -> float:
        """Queue ``data`` for transmission now (or when the line is free); return when it will end.

        ``uart``: the node's own settings, when they differ from the line's (see :func:`uart_receive`).
        """
        return self.bus.transmit(self, data, dest, uart)

    def __repr__(self) -> str:
        return f"<Node {self.name}>"


class SerialBus:
    """A half-duplex serial line shared by a master node and slave nodes, on a :class:`VirtualClock`.

    See the module's documentation for the rules.  The ``monitor`` (a :class:`TrafficLog`) records every
    transmission: time of its first bit, its bytes as they went on the line, who sent it, and what the
    fault injector did to it.
    """

    def __init__(self, timing: SerialTiming, clock: VirtualClock, faults: Faults | None = None,
                 monitor: TrafficLog | None = None) -> None:
        self.timing = timing
        self.clock = clock
        self.faults = faults if faults is not None else Faults()
        self.monitor = monitor if monitor is not None else TrafficLog()
        self.stats = BusStats()
        self.nodes: list[Node] = []
        self.free_at = float("-inf")
        """When the line is next free for a new frame (after the inter-frame silence)."""
        # receiver state, shared by every node: they all hear the same bytes at the same moments
        self._buf = bytearray()
        self._first = 0.0
        self._last = float("-inf")
        self._sender: Node | None = None
        self._broken = False
        self._done: Timer | None = None
        self.current_sender: Node | None = None
        """While a frame is being handed to the receivers: the node that sent it (None otherwise)."""

    def attach(self, name: str, on_frame: Callable[[bytes, float], None], is_master: bool = False) -> Node:
        node = Node(self, name, is_master, on_frame)
        self.nodes.append(node)
        return node

    def detach(self, node: Node) -> None:
        if node in self.nodes:
            self.nodes.remove(node)

    # -- transmitting -------------------------------------------------------------------------------
    def transmit(self, node: Node, data: bytes, dest: str = "", uart: SerialTiming | None = None) -> float:
        """Put ``data`` on the line for ``node``; return when its last bit will have left.

        ``uart`` is the sender's own character format when it is not the line's: the bytes then go on
        the line as the line's receivers assemble them (:func:`uart_receive`), and the monitor's note
        says so.
        """
        timing, clock = self.timing, self.clock
        now = clock.now
        start = now
        if self.free_at > now + _EPS:
            start = self.free_at
            self.stats.waits += 1
        is_master = node.is_master
        role = "request" if is_master else "response"
        note = ""
        if uart is not None and not same_format(uart, timing):
            reading = uart_receive(data, uart, timing)
            note = (f"sent at {uart} on a {timing} line: the line's receivers assemble "
                    f"{reading.describe()}")
            data = reading.data
        gaps: dict[int, float] = {}
        if self.faults.touches_wire:
            data, gaps, notes = self.faults.corrupt(data, role, timing.bytesize)
            note = "; ".join(([note] if note else []) + notes)
        c = timing.char_time
        # Byte i ends at start + (i + 1) character times (+ any gap before it).  The times are summed
        # one character at a time, exactly as the line would count them: adding c n times is not
        # bit-for-bit the same float as n * c, and every timing the course prints comes from this sum.
        times: list[float] | None = None
        if gaps or timing.mode != "rtu":
            times = []
            t = start
            for index in range(len(data)):
                if index in gaps:
                    t += gaps[index] * c
                t += c
                times.append(t)
            end = times[-1] if times else start
        else:
            # RTU without gaps: the receivers only need the first and the last byte's times
            end = reduce(add, repeat(c, len(data)), start)
        node.tx_end = end
        self.free_at = end + timing.frame_gap
        self.monitor.record(
            start, "tx" if is_master else "rx", timing.mode, data, node.name,
            dest or ("slaves" if is_master else "master"), note, role, end - start,
        )
        if not data:
            return end
        if times is None and start == now and not self._buf and self._done is None:
            # The line is idle and the frame starts now: the receivers take it in at once.  (Later, or
            # while a frame is still open, the bytes reach them in an event at ``start``.)
            self._line_rtu_whole(node, data, start, end)
        else:
            clock.schedule(start, self._line, node, data, start, end, times)
        return end

    # -- receiving (one decoder: every receiver hears the same thing) --------------------------------
    def _line(self, sender: Node, data: bytes, start: float, end: float, times: list[float] | None) -> None:
        """The bytes of one transmission reach the receivers, all in one event at its start.

        ``times[i]`` is when byte ``i``'s last bit arrives.  Without gaps (``times`` is None: RTU only)
        the bytes follow each other back to back, and only the first one can end or break a frame.
        """
        if times is None:
            self._line_rtu_whole(sender, data, start, end)
        elif self.timing.mode == "rtu":
            self._line_rtu(sender, data, times)
        else:
            self._line_ascii(sender, data, times)

    def _line_rtu_whole(self, sender: Node, data: bytes, start: float, end: float) -> None:
        """:meth:`_line_rtu` for bytes sent back to back: the same decisions, without a loop.

        Between two back-to-back bytes the silence is zero (a float rounding of it at most), so it
        never exceeds t1.5: only the silence before the first byte can close or break a frame.
        """
        timing = self.timing
        c = timing.char_time
        t = start + c  # the first byte's time, computed as the per-byte sum computes it
        buf = self._buf
        if buf:
            silence = (t - c) - self._last
            if silence >= timing.t35 - _EPS:
                self._schedule_done()  # what came before was a complete frame
                buf = self._buf
            elif silence > timing.t15 + _EPS and not self._broken:
                self._broken = True
        if not buf:
            self._first = t - c
            self._sender = sender
        buf += data
        self._last = end
        self._schedule_done(keep_open=True)

    def _line_rtu(self, sender: Node, data: bytes, times: list[float]) -> None:
        timing = self.timing
        c, t15, t35 = timing.char_time, timing.t15, timing.t35
        buf = self._buf
        for byte, t in zip(data, times):
            if buf:
                silence = (t - c) - self._last
                if silence >= t35 - _EPS:
                    self._schedule_done()  # what came before was a complete frame
                    buf = self._buf
                elif silence > t15 + _EPS and not self._broken:
                    self._broken = True
            if not buf:
                self._first = t - c
                self._sender = sender
            buf.append(byte)
            self._last = t
        self._schedule_done(keep_open=True)

    def _schedule_done(self, keep_open: bool = False) -> None:
        """Arrange for the pending frame to be delivered at ``last byte + t3.5``.

        With ``keep_open`` the frame may still be continued by a later transmission (the timer is then
        cancelled); otherwise it is closed now and a new frame starts with the next byte.
        """
        if self._done is not None:
            self._done.cancel()
            self._done = None
        if not self._buf:
            return
        when = self._last + self.timing.t35
        if keep_open:
            self._done = self.clock.call_at(when, self._close_frame)
            return
        self.clock.schedule(when, self._deliver, bytes(self._buf), self._sender, self._first, self._broken)
        self._buf = bytearray()
        self._broken = False

    def _close_frame(self) -> None:
        self._done = None
        frame, sender, first, broken = bytes(self._buf), self._sender, self._first, self._broken
        self._buf = bytearray()
        self._broken = False
        self._deliver(frame, sender, first, broken)

    def _line_ascii(self, sender: Node, data: bytes, times: list[float]) -> None:
        timing = self.timing
        c, limit = timing.char_time, timing.ascii_timeout
        for byte, t in zip(data, times):
            buf = self._buf
            if buf and (t - c) - self._last > limit + _EPS:
                self.stats.discarded_frames += 1  # inter-character timeout
                self._note(f"ASCII frame discarded: more than {limit:g} s of silence inside it")
                buf.clear()
            if byte == 0x3A:  # ':' starts a frame, even in the middle of one
                if buf:
                    self.stats.discarded_frames += 1
                    self._note("ASCII frame discarded: a new ':' arrived before its CR LF")
                buf.clear()
                buf.append(byte)
                self._first = t - c
                self._sender = sender
                self._last = t
                continue
            if not buf:
                self.stats.junk_bytes += 1
                continue
            buf.append(byte)
            self._last = t
            if byte == 0x0A and len(buf) >= 2 and buf[-2] == 0x0D:
                self.clock.schedule(t, self._deliver, bytes(buf), self._sender, self._first, False)
                buf.clear()
            elif len(buf) >= 513:
                self.stats.discarded_frames += 1
                self._note("ASCII frame discarded: 513 characters without CR LF")
                buf.clear()

    def _note(self, text: str) -> None:
        """Add a line event to the note of the newest monitor entry."""
        self.monitor.annotate(text)

    def _deliver(self, frame: bytes, sender: Node | None, first: float, broken: bool) -> None:
        if broken:
            self.stats.broken_frames += 1
            self._note(
                f"frame broken by a silence of more than 1.5 characters: receivers discard its "
                f"{len(frame)} bytes"
            )
            return
        self.stats.frames += 1
        now = self.clock.now
        previous, self.current_sender = self.current_sender, sender
        try:
            for node in list(self.nodes):
                if node is sender:
                    continue
                if first < node.tx_end - _EPS:
                    self.stats.ignored_frames += 1
                    continue
                node.on_frame(frame, now)
        finally:
            self.current_sender = previous

    def pending_input(self) -> deque[bytes]:  # pragma: no cover - convenience for debugging
        return deque([bytes(self._buf)]) if self._buf else deque()
