"""The Modbus slave (a *server* in the words of Modbus/TCP): a request in, a response out.

A slave owns a :class:`~modbus_edu.datamodel.DataBank`, the four tables a master can read and write.
It never speaks first.  For each frame that reaches it, in this order (the order of a real device):

1. **Check the frame.**  A wrong CRC (RTU) or LRC (ASCII), or a frame that does not follow the rules of
   its mode, gets *no answer at all*: the slave cannot trust any byte of it, not even the address.  The
   master will time out.  Counted in ``counters.checksum_errors`` / ``counters.bad_frames``.
2. **Check the unit.**  A request for another unit is none of its business: silence
   (``counters.other_unit``).  On a serial bus every slave hears every frame, so this is normal.
   Unit 0 is the **broadcast** address of a serial line: every slave carries out the write (FC 5, 6,
   15, 16, 21, 22: :data:`~modbus_edu.codes.BROADCAST_FUNCTIONS`, the table the master follows too),
   and none answers (``counters.broadcasts``).  A broadcast of any other function (a read, FC 8
   Diagnostics, and, by this library's choice, FC 23 Read/Write Multiple Registers) has no meaning here:
   it is counted, neither carried out nor answered.
3. **Carry out the request** on the bank and answer, or answer an **exception response** (the function
   code with its top bit set, and an exception code):

   ==  =========================  ===============================================================
   01  illegal function           the function code is not one this slave implements
   02  illegal data address       the addresses are outside the bank (or not declared in a sparse one)
   03  illegal data value         a bad quantity, a value that does not fit, a byte count or a length
                                  that disagrees with the rest of the request
   04  server device failure      the device failed while doing it (here: a user hook raised)
   ==  =========================  ===============================================================

Units: a ``Slave(unit=5)`` answers unit 5 only, in every mode.  ``Slave(unit=None)`` answers any unit
(1..247 on a serial line, 1..255 on TCP).  :meth:`handle` applies the serial-line rule to unit 0
(broadcast: acted on, never answered) whatever the mode, because a slave cannot know how it was reached.
Modbus/TCP has no broadcast: the *Modbus Messaging on TCP/IP Implementation Guide* (V1.0b, section
4.4.1.2, "Unit Identifier") says that a server reached directly by its IP address does not need the unit
identifier, that clients should send 0xFF, and that 0 is accepted too, to talk to the device itself.
The server that knows the device was reached that way says so by calling :meth:`handle_direct`: the
slave answers whatever the unit id, and its response carries the request's unit id back
(:class:`~modbus_edu.links.tcp.TcpServer` does it for units 0 and 0xFF when it serves a single slave).

Hooks let a simulated device come alive: ``on_read(slave, table_kind, address, count)`` runs *before* a
read (update the values there: a meter measures when asked), ``on_write(slave, table_kind, address,
values)`` *after* a write (react to a set-point).  Subclasses may override :meth:`before_read` and
:meth:`after_write` instead.  A hook that raises makes the slave answer exception 04; a hook that raises
:class:`~modbus_edu.errors.ModbusExceptionError` chooses the exception code itself (06 "busy", say).

Time: a slave takes :meth:`response_delay` seconds to answer (``processing_time`` by default, 0).  Links
with a clock use it; a device with a slow main loop overrides it.

Sans-I/O: :meth:`handle` takes the bytes of one frame and returns the bytes of the answer (or None).
It never touches a socket, a port or a clock; the links do.
"""

from __future__ import annotations

import dataclasses
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, fields
from functools import cache, lru_cache
from typing import Any, ClassVar

from . import pdu as _pdu
from .codes import BROADCAST_FUNCTIONS
from .codes import MBAP as _MBAP
from .datamodel import DataBank, Table, table_kind
from .errors import (
    AddressRangeError,
    ChecksumError,
    ConfigError,
    FrameError,
    IllegalAddressError,
    ModbusError,
    ModbusExceptionError,
    PduError,
    UnknownFunctionError,
    guard_numbers,
    shown,
)
from .framing import MODES, Frame, decode_frame, make_frame
from .framing.tcp import is_one_frame
from .pdu import ExceptionCode, ExceptionResponse, Pdu
from .traffic import TrafficLog, pdu_note

__all__ = ["Slave", "SlaveCounters", "dispatch"]

ReadHook = Callable[["Slave", str, int, int], Any]
WriteHook = Callable[["Slave", str, int, list], Any]

_SEND_EVENT = {1: 0x01, 2: 0x01, 3: 0x01, 4: 0x02, 5: 0x04, 6: 0x04, 7: 0x08}
"""FC 12's send-event bits for an exception response: read exception (01-03), abort (04), busy (05, 06),
program NAK (07)."""

_RESETS_EVENT_COUNT = frozenset({0x01, 0x0A})
"""FC 8's Restart Communications and Clear Counters reset FC 11's event counter (spec, section 6.9)."""


def _counts_as_event(response: Pdu) -> bool:
    """Whether a normal response adds one to FC 11's event counter: not FC 11 and FC 12 themselves (the
    spec's fetch commands), nor the FC 8 sub-functions that just reset it."""
    code = response.function_code
    if code == 0x08:
        return response.sub_function not in _RESETS_EVENT_COUNT  # type: ignore[attr-defined]
    return code not in (0x0B, 0x0C)


@dataclass
class SlaveCounters:
    """What a slave has seen (the diagnostic counters of a real device, simplified).

    ``requests``         requests carried out or answered: for this unit, broadcast, or handed to
                         :meth:`Slave.handle_direct` (a Modbus/TCP request for the device itself)
    ``responses``        responses sent, exception responses included
    ``exceptions``       exception responses sent
    ``checksum_errors``  frames dropped because the CRC / LRC did not match
    ``bad_frames``       frames dropped because they broke the rules of their mode (length, ':' and
                         CR LF, MBAP header, reserved unit 248..255, function code 0 or 128..255)
    ``broadcasts``       broadcast requests (unit 0) received: carried out, never answered
    ``other_unit``       valid frames for another unit, ignored
    """

    requests: int = 0
    responses: int = 0
    exceptions: int = 0
    checksum_errors: int = 0
    bad_frames: int = 0
    broadcasts: int = 0
    other_unit: int = 0

    def reset(self) -> None:
        """Set every counter back to 0."""
        for f in fields(self):
            setattr(self, f.name, 0)

    def as_dict(self) -> dict[str, int]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


#: What a plain :class:`Slave` does with a request: a class that changes any of it answers the general way.
_REQUEST_PATH = ("handle", "_handle", "_answer", "process", "_execute", "_read_table", "before_read",
                 "accepts", "HANDLERS")


@cache
def _plain_slave(cls: type) -> bool:
    """Whether ``cls`` handles a request as :class:`Slave` does (its own subclasses may override a part)."""
    return all(getattr(cls, name) is getattr(Slave, name) for name in _REQUEST_PATH)


def _plain_tables(bank: DataBank) -> bool:
    """Whether every table of ``bank`` is a plain :class:`~modbus_edu.datamodel.Table`."""
    return (bank.holding_registers.__class__ is Table and bank.input_registers.__class__ is Table
            and bank.coils.__class__ is Table and bank.discrete_inputs.__class__ is Table)


def _check_mode(mode: str) -> str:
    if mode not in MODES:
        raise ConfigError(f"mode must be one of {', '.join(MODES)}, got {shown(mode)}")
    return mode


@lru_cache(maxsize=256, typed=True)
def _decode_request(data: bytes, mode: str) -> Frame:
    """``decode_frame(data, mode, "request")``, remembered for the last 256 different frames.

    A master polls: it sends the same few requests over and over, and decoding a frame is a pure
    function of its bytes whose result is immutable, so each different request is decoded once.  A frame
    that fails to decode raises every time (errors are not remembered).  Not for TCP: there every request
    carries a new transaction id.
    """
    return decode_frame(data, mode, "request")


def _peek_unit_function(data: bytes, mode: str) -> tuple[int, int]:
    """Unit and function code of a frame whose envelope (length, checksum, header) is known good."""
    if mode == "tcp":
        return data[6], data[7]
    if mode == "ascii":
        return int(data[1:3], 16), int(data[3:5], 16)
    return data[0], data[1]


class Slave:
    """A Modbus slave: a :class:`~modbus_edu.datamodel.DataBank` that answers requests.

    ``Slave(unit=1, bank=None)`` -- ``bank`` defaults to a dense ``DataBank()`` (every address exists
    and holds 0).  Keywords: ``processing_time`` (seconds before the answer starts, on links with a
    clock), ``on_read`` / ``on_write`` hooks, ``name`` (for logs).  A setting of the wrong kind (a bank
    that is not a :class:`~modbus_edu.datamodel.DataBank`, a hook that cannot be called) raises
    :class:`~modbus_edu.errors.ConfigError` at once, not a puzzling exception 04 at the first request.

    >>> from modbus_edu.framing import RtuFrame
    >>> from modbus_edu.pdu import ReadHoldingRegistersRequest
    >>> slave = Slave(unit=1)
    >>> slave.bank.holding_registers[0] = 1234
    >>> request = RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=1)).encode()
    >>> slave.handle(request, "rtu").hex(" ")
    '01 03 02 04 d2 3a d9'
    """

    @guard_numbers
    def __init__(
        self,
        unit: int | None = 1,
        bank: DataBank | None = None,
        *,
        processing_time: float = 0.0,
        on_read: ReadHook | None = None,
        on_write: WriteHook | None = None,
        name: str | None = None,
        server_id: bytes | None = None,
        run_indicator: bool = True,
        additional_data: bytes = b"",
        exception_status: int = 0,
        identity: dict[int, str | bytes] | None = None,
    ) -> None:
        if unit is not None and (isinstance(unit, bool) or not isinstance(unit, int) or not 1 <= unit <= 255):
            raise ConfigError(
                f"a slave's unit must be 1..247 (serial) or 1..255 (TCP), or None for 'any unit'; got "
                f"{shown(unit)} (0 is the broadcast address: no slave owns it)"
            )
        try:
            processing_time = float(processing_time)
        except (TypeError, ValueError):
            raise ConfigError(
                f"processing_time must be a number of seconds, got {shown(processing_time)}"
            ) from None
        if not processing_time >= 0:
            raise ConfigError(f"processing_time must be >= 0 s, got {shown(processing_time)}")
        if bank is not None and not isinstance(bank, DataBank):
            raise ConfigError(
                f"bank must be a DataBank (the four tables a master reads and writes) or None for a new "
                f"dense one, got {type(bank).__name__} {shown(bank)}"
            )
        for hook_name, hook in (("on_read", on_read), ("on_write", on_write)):
            if hook is not None and not callable(hook):
                raise ConfigError(
                    f"{hook_name} must be a function (or None), got {type(hook).__name__} {shown(hook)}"
                )
        if name is not None and not isinstance(name, str):
            raise ConfigError(f"name must be a text (or None), got {type(name).__name__} {shown(name)}")
        self.unit = unit
        self.bank = bank if bank is not None else DataBank()
        self.processing_time = processing_time
        self.on_read = on_read
        self.on_write = on_write
        self.name = name or (f"slave {unit}" if unit is not None else "slave (any unit)")
        if not isinstance(run_indicator, bool):  # None is what a decoder says of a device's own layout
            raise ConfigError(f"run_indicator must be True (0xFF, the device runs) or False (0x00), got "
                              f"{shown(run_indicator)}")
        report = _pdu.ReportServerIdResponse(  # checks all three (a ValueRangeError)
            server_id if server_id is not None else f"modbus_edu {self.name}".encode(), run_indicator,
            additional_data)
        self.server_id = report.server_id
        """What Report Server ID (FC 17) answers first: device-specific bytes (default: the slave's name)."""
        self.run_indicator = run_indicator
        """FC 17's run indicator: True (0xFF, the device runs) or False (0x00)."""
        self.additional_data = report.additional_data
        """What FC 17 sends after the run indicator: device-specific bytes (a version text, say)."""
        self.exception_status = exception_status
        """FC 7's eight status bits, 0..255, which the device defines (0 by default: nothing to report)."""
        self.identity = _identity(identity if identity is not None else {
            0x00: "modbus_edu", 0x01: "simulated slave", 0x02: "1.0", 0x04: self.name})
        """FC 43/14's objects: id -> bytes (0-2 basic, 3-6 regular, 0x80-0xFF extended)."""
        _pdu.ReadExceptionStatusResponse(self.exception_status)
        self.counters = SlaveCounters()
        self.listen_only = False
        """FC 8/04 put the slave in listen-only mode: it counts what it hears and answers nothing, until
        FC 8/01 (restart communications)."""
        self.diagnostic_register = 0
        """FC 8/02's 16-bit register, which the device defines (0: nothing to report)."""
        self.event_count = 0
        """FC 11's count of messages completed normally."""
        self.events: deque[int] = deque(maxlen=64)
        """FC 12's event log, newest first: 0x80+ received, 0x40+ sent, 0x04 listen-only, 0x00 restart."""
        self._diagnostics_base = SlaveCounters()
        self.log = TrafficLog(maxlen=1000)
        """The newest 1000 frames this slave received (``rx``) and sent (``tx``)."""
        self.clock: Any = None
        """A clock for the log's time stamps, set by the link the slave is attached to (or None: 0.0)."""
        self.sender = "master"
        """Who sent the frame being handled, for the log: ``"master"``, unless a link that knows better
        passes the frame through :meth:`hear` (on a multidrop bus a slave also hears the other slaves)."""
        self.last_error: BaseException | None = None
        """The exception a hook raised last (the cause of an exception 04), for debugging."""
        self._direct = False  # True while handle_direct() runs: the unit id does not choose this slave
        self.listeners: list[Callable[[Slave], Any]] = []
        """Called with the slave after each request it handled (from any link, in the link's thread), its
        answer already logged: a panel that shows the slave follows its traffic this way.  A listener
        must be quick and must not raise; the list is empty unless someone watches."""

    def __repr__(self) -> str:
        unit = "any" if self.unit is None else self.unit
        return f"<{type(self).__name__} {self.name!r} unit={unit} {self.counters.as_dict()}>"

    # -- time -----------------------------------------------------------------------------------
    def response_delay(self, arrival_time: float) -> float:
        """Seconds between the end of a request (at ``arrival_time``) and the start of the answer.

        ``processing_time`` by default.  A device overrides this: a slave whose main loop runs every
        50 ms only sees a request at its next loop, so its delay depends on when the request came.
        """
        return self.processing_time

    def _now(self) -> float:
        clock = self.clock
        return clock.now if clock is not None else 0.0

    # -- units ----------------------------------------------------------------------------------
    def accepts(self, unit: int) -> bool:
        """True if a request for ``unit`` is for this slave (broadcast 0 aside: every slave acts on it)."""
        return unit != 0 and (self.unit is None or unit == self.unit)

    # -- frames ---------------------------------------------------------------------------------
    def hear(self, frame: bytes, mode: str = "rtu", source: str = "master") -> bytes | None:
        """:meth:`handle` a frame that ``source`` put on the line: what a link that knows the sender calls.

        On an RS-485 bus every node hears every frame, the other slaves' responses included.  The
        slave ignores those (they carry another unit), but its log should say who sent them:
        ``"slave 2 -> slave 1; for unit 2: ignored"``, not ``"master -> slave 1"``.  The label is
        :attr:`sender` while the frame is handled.  An answer is always logged as going to the master:
        a slave takes every request for one from the master (it cannot tell), and on a serial line only
        the master takes in responses.
        """
        previous = self.sender
        self.sender = source
        try:
            return self.handle(frame, mode)
        finally:
            self.sender = previous

    def handle_direct(self, frame: bytes) -> bytes | None:
        """:meth:`handle` a Modbus/TCP frame sent to this device itself: the unit id does not choose.

        On TCP the IP address chooses the device.  The *Modbus Messaging on TCP/IP Implementation
        Guide* (V1.0b, section 4.4.1.2) recommends unit id 0xFF for a device reached that way and accepts
        0 as well; there is no broadcast on TCP.  A server that knows the request reached this device
        directly (:class:`~modbus_edu.links.tcp.TcpServer` serving one slave, for units 0 and 0xFF) calls
        this instead of :meth:`handle`: the slave carries out the request and answers, whatever the unit
        id, and the response echoes the request's unit id (as every Modbus/TCP response does).  The
        frame goes through :meth:`handle`, so a device that overrides it (a receive buffer, say) keeps
        its behaviour.
        """
        previous = self._direct
        self._direct = True
        try:
            return self.handle(frame, "tcp")
        finally:
            self._direct = previous

    def handle(self, frame: bytes, mode: str = "rtu") -> bytes | None:
        """Process one received frame; return the bytes of the answer, or ``None`` for no answer.

        ``mode`` is ``"rtu"``, ``"ascii"`` or ``"tcp"``.  No answer when the frame is corrupt or
        malformed, for another unit, or a broadcast.  A TCP response carries the request's transaction
        identifier.  Both frames go to :attr:`log`, the received one with a note saying what became of it.
        """
        if mode not in MODES:
            mode = _check_mode(mode)
        if frame.__class__ is not bytes:
            if not isinstance(frame, (bytes, bytearray, memoryview)):
                raise FrameError(f"Slave.handle expects the bytes of one frame, got {type(frame).__name__}")
            frame = bytes(frame)
        if mode == "tcp":
            answer = self._answer_quickly(frame)
            if answer is not None:
                if self.listeners:
                    self._notify()
                return answer
        clock = self.clock
        now = clock.now if clock is not None else 0.0
        answer, response, note = self._handle(frame, mode)
        log = self.log
        sender = self.sender
        log.record(now, "rx", mode, frame, sender, self.name, note, "request")
        if answer is not None:
            log.record(now, "tx", mode, answer, self.name, "master",
                       pdu_note(response) if hasattr(response, "summary") else "", "response")
        if self.listeners:
            self._notify()
        return answer

    def _answer_quickly(self, frame: bytes) -> bytes | None:
        """The fast path of a Modbus/TCP request, or None to take the general one (:meth:`_handle`).

        A well-formed request (its MBAP header checked by bytes, as :class:`~modbus_edu.framing.TcpFrame`
        checks it) for this slave, whose function's class answers it from bytes
        (:meth:`~modbus_edu.pdu.Pdu.answer_from_bytes`: the reads), is answered without building a frame
        or a PDU object, with what the general way does: the same counters, FC 12 events and FC 11 event
        counter, the same two log entries (the answer's note written when the log is read).  It steps
        aside wherever its assumptions fail: a subclass that changes how requests are handled, hooks
        (``on_read``), a bank or a table of another class, listen-only mode, another unit, a broadcast.
        """
        if (self.on_read is not None or self.listen_only or not _plain_slave(self.__class__)
                or not is_one_frame(frame)):
            return None
        unit = frame[6]
        own = unit != 0 and (self.unit is None or unit == self.unit)  # accepts(unit), inlined
        if not (own or self._direct):
            return None
        cls = _pdu.REQUEST_CLASSES.get(frame[7])
        bank = self.bank
        if cls is None or bank.__class__ is not DataBank or not _plain_tables(bank):
            return None
        request = frame[7:]
        reply = cls.answer_from_bytes(request, bank)
        if reply is None:
            return None
        counters = self.counters
        counters.requests += 1
        counters.responses += 1
        events = self.events
        events.appendleft(0x80)
        events.appendleft(0x40)
        self.event_count = (self.event_count + 1) & 0xFFFF  # a read counts (FC 11, 12 and 8 answer slowly)
        answer = _MBAP.pack(frame[0] << 8 | frame[1], 0, len(reply) + 1, unit) + reply
        clock = self.clock
        now = clock.now if clock is not None else 0.0
        note = "" if own else f"unit {unit} on Modbus/TCP: this device itself"
        log = self.log
        log.record(now, "rx", "tcp", frame, self.sender, self.name, note, "request")
        log.record(now, "tx", "tcp", answer, self.name, "master", (request, reply), "response")
        return answer

    def _handle(self, data: bytes, mode: str) -> tuple[bytes | None, Pdu | None, str]:
        """(answer bytes, response PDU, note for the log) for one received frame."""
        counters = self.counters
        direct = self._direct and mode == "tcp"  # handle_direct(): reached by IP, the unit id does not count
        try:
            decoded = decode_frame(data, mode, "request") if mode == "tcp" else _decode_request(data, mode)
        except ChecksumError as exc:
            counters.checksum_errors += 1
            return None, None, f"dropped: {exc}"
        except FrameError as exc:
            counters.bad_frames += 1
            return None, None, f"dropped: {exc}"
        except PduError as exc:
            # The envelope was good (framing checks it before the PDU): unit and function are known.
            unit, function = _peek_unit_function(data, mode)
            if unit == 0 and not direct:
                counters.broadcasts += 1
                counters.requests += 1
                return None, None, f"broadcast not carried out: {exc}"
            if not direct and not self.accepts(unit):
                counters.other_unit += 1
                return None, None, f"for unit {unit}: ignored"
            if function == 0 or function >= 0x80:
                counters.bad_frames += 1
                return None, None, f"dropped: function code {function} cannot be requested"
            if self.listen_only:  # not even an exception response
                counters.requests += 1
                self.events.appendleft(0xA0)
                return None, None, f"listen-only mode (FC 8/04): heard, not answered ({exc})"
            if isinstance(exc, UnknownFunctionError):
                code = ExceptionCode.ILLEGAL_FUNCTION
            elif isinstance(exc, AddressRangeError):
                code = ExceptionCode.ILLEGAL_DATA_ADDRESS
            else:  # quantity, value, byte count, implied length: the spec's exception 03
                code = ExceptionCode.ILLEGAL_DATA_VALUE
            self.last_error = exc
            counters.requests += 1
            response = ExceptionResponse(function, int(code))
            return self._answer(mode, unit, response, data), response, f"refused: {exc}"
        unit = decoded.unit
        pdu = decoded.pdu
        if unit == 0 and not direct:
            counters.broadcasts += 1
            counters.requests += 1
            if self.listen_only:  # the spec: messages are monitored, no action is taken
                return None, None, "broadcast in listen-only mode (FC 8/04): heard, not carried out"
            if pdu.function_code in BROADCAST_FUNCTIONS:
                self.process(pdu)
                return None, None, "broadcast: carried out, no answer"
            return None, None, (f"broadcast of FC {pdu.function_code}: ignored (a broadcast can only write, "
                                "with FC 5, 6, 15, 16, 21 or 22)")
        if not direct and (not self.accepts(unit) or (unit > 247 and unit != self.unit and mode != "tcp")):
            counters.other_unit += 1  # a reserved serial address is answered only by a slave set to it
            return None, None, f"for unit {unit}: ignored"
        counters.requests += 1
        self.events.appendleft(0x80 | (0x20 if self.listen_only else 0))
        # listen-only mode silences the slave whatever the unit reached it (0 and 0xFF on TCP too), until
        # Restart Communications (FC 8/01)
        if self.listen_only and not (pdu.function_code == 0x08 and pdu.sub_function == 0x01):
            return None, None, "listen-only mode (FC 8/04): heard, not answered"
        response = self.process(pdu)
        if response is None:
            return None, None, "no answer, as the request asks"
        note = "" if self.accepts(unit) else f"unit {unit} on Modbus/TCP: this device itself"
        return self._answer(mode, unit, response, data), response, note

    def _answer(self, mode: str, unit: int, response: Pdu, request: bytes) -> bytes:
        counters = self.counters
        counters.responses += 1
        if isinstance(response, ExceptionResponse):
            counters.exceptions += 1
            code = response.code
            self.events.appendleft(0x40 | _SEND_EVENT.get(code, 0))
        else:
            self.events.appendleft(0x40)
            if _counts_as_event(response):
                self.event_count = (self.event_count + 1) & 0xFFFF
        tid = int.from_bytes(request[0:2], "big") if mode == "tcp" else 0
        return make_frame(mode, unit, response, tid).encode()

    # -- PDUs -----------------------------------------------------------------------------------
    def handle_pdu(self, request: Pdu) -> Pdu:
        """Carry out a request PDU and return the response PDU (an ExceptionResponse if it failed).

        Counts the request and the response, like :meth:`handle`.
        """
        counters = self.counters
        counters.requests += 1
        response = self.process(request)
        counters.responses += 1
        if isinstance(response, ExceptionResponse):
            counters.exceptions += 1
        if self.listeners:
            self._notify()
        return response

    def _notify(self) -> None:
        for listener in tuple(self.listeners):  # a listener may remove itself
            listener(self)

    def process(self, request: Pdu) -> Pdu:
        """The heart of the slave: the bank read or written, the response built.  Counts nothing.

        Never raises for a protocol problem: every failure becomes an exception response.
        """
        function = getattr(request, "function_code", 0)
        if getattr(request, "role", None) != "request" or function not in self.HANDLERS:
            function = function & 0x7F if isinstance(function, int) and function & 0x7F else 1
            return ExceptionResponse(function, int(ExceptionCode.ILLEGAL_FUNCTION))
        try:
            return self._execute(request)
        except ModbusExceptionError as exc:
            self.last_error = exc
            try:
                return ExceptionResponse(function, exc.code)
            except ModbusError:  # a hook chose an impossible code: that is a device failure
                return ExceptionResponse(function, int(ExceptionCode.SERVER_DEVICE_FAILURE))
        except (IllegalAddressError, AddressRangeError) as exc:
            self.last_error = exc
            return ExceptionResponse(function, int(ExceptionCode.ILLEGAL_DATA_ADDRESS))
        except PduError as exc:
            self.last_error = exc
            return ExceptionResponse(function, int(ExceptionCode.ILLEGAL_DATA_VALUE))
        except Exception as exc:  # noqa: BLE001 - a failing hook or device is exception 04
            self.last_error = exc
            return ExceptionResponse(function, int(ExceptionCode.SERVER_DEVICE_FAILURE))

    #: The method that carries out each function code's request: a new function code adds its line here.
    HANDLERS: ClassVar[dict[int, str]] = {
        0x01: "_read_table", 0x02: "_read_table", 0x03: "_read_table", 0x04: "_read_table",
        0x05: "_write_single", 0x06: "_write_single", 0x0F: "_write_multiple", 0x10: "_write_multiple",
        0x07: "_read_exception_status", 0x08: "_diagnose", 0x0B: "_get_event_counter",
        0x0C: "_get_event_log", 0x11: "_report_server_id", 0x14: "_read_file_records",
        0x15: "_write_file_records", 0x16: "_mask_write_register", 0x17: "_read_write_registers",
        0x18: "_read_fifo_queue", 0x2B: "_identify",
    }

    def _execute(self, request: Any) -> Pdu | None:
        return getattr(self, self.HANDLERS[request.function_code])(request)

    def _read_table(self, request: Any) -> Pdu:
        """FC 1-4: the table of the function, read."""
        kind = table_kind(request.function_code)
        self.before_read(kind, request.address, request.count)
        values = tuple(self.bank.table(kind).read(request.address, request.count))
        cls = _pdu.RESPONSE_CLASSES[request.function_code]
        return cls(bits=values) if request.function_code in (1, 2) else cls(registers=values)

    def _write_single(self, request: Any) -> Pdu:
        """FC 5 and 6: one coil or register written; the response echoes the request."""
        kind = table_kind(request.function_code)
        values = [request.value]
        self.bank.table(kind).write(request.address, values)
        self.after_write(kind, request.address, values)
        return _pdu.RESPONSE_CLASSES[request.function_code](address=request.address, value=request.value)

    def _write_multiple(self, request: Any) -> Pdu:
        """FC 15 and 16: coils or registers written; the response says where and how many."""
        kind = table_kind(request.function_code)
        values = list(request.values)
        self.bank.table(kind).write(request.address, values)
        self.after_write(kind, request.address, values)
        return _pdu.RESPONSE_CLASSES[request.function_code](address=request.address, count=len(values))

    def _read_exception_status(self, request: Any) -> Pdu:
        """FC 7: the eight exception status outputs."""
        return _pdu.ReadExceptionStatusResponse(self.exception_status)

    def _report_server_id(self, request: Any) -> Pdu:
        """FC 17: the server ID, the run indicator and the additional data, in the spec's order."""
        return _pdu.ReportServerIdResponse(self.server_id, self.run_indicator, self.additional_data)

    def diagnostic_counters(self) -> dict[int, int]:
        """FC 8's counters by sub-function, since the last restart or clear (16 bits each).

        0x0B messages heard on the bus with a good checksum (the serial-line guide's Appendix A: "messages
        with bad CRC are not taken into account"), 0x0C messages with a checksum error, 0x0D exception
        responses sent, 0x0E messages for this slave (broadcasts included), 0x0F of them not answered
        (broadcasts, listen-only), 0x10 NAKs, 0x11 busy answers, 0x12 character overruns (a simulated
        slave has none of the last three).
        """
        now, base = self.counters, self._diagnostics_base

        def since(name: str) -> int:
            return getattr(now, name) - getattr(base, name)

        heard = since("requests") + since("bad_frames") + since("other_unit")
        counts = {0x0B: heard, 0x0C: since("checksum_errors"), 0x0D: since("exceptions"),
                  0x0E: since("requests"), 0x0F: since("requests") - since("responses"),
                  0x10: 0, 0x11: 0, 0x12: 0}
        return {key: value & 0xFFFF for key, value in counts.items()}

    def _get_event_counter(self, request: Any) -> Pdu:
        """FC 11: the status word and the event counter."""
        return _pdu.GetCommEventCounterResponse(0, self.event_count)

    def _get_event_log(self, request: Any) -> Pdu:
        """FC 12: the status word, the event and message counters, and the events, newest first."""
        messages = self.diagnostic_counters()[0x0B]
        return _pdu.GetCommEventLogResponse(0, self.event_count, messages, bytes(self.events))

    def _diagnose(self, request: Any) -> Pdu | None:
        """FC 8: a sub-function (None: no answer, in listen-only mode or after it)."""
        sub, data = request.sub_function, request.data
        echo = _pdu.DiagnosticsResponse(sub, data)
        if sub == 0x00:  # return query data: the line check
            return echo
        if sub == 0x01:  # restart communications: counters cleared, listen-only ended
            was_listening = self.listen_only
            self.listen_only = False
            self._diagnostics_base = dataclasses.replace(self.counters)
            self.event_count = 0
            if request.value == 0xFF00:
                self.events.clear()
            self.events.appendleft(0x00)
            return None if was_listening else echo
        if sub == 0x04:  # force listen-only mode: no answer, now or later
            self.listen_only = True
            self.events.appendleft(0x04)
            return None
        if sub in (0x03, 0x14):  # change the ASCII delimiter / clear the overrun counter: accepted
            return echo
        if sub == 0x0A:
            self._diagnostics_base = dataclasses.replace(self.counters)
            self.diagnostic_register = 0
            self.event_count = 0
            return echo
        if request.value != 0:
            raise ModbusExceptionError(0x08, int(ExceptionCode.ILLEGAL_DATA_VALUE))
        value = self.diagnostic_register if sub == 0x02 else self.diagnostic_counters()[sub]
        return _pdu.DiagnosticsResponse(sub, value.to_bytes(2, "big"))

    def _read_file_records(self, request: Any) -> Pdu:
        """FC 20 over :attr:`DataBank.files` (see :class:`~modbus_edu.datamodel.FileRecords`)."""
        files = self.bank.files
        return _pdu.ReadFileRecordResponse(tuple(tuple(files.read(*group)) for group in request.records))

    def _write_file_records(self, request: Any) -> Pdu:
        """FC 21 over :attr:`DataBank.files`: every record checked before any is written."""
        self.bank.files.write(request.records)
        return _pdu.WriteFileRecordResponse(request.records)

    def _identify(self, request: Any) -> Pdu:
        """FC 43/14: the identity objects asked for; a stream that does not fit says 'more follows'."""
        objects = self.identity
        code, start = request.read_code, request.object_id
        level = 0x83 if any(i >= 0x80 for i in objects) else 0x82 if any(i >= 3 for i in objects) else 0x81
        if code == 4:  # one object
            if start not in objects:
                raise ModbusExceptionError(0x2B, int(ExceptionCode.ILLEGAL_DATA_ADDRESS))
            return _pdu.ReadDeviceIdentificationResponse(4, level, False, 0, ((start, objects[start]),))
        last = {1: 0x02, 2: 0x06, 3: 0xFF}[code]
        ids = [i for i in sorted(objects) if i <= last]
        if start not in ids:
            start = 0  # the spec: an unknown object id in a stream starts it from the beginning
        ids = [i for i in ids if i >= start]
        room, chosen = _pdu.MAX_PDU_SIZE - 7, []
        for object_id in ids:
            size = 2 + len(objects[object_id])
            if size > room and chosen:
                following = ids[len(chosen)]
                return _pdu.ReadDeviceIdentificationResponse(
                    code, level, True, following, tuple((i, objects[i]) for i in chosen))
            room -= size
            chosen.append(object_id)
        return _pdu.ReadDeviceIdentificationResponse(code, level, False, 0,
                                                     tuple((i, objects[i]) for i in chosen))

    def _read_fifo_queue(self, request: Any) -> Pdu:
        """FC 24: the count at the pointer address, the values after it."""
        kind = "holding_registers"
        table = self.bank.table(kind)
        self.before_read(kind, request.address, 1)
        count = table.read(request.address, 1)[0]
        if count > _pdu.MAX_FIFO_COUNT:
            raise ModbusExceptionError(0x18, int(ExceptionCode.ILLEGAL_DATA_VALUE))
        if request.address + 1 + count > 0x10000:
            raise ModbusExceptionError(0x18, int(ExceptionCode.ILLEGAL_DATA_ADDRESS))
        self.before_read(kind, request.address + 1, count)
        return _pdu.ReadFifoQueueResponse(tuple(table.read(request.address + 1, count)))

    def _mask_write_register(self, request: Any) -> Pdu:
        """FC 22: one holding register, (current AND and_mask) OR (or_mask AND NOT and_mask)."""
        kind = "holding_registers"
        table = self.bank.table(kind)
        self.before_read(kind, request.address, 1)
        current = table.read(request.address, 1)[0]
        value = _pdu.mask_write(current, request.and_mask, request.or_mask)
        table.write(request.address, [value])
        self.after_write(kind, request.address, [value])
        return _pdu.MaskWriteRegisterResponse(request.address, request.and_mask, request.or_mask)

    def _read_write_registers(self, request: Any) -> Pdu:
        """FC 23: holding registers written, then read, in one transaction."""
        kind = "holding_registers"
        table = self.bank.table(kind)
        table.read(request.read_address, request.read_count)  # both ranges exist, or nothing is written
        values = list(request.values)
        table.write(request.write_address, values)
        self.after_write(kind, request.write_address, values)
        self.before_read(kind, request.read_address, request.read_count)
        registers = table.read(request.read_address, request.read_count)
        return _pdu.ReadWriteMultipleRegistersResponse(registers=tuple(registers))

    # -- hooks ----------------------------------------------------------------------------------
    def before_read(self, table_kind: str, address: int, count: int) -> None:
        """Called before every read; calls ``on_read``.  Override to compute values on demand."""
        if self.on_read is not None:
            self.on_read(self, table_kind, address, count)

    def after_write(self, table_kind: str, address: int, values: list) -> None:
        """Called after every write; calls ``on_write``.  Override to react to what was written."""
        if self.on_write is not None:
            self.on_write(self, table_kind, address, values)


def _identity(objects: Any) -> dict[int, bytes]:
    """Identity objects as id -> bytes, checked: ids 0..255, values text or bytes of at most 244 bytes."""
    if not isinstance(objects, dict):
        raise ConfigError(f"identity is a dict of object id -> text, got {type(objects).__name__}")
    checked = {}
    for object_id, value in objects.items():
        if isinstance(object_id, bool) or not isinstance(object_id, int) or not 0 <= object_id <= 0xFF:
            raise ConfigError(f"identity object ids are 0..255, got {shown(object_id)}")
        data = value.encode() if isinstance(value, str) else value
        if not isinstance(data, (bytes, bytearray)) or len(data) > _pdu.MAX_PDU_SIZE - 9:
            raise ConfigError(f"identity object {object_id} must be text or bytes of at most 244 bytes")
        checked[object_id] = bytes(data)
    return checked


def dispatch(slaves: Slave | Iterable[Slave], frame: bytes, mode: str = "rtu") -> list[bytes]:
    """Give one frame to every slave (as a shared serial bus does) and collect their answers.

    Each slave filters by unit itself, so normally at most one answers.  Two slaves with the same
    unit would both answer: on a real bus their responses collide.
    """
    if isinstance(slaves, Slave):
        slaves = [slaves]
    answers = []
    for slave in slaves:
        answer = slave.handle(frame, mode)
        if answer is not None:
            answers.append(answer)
    return answers
