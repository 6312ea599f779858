"""In-process links on a virtual clock: a serial bus and a TCP connection, with slaves at the far end.

:func:`loopback_serial` builds a virtual RS-232/RS-485 line (see :mod:`modbus_edu.links.wire` for its
timing rules) with one or several :class:`~modbus_edu.slave.Slave` objects on it, and returns the
master's end as a :class:`~modbus_edu.links.base.Link`.  :func:`loopback_tcp` does the same for
Modbus/TCP, with a configurable network latency.

Everything runs on ``link.clock``, a :class:`~modbus_edu.clock.VirtualClock`: ``receive(timeout)`` runs
the simulation until a frame arrives or the timeout passes, and returns at once in real time.  With a
slave's processing time of 0, one FC3 transaction for 1 register at 9600 baud 8N1 advances
``link.clock.now`` by exactly (8 + 3.5 + 7 + 3.5) x 10 / 9600 s = 22.92 ms.

>>> import modbus_edu as mb
>>> from modbus_edu.slave import Slave
>>> link = loopback_serial(Slave(unit=1), baudrate=9600)
>>> frame = bytes.fromhex("01 03 00 00 00 01 84 0A")
>>> link.send(frame)
>>> link.receive(timeout=1.0).hex(" ")
'01 03 02 00 00 b8 44'
>>> round(link.clock.now * 1000, 2)
22.92
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable
from functools import partial

from ..clock import VirtualClock
from ..crc import crc16, lrc
from ..errors import ConfigError, LinkError, guard_numbers, shown
from ..framing import TcpSplitter
from ..slave import Slave
from ..traffic import TrafficLog
from .base import Link
from .faults import Faults
from .routing import GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND, exception_reply, normalize_slaves, route_unit
from .wire import BusStats, SerialBus, SerialTiming, same_format, uart_receive

__all__ = ["LoopbackSerialLink", "LoopbackTcpLink", "loopback_serial", "loopback_tcp"]


def _slave_list(slaves: Slave | Iterable[Slave] | None) -> list[Slave]:
    if slaves is None:
        return []
    if isinstance(slaves, Slave):
        return [slaves]
    if isinstance(slaves, dict):
        slaves = slaves.values()
    try:
        result = list(slaves)
    except TypeError:
        raise ConfigError(f"expected a Slave or a list of Slaves, got {type(slaves).__name__}") from None
    for s in result:
        if not isinstance(s, Slave):
            raise ConfigError(f"expected Slave objects, got {type(s).__name__} {shown(s)}")
    return result


def _check_timeout(timeout: float) -> float:
    try:
        timeout = float(timeout)
    except (TypeError, ValueError, OverflowError):
        raise ConfigError(f"timeout must be a number of seconds, got {shown(timeout)}") from None
    if not timeout >= 0:
        raise ConfigError(f"timeout must be >= 0 s, got {shown(timeout)}")
    return timeout


def _rewrite_unit(frame: bytes, mode: str, unit: int) -> bytes:
    """The same response with another unit id (checksum recomputed): the ``answer_as`` fault."""
    if mode == "tcp":
        return frame[:6] + bytes([unit]) + frame[7:]
    if mode == "ascii":
        body = bytes([unit]) + bytes.fromhex(frame[3:-4].decode("ascii"))
        return b":" + (body + bytes([lrc(body)])).hex().upper().encode("ascii") + b"\r\n"
    body = bytes([unit]) + frame[1:-2]
    return body + crc16(body).to_bytes(2, "little")


def _frame_unit(frame: bytes, mode: str) -> int | None:
    """The unit byte of a raw frame, or None if it cannot be read."""
    try:
        if mode == "tcp":
            return frame[6] if len(frame) > 6 else None
        if mode == "ascii":
            return int(frame[1:3], 16) if len(frame) >= 3 and frame[:1] == b":" else None
        return frame[0] if frame else None
    except ValueError:
        return None


class _LoopbackLink(Link):
    """What both loopback links share: the clock, the inbox, ``receive``, the slaves, the faults."""

    clock: VirtualClock

    def __init__(self, mode: str, clock: VirtualClock | None, seed: int | None) -> None:
        self.mode = mode
        self.clock = clock if clock is not None else VirtualClock()
        self.faults = Faults(seed)
        self.monitor = TrafficLog()
        self._inbox: deque[bytes] = deque()
        self._slaves: list[Slave] = []

    @property
    def slaves(self) -> list[Slave]:
        """The slaves at the far end (a copy of the list: use :meth:`attach` / :meth:`detach`)."""
        return list(self._slaves)

    def receive(self, timeout: float) -> bytes | None:
        """Run the virtual clock until a complete frame has arrived (then return it) or ``timeout`` passes."""
        if self.closed:
            self._check_open()
        if timeout.__class__ is not float or not timeout >= 0:
            timeout = _check_timeout(timeout)
        inbox = self._inbox
        if not inbox:
            clock = self.clock
            clock.run_until(clock.now + timeout, inbox.__len__)
        return inbox.popleft() if inbox else None

    def run(self, seconds: float) -> None:
        """Let ``seconds`` of virtual time pass (slaves keep working; frames that arrive are kept)."""
        self.clock.advance(seconds)

    def close(self) -> None:
        self.closed = True
        self._inbox.clear()

    def _check_open(self) -> None:
        if self.closed:
            raise LinkError(f"{self.description}: the link is closed; create a new one")


class LoopbackSerialLink(_LoopbackLink):
    """The master's end of a virtual serial line with slaves on it.  Build it with :func:`loopback_serial`.

    ``timing`` (a :class:`~modbus_edu.links.wire.SerialTiming`) holds the line settings and the derived
    character time, t1.5 and t3.5; ``bus`` is the :class:`~modbus_edu.links.wire.SerialBus`;
    ``monitor`` a :class:`~modbus_edu.traffic.TrafficLog` of everything on the line; ``faults`` the
    :class:`~modbus_edu.links.faults.Faults` injected; ``stats`` what the line saw.

    **A slave's own line settings.**  A slave that has a ``serial_settings`` attribute (a mapping with
    any of the keys ``"baudrate"``, ``"parity"``, ``"stopbits"``, ``"bytesize"``; a missing key means
    "as the line") listens and talks with those settings, as a real device does with what its
    configuration says.  :class:`~modbus_edu.devices.ArduinoSlave` and
    :class:`~modbus_edu.devices.PowerMeter` have one; on a plain :class:`~modbus_edu.slave.Slave` you may
    set one (``slave.serial_settings = {"baudrate": 19200}``).  The attribute is read for every frame,
    so correcting it mends the wire.  When the settings match the line's (the usual case) nothing
    changes.  When they differ, the slave's receiver samples the line at its own speed and format
    (:func:`~modbus_edu.links.wire.uart_receive`): it assembles garbage (framing errors, characters with
    a parity error dropped), its CRC check fails (``slave.counters``), and it never answers; the
    monitor's note says what its receiver made of the frame.  (A stop-bit difference alone goes
    unnoticed, as on a real line.)
    """

    def __init__(
        self,
        slaves: Slave | Iterable[Slave] | None = None,
        *,
        baudrate: int = 9600,
        parity: str = "N",
        stopbits: float = 1,
        mode: str = "rtu",
        bytesize: int | None = None,
        seed: int | None = 0,
        clock: VirtualClock | None = None,
        ascii_timeout: float = 1.0,
    ) -> None:
        if mode not in ("rtu", "ascii"):
            raise ConfigError(f"a serial line carries 'rtu' or 'ascii' frames, got mode {shown(mode)}")
        if bytesize is None:
            bytesize = 8 if mode == "rtu" else 7
        super().__init__(mode, clock, seed)
        self.timing = SerialTiming(baudrate, parity, stopbits, bytesize, mode, ascii_timeout)
        self.bus = SerialBus(self.timing, self.clock, self.faults, self.monitor)
        self._node = self.bus.attach("master", self._on_frame, is_master=True)
        self._slave_nodes: dict[int, object] = {}
        self._uarts: dict[int, tuple[tuple, SerialTiming | None]] = {}
        for slave in _slave_list(slaves):
            self.attach(slave)

    # -- the bus ------------------------------------------------------------------------------------
    def attach(self, slave: Slave) -> None:
        """Connect one more slave to the bus (RS-485 multidrop)."""
        if not isinstance(slave, Slave):
            raise ConfigError(f"expected a Slave, got {type(slave).__name__}")
        if id(slave) in self._slave_nodes:
            return
        node = self.bus.attach(slave.name, partial(self._slave_hears, slave))
        self._slave_nodes[id(slave)] = node
        self._slaves.append(slave)
        if slave.clock is None:
            slave.clock = self.clock

    def detach(self, slave: Slave) -> None:
        """Disconnect a slave from the bus."""
        node = self._slave_nodes.pop(id(slave), None)
        self._uarts.pop(id(slave), None)
        if node is not None:
            self.bus.detach(node)  # type: ignore[arg-type]
            self._slaves.remove(slave)

    @property
    def stats(self) -> BusStats:
        """What the line saw: frames, broken frames, discarded frames, ..."""
        return self.bus.stats

    def uart_of(self, slave: Slave) -> SerialTiming | None:
        """The slave's own line settings when they differ from the line's, else None.

        Read from ``slave.serial_settings`` (see the class documentation); a bad value raises
        :class:`~modbus_edu.errors.ConfigError` naming the slave.
        """
        settings = getattr(slave, "serial_settings", None)
        if not settings:
            return None
        line = self.timing
        try:
            get = settings.get
        except AttributeError:
            raise ConfigError(f"{slave.name}: serial_settings must be a mapping such as "
                              f"{{'baudrate': 9600, 'parity': 'N', 'stopbits': 1}}, got {shown(settings)}"
                              ) from None
        key = (get("baudrate", line.baudrate), get("parity", line.parity), get("stopbits", line.stopbits),
               get("bytesize", line.bytesize))
        cached = self._uarts.get(id(slave))
        if cached is not None and cached[0] == key:
            return cached[1]
        baudrate, parity, stopbits, bytesize = key
        try:
            uart = SerialTiming(baudrate, parity, stopbits, bytesize, "rtu" if bytesize == 8 else "ascii")
        except ConfigError as exc:
            raise ConfigError(f"{slave.name}'s serial_settings: {exc}") from None
        result = None if same_format(uart, line) else uart
        self._uarts[id(slave)] = (key, result)
        return result

    def _slave_hears(self, slave: Slave, frame: bytes, when: float) -> None:
        faults = self.faults
        mode = self.mode
        if faults.silences(slave.unit):
            # cut off the bus: it hears nothing; a frame addressed to it uses up one of the fault's requests
            unit = _frame_unit(frame, mode)
            if unit is not None and (unit == 0 or slave.accepts(unit)):
                faults.is_silenced(slave.unit)
                self._annotate(f"{slave.name} is silenced: it does not hear this frame")
            return
        uart = self.uart_of(slave)
        if faults.swapped(slave.unit):
            # A and B swapped at its terminals: its transceiver sees every level inverted
            faults.injected["inverted"] += 1
            reading = uart_receive(frame, self.timing, uart or self.timing, inverted=True)
            self._annotate(f"{slave.name} is wired with A and B swapped: its receiver assembles "
                           f"{reading.describe()}")
            frame = reading.data
            if not frame:
                return
        elif uart is not None:
            # the slave's UART samples the line with its own settings: it assembles something else
            reading = uart_receive(frame, self.timing, uart)
            self._annotate(f"{slave.name} listens at {uart}: its receiver assembles {reading.describe()}")
            frame = reading.data
            if not frame:
                return
        # who sent it: the master, or (on a multidrop bus) another slave answering the master
        sender = self.bus.current_sender
        source = sender.name if sender is not None else "master"
        answer = slave.hear(frame, mode, source)
        if answer is None:
            return
        other = faults.wrong_unit(slave.unit)
        if other is not None:
            answer = _rewrite_unit(answer, mode, other)
        delay = slave.response_delay(when) + faults.extra_delay(slave.unit)
        node = self._slave_nodes[id(slave)]
        if delay > 0:
            self.clock.schedule(when + delay, node.transmit, answer, "master", uart)  # type: ignore[attr-defined]
        else:
            node.transmit(answer, "master", uart)  # type: ignore[attr-defined]

    def _annotate(self, text: str) -> None:
        self.monitor.annotate(text)

    def _on_frame(self, frame: bytes, when: float) -> None:
        self._inbox.append(frame)

    def _echo_back(self, frame: bytes) -> None:
        self._annotate("the adapter echoed this request back to the master")
        self._inbox.append(frame)

    # -- the Link interface ---------------------------------------------------------------------------
    def send(self, frame: bytes) -> None:
        """Put one frame on the line (now, or as soon as the line is free)."""
        self._check_open()
        if not isinstance(frame, (bytes, bytearray, memoryview)):
            raise LinkError(f"send() takes the bytes of one frame, got {type(frame).__name__}")
        data = bytes(frame)
        dest = ""
        unit = _frame_unit(data, self.mode)
        if unit is not None:
            dest = "broadcast" if unit == 0 else f"unit {unit}"
        end = self._node.transmit(data, dest)
        if self.faults.echo and data:
            # the adapter's receiver stays on while it transmits: the request comes back to the master,
            # a frame of its own once the line has been quiet for 3.5 characters
            self.faults.injected["echoed"] += 1
            self.clock.schedule(end + self.timing.frame_gap, self._echo_back, data)

    def flush(self) -> None:
        """Run the clock until the line is free: what was sent has arrived and its 3.5-char silence passed."""
        self._check_open()
        free = self.bus.free_at
        if free > self.clock.now:
            self.clock.run_until(free)

    @property
    def description(self) -> str:
        n = len(self._slaves)
        kind = "RS-485 bus" if n > 1 else "serial line"
        return f"virtual {kind}, {self.timing}, {self.mode.upper()}, {n} slave{'s' if n != 1 else ''}"


class LoopbackTcpLink(_LoopbackLink):
    """The client's end of a virtual Modbus/TCP connection to a server holding slaves.

    Build it with :func:`loopback_tcp`.  Each direction takes ``latency`` seconds.  The server handles
    one request at a time, in order (like most real servers on one connection): a request that arrives
    while the previous one is still being answered waits its turn.  Unit 0 is broadcast (every slave
    acts, none answers); other units reach the slave with that unit, and no answer comes back if there is
    none.  ``monitor`` logs both directions as the server sees them.
    """

    def __init__(
        self,
        slaves: Slave | Iterable[Slave] | None = None,
        *,
        latency: float = 0.0,
        seed: int | None = 0,
        clock: VirtualClock | None = None,
    ) -> None:
        super().__init__("tcp", clock, seed)
        try:
            latency = float(latency)
        except (TypeError, ValueError, OverflowError):
            raise ConfigError(f"latency must be a number of seconds, got {shown(latency)}") from None
        if not latency >= 0:
            raise ConfigError(f"latency must be >= 0 s, got {shown(latency)}")
        self.latency = latency
        self._server_splitter = TcpSplitter()
        self._client_splitter = TcpSplitter()
        self._server_busy_until = float("-inf")
        self._in_flight_until = float("-inf")
        for slave in _slave_list(slaves):
            self.attach(slave)

    def attach(self, slave: Slave) -> None:
        """Put one more slave behind the server."""
        if not isinstance(slave, Slave):
            raise ConfigError(f"expected a Slave, got {type(slave).__name__}")
        if slave not in self._slaves:
            self._slaves.append(slave)
            if slave.clock is None:
                slave.clock = self.clock

    def detach(self, slave: Slave) -> None:
        if slave in self._slaves:
            self._slaves.remove(slave)

    def send(self, frame: bytes) -> None:
        """Send bytes to the server; they arrive ``latency`` seconds later."""
        self._check_open()
        if not isinstance(frame, (bytes, bytearray, memoryview)):
            raise LinkError(f"send() takes the bytes of one frame, got {type(frame).__name__}")
        data = bytes(frame)
        if self.faults.touches_wire:
            raise ConfigError(
                "bit errors and lost bytes are serial-line faults: TCP checks and retransmits its "
                "segments, so a Modbus/TCP frame arrives whole or not at all; use delay/silence/answer_as"
            )
        arrival = self.clock.now + self.latency
        self._in_flight_until = max(self._in_flight_until, arrival)
        self.clock.schedule(arrival, self._server_receives, data)

    def flush(self) -> None:
        """Run the clock until every request sent so far has reached the server and been handled."""
        self._check_open()
        until = max(self._in_flight_until, self._server_busy_until)
        if until > self.clock.now:
            self.clock.run_until(until)

    def _server_receives(self, data: bytes) -> None:
        for frame in self._server_splitter.feed(data):
            start = max(self.clock.now, self._server_busy_until)
            if start > self.clock.now:
                self._server_busy_until = start  # queued behind the request being answered
                self.clock.schedule(start, self._serve, frame)
            else:
                self._serve(frame)

    def _serve(self, frame: bytes) -> None:
        """The server's side: route by unit id as :class:`~modbus_edu.links.tcp.TcpServer` does
        (:func:`~modbus_edu.links.routing.route_unit`: one slave is reached by units 0 and 0xFF too; a unit
        nobody serves is answered with exception 0x0B; TCP has no broadcast)."""
        now = self.clock.now
        self.monitor.record(now, "tx", "tcp", frame, "client", self._dest(frame), "", "request")
        if not self._slaves:
            self._annotate("no slave is attached: nobody answers")
            return
        slave, direct = route_unit(normalize_slaves(self._slaves), frame[6])
        if slave is None:
            answer = exception_reply(frame, GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND)
            self._annotate(f"no slave at unit {frame[6]}: the server answers exception 0x0B")
            if answer is not None:
                self._server_busy_until = max(self._server_busy_until, now)
                self.clock.schedule(now, self._server_sends, answer, "server")
            return
        faults = self.faults
        if faults.is_silenced(slave.unit):
            self._annotate(f"{slave.name} is silenced: it does not see this request")
            return
        answer = slave.handle_direct(frame) if direct else slave.handle(frame, "tcp")
        if answer is None:
            return
        other = faults.wrong_unit(slave.unit)
        if other is not None:
            answer = _rewrite_unit(answer, "tcp", other)
        done = now + slave.response_delay(now) + faults.extra_delay(slave.unit)
        self._server_busy_until = max(self._server_busy_until, done)
        self.clock.schedule(done, self._server_sends, answer, slave.name)

    def _server_sends(self, answer: bytes, name: str) -> None:
        self.monitor.record(self.clock.now, "rx", "tcp", answer, name, "client", "", "response")
        self.clock.schedule(self.clock.now + self.latency, self._client_receives, answer)

    def _client_receives(self, data: bytes) -> None:
        self._inbox.extend(self._client_splitter.feed(data))

    def _annotate(self, text: str) -> None:
        self.monitor.annotate(text)

    @staticmethod
    def _dest(frame: bytes) -> str:
        unit = _frame_unit(frame, "tcp")
        if unit is None:
            return "server"
        return f"unit {unit}"

    @property
    def description(self) -> str:
        n = len(self._slaves)
        lat = f", latency {self.latency * 1000:g} ms" if self.latency else ""
        return f"virtual Modbus/TCP connection{lat}, {n} slave{'s' if n != 1 else ''}"


@guard_numbers
def loopback_serial(
    slaves: Slave | Iterable[Slave] | None = None,
    baudrate: int = 9600,
    parity: str = "N",
    stopbits: float = 1,
    mode: str = "rtu",
    bytesize: int | None = None,
    seed: int | None = 0,
    *,
    clock: VirtualClock | None = None,
    ascii_timeout: float = 1.0,
) -> LoopbackSerialLink:
    """A virtual serial line (RS-232 with one slave, RS-485 multidrop with several), as a master's Link.

    ``slaves``: one :class:`~modbus_edu.slave.Slave` or a list.  ``mode``: ``"rtu"`` (8 data bits) or
    ``"ascii"`` (7 data bits unless ``bytesize=8``).  ``seed`` seeds the fault injector.  The link's
    ``clock`` is a :class:`~modbus_edu.clock.VirtualClock`; ``link.clock.now`` is its time in seconds.
    """
    return LoopbackSerialLink(
        slaves, baudrate=baudrate, parity=parity, stopbits=stopbits, mode=mode, bytesize=bytesize,
        seed=seed, clock=clock, ascii_timeout=ascii_timeout,
    )


@guard_numbers
def loopback_tcp(
    slaves: Slave | Iterable[Slave] | None = None,
    latency: float = 0.0,
    seed: int | None = 0,
    *,
    clock: VirtualClock | None = None,
) -> LoopbackTcpLink:
    """A virtual Modbus/TCP connection to a server holding ``slaves`` (selected by unit id)."""
    return LoopbackTcpLink(slaves, latency=latency, seed=seed, clock=clock)
