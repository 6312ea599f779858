"""The Modbus master (a *client* in the words of Modbus/TCP): it asks, slaves answer.

A :class:`Master` sits on a :class:`~modbus_edu.links.base.Link` and offers the eight everyday functions
as methods.  For each request it:

1. waits for the **turnaround delay** (``delay``) since the end of the previous transaction;
2. throws away any frame that arrived in the meantime (a **stale** answer to an earlier request that
   had already timed out: counted in ``stats.mismatches``);
3. frames the request (RTU, ASCII or TCP, as the link's ``mode`` says; on TCP with the next
   **transaction id**, +1 per request, 65535 wraps to 0), logs it and sends it;
4. waits at most ``timeout`` seconds, on the link's clock, for *its* response:

   * a frame whose CRC/LRC is wrong ends the attempt (``stats.checksum_errors``): the slave answered,
     but nothing in the frame can be trusted;
   * a frame from another unit, for another function or (TCP) with another transaction id is a
     **mismatch** (``stats.mismatches``): it is logged and ignored, and the master keeps waiting for the
     right one until the timeout.  On TCP that is what makes a late answer harmless: it carries the
     transaction id of the request it answers.  RTU and ASCII have no transaction id: a late answer from
     the same unit to the same function *cannot* be told from the answer to the next request.  That is
     why a serial master's timeout must be longer than the slowest answer of its slaves;
   * an **exception response** (``stats.exceptions``) raises
     :class:`~modbus_edu.errors.ModbusExceptionError` (``.code``, ``.meaning``); it is not retried;
   * a well-formed response that does not fit the request (its request's
     :meth:`~modbus_edu.pdu.Pdu.misfit`: the wrong number of values or records, a write echo that
     differs, another FC 8 sub-function, another FC 43 read code) ends the attempt
     (``stats.bad_responses``);
   * nothing in time: ``stats.timeouts``;

5. **retries** a failed attempt up to ``retries`` times, then raises the last error
   (:class:`~modbus_edu.errors.ModbusTimeoutError`, or
   :class:`~modbus_edu.errors.TransactionMismatchError` when only mismatched frames came, or the
   :class:`~modbus_edu.errors.ChecksumError` / frame error of the bad response).

Each attempt counts once in ``stats.requests`` and ends in exactly one of ``valid_responses``,
``exceptions``, ``timeouts``, ``checksum_errors``, ``bad_responses`` -- except a **broadcast** (unit 0
on a serial line), which nobody answers: the master sends it, lets it leave the line (``link.flush()``),
waits the turnaround delay and returns (``stats.broadcasts``).  A broadcast can only write, with FC 5,
6, 15, 16, 21 or 22 (:data:`~modbus_edu.codes.BROADCAST_FUNCTIONS`, the one table the slave follows too):
any other function to unit 0 on a serial line (a read, FC 23 Read/Write Multiple Registers, FC 8
Diagnostics) raises :class:`~modbus_edu.errors.ConfigError` before anything is sent.

Modbus/TCP has no broadcast.  There unit 0, like the recommended 0xFF, means "the device at this IP
address itself" (*Modbus Messaging on TCP/IP Implementation Guide* V1.0b, section 4.4.1.2): a request
to unit 0 on a TCP link, read or write, waits for its answer like any other.  A gateway to a serial
line has no such device behind unit 0 (there it would be a broadcast, which nobody answers): it answers
exception 0x0A, *gateway path unavailable*, at once, as it does for units 248 to 255.  It does not answer
0x0B, *gateway target device failed to respond*: that code says a request went out to a device on the
line and no answer came in time, and a request to unit 0 never goes out
(:class:`~modbus_edu.gateway.TcpGateway`).

Everything is timed on ``link.clock``: on a loopback link a ten-minute poll runs in a blink, and the
latencies in ``stats.latencies`` are those of the simulated wire.
"""

from __future__ import annotations

import warnings
from collections import deque
from dataclasses import dataclass, field, fields
from functools import lru_cache
from typing import Any

from . import pdu as _pdu
from .codes import BROADCAST_FUNCTIONS, function_title
from .errors import (
    ChecksumError,
    ConfigError,
    FrameError,
    ModbusError,
    ModbusExceptionError,
    ModbusTimeoutError,
    PduError,
    TransactionMismatchError,
    guard_numbers,
    shown,
)
from .framing import decode_frame, make_frame
from .links.base import Link
from .master_steps import FLUSH, RECEIVE, SLEEP, AsyncCalls, Steps, run_steps
from .pdu import ExceptionResponse, Pdu
from .traffic import TrafficLog, pdu_note

MAX_LOG = 10_000
"""The most frames ``Master.log`` keeps (the newest): a poll left running overnight stays bounded."""

MAX_LATENCIES = 10_000
"""The most latencies ``stats.latencies`` keeps (the newest)."""

MAX_STALE = 256
"""The most stale frames discarded before a request is sent; the rest are discarded while it waits."""

MAX_IDENTIFICATION_OBJECTS = 256
"""The most FC 43/14 objects :meth:`Master.read_device_identification` takes over all of its parts (there
are 256 object ids): a device whose 'more follows' goes on past them is refused."""

IDENTIFICATION_TIMEOUTS = 10
"""How many timeouts :meth:`Master.read_device_identification` may take over all of its parts."""

MAX_MISMATCH_NOTES = 3
"""How many foreign frames a :class:`TransactionMismatchError` describes; it counts them all."""

__all__ = ["Master", "MasterStats", "Verdict", "classify_response"]


def _counted(number: int, noun: str) -> str:
    """``number`` and ``noun`` in the number it asks for: "1 timeout", "2 timeouts"; a noun written
    ``"mismatch:es"`` takes "es" in the plural."""
    noun, _, ending = noun.partition(":")
    return f"{number} {noun}{'' if number == 1 else ending or 's'}"


@dataclass
class MasterStats:
    """A master's statistics (the counters of the robot test-tool paper's tool, and a few more).

    ``requests``         frames sent (each retry counts)
    ``valid_responses``  normal responses that fit their request
    ``exceptions``       exception responses
    ``timeouts``         attempts that got no (acceptable) answer in time
    ``checksum_errors``  responses with a wrong CRC / LRC
    ``bad_responses``    responses that broke a framing rule or did not fit the request
    ``mismatches``       frames ignored: another unit, function or transaction id, or stale
    ``broadcasts``       broadcast requests (unit 0 on a serial line: no answer expected)
    ``retries``          attempts that were retries
    ``latencies``        seconds from sending to a response (valid or exception), on the link's clock
    """

    requests: int = 0
    valid_responses: int = 0
    exceptions: int = 0
    timeouts: int = 0
    checksum_errors: int = 0
    bad_responses: int = 0
    mismatches: int = 0
    broadcasts: int = 0
    retries: int = 0
    latencies: deque[float] = field(default_factory=lambda: deque(maxlen=MAX_LATENCIES))

    def reset(self) -> None:
        """Back to zero (the robot test-tool paper's "reset counters" button)."""
        for f in fields(self):
            setattr(self, f.name, deque(maxlen=MAX_LATENCIES) if f.name == "latencies" else 0)

    @property
    def answered(self) -> int:
        """Attempts that got an answer: valid responses and exception responses."""
        return self.valid_responses + self.exceptions

    @property
    def success_rate(self) -> float:
        """Valid responses / requests that expected an answer (0.0 when none was sent)."""
        expected = self.requests - self.broadcasts
        return self.valid_responses / expected if expected else 0.0

    def as_dict(self) -> dict[str, Any]:
        return {f.name: (list(getattr(self, f.name)) if f.name == "latencies" else getattr(self, f.name))
                for f in fields(self)}

    def summary(self) -> str:
        """One line: ``10 requests: 9 valid, 0 exceptions, 1 timeout, ...`` (each noun in the number its
        count asks for)."""
        lat = ""
        if self.latencies:
            lat = (f"; latency min {min(self.latencies) * 1000:.2f} ms, "
                   f"max {max(self.latencies) * 1000:.2f} ms")
        counts = ", ".join(_counted(getattr(self, name), noun) for name, noun in (
            ("exceptions", "exception"), ("timeouts", "timeout"), ("checksum_errors", "checksum error"),
            ("bad_responses", "bad response"), ("mismatches", "mismatch:es"), ("broadcasts", "broadcast")))
        return f"{_counted(self.requests, 'request')}: {self.valid_responses} valid, {counts}{lat}"

    def __str__(self) -> str:
        return self.summary()


_READS = {
    1: _pdu.ReadCoilsRequest,
    2: _pdu.ReadDiscreteInputsRequest,
    3: _pdu.ReadHoldingRegistersRequest,
    4: _pdu.ReadInputRegistersRequest,
}


class _DefaultCount(int):
    """The default number of polls, 10, told apart from a 10 passed by the caller (older spelling)."""


_DEFAULT_POLLS = _DefaultCount(10)

_POLL_SETTINGS = "interval, polls (the number of polls), function, unit, address, quantity, with_time"


def _check_seconds(name: str, value: Any) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ConfigError(f"{name} must be a number of seconds, got {shown(value)}") from None
    if not value >= 0:
        raise ConfigError(f"{name} must be >= 0 s, got {shown(value)}")
    return value


@lru_cache(maxsize=256, typed=True)
def _request_frame(mode: str, unit: int, request: Pdu) -> bytes:
    """The bytes of a serial (RTU / ASCII) request frame, remembered for the last 256 different ones.

    A master polls: it sends the same few requests over and over.  Framing is a pure function of the
    mode, the unit and the (immutable) request, so each different frame is built once.
    """
    return make_frame(mode, unit, request, 0).encode()


def _peek(data: bytes, mode: str) -> tuple[int | None, int | None, int | None]:
    """(transaction id, unit, function code) of a raw frame, as far as they can be read."""
    try:
        if mode == "tcp":
            tid = int.from_bytes(data[0:2], "big") if len(data) >= 2 else None
            return tid, (data[6] if len(data) > 6 else None), (data[7] if len(data) > 7 else None)
        if mode == "ascii":
            unit = int(data[1:3], 16) if len(data) >= 3 else None
            function = int(data[3:5], 16) if len(data) >= 5 else None
            return None, unit, function
        return None, (data[0] if data else None), (data[1] if len(data) > 1 else None)
    except ValueError:
        return None, None, None



def _source(data: bytes, mode: str) -> str:
    """Who sent a raw frame, for the traffic log: ``unit N``, or ``?`` if it cannot be read."""
    unit = _peek(data, mode)[1]
    return f"unit {unit}" if unit is not None else "?"


def _mismatch(mode: str, unit: int, function: int, tid: int, r_tid: int | None, r_unit: int | None,
              r_function: int | None) -> str:
    """Why a response does not belong to the request ('' if it does)."""
    if mode == "tcp" and r_tid is not None and r_tid != tid:
        return f"transaction id {r_tid}, expected {tid}"
    if r_unit is not None and r_unit != unit:
        return f"unit {r_unit}, expected {unit}"
    if r_function is not None and (r_function & 0x7F) != function:
        return f"function {r_function & 0x7F}, expected {function}"
    return ""


@dataclass(frozen=True)
class Verdict:
    """What a received frame is to the request awaiting its response (see :func:`classify_response`).

    ``kind`` is ``"valid"`` or ``"exception"`` (``response`` is the answer), ``"mismatch"`` (a frame for
    another transaction, unit or function: ``why``; the wait goes on), ``"bad"`` (a malformed answer, or
    one that does not fit the request) or ``"checksum"`` (``error`` is what the master raises).
    ``source`` and ``note`` are what the traffic log records.
    """

    kind: str
    source: str
    note: str
    response: Pdu | None = None
    error: ModbusError | None = None
    why: str = ""


def classify_response(data: bytes, mode: str, request: Pdu, unit: int, tid: int) -> Verdict:
    """Judge a frame received while ``request`` (to ``unit``, transaction ``tid``) waits for its answer.

    Pure: no clock, no link, no counter.  A frame whose envelope, unit and function can be read but
    belong to another request is a mismatch even when its PDU is malformed; a response of the right
    function must fit its request (:meth:`~modbus_edu.pdu.Pdu.misfit`).
    """
    function = request.function_code
    try:
        decoded = decode_frame(data, mode, "response")
    except ChecksumError as exc:
        return Verdict("checksum", _source(data, mode), f"checksum error: {exc}", error=exc)
    except (FrameError, PduError) as exc:
        why = _mismatch(mode, unit, function, tid, *_peek(data, mode))
        if why and not isinstance(exc, FrameError):
            return Verdict("mismatch", _source(data, mode), f"mismatch, ignored: {why}", why=why)
        return Verdict("bad", _source(data, mode), f"bad response: {exc}", error=exc)
    response = decoded.pdu
    source = f"unit {decoded.unit}"
    why = _mismatch(mode, unit, function, tid, getattr(decoded, "transaction_id", None), decoded.unit,
                    response.function_code)
    if why:
        return Verdict("mismatch", source, f"mismatch, ignored: {why}", why=why)
    if isinstance(response, ExceptionResponse):
        return Verdict("exception", source, pdu_note(response), response=response)
    problem = request.misfit(response)
    if problem:
        return Verdict("bad", source, f"bad response: {problem}", error=PduError(
            f"the response of unit {unit} does not fit {request.title}: {problem}"))
    return Verdict("valid", source, pdu_note(response), response=response)

class Master(AsyncCalls):
    """A Modbus master on a link: ``Master(link, timeout=1.0, retries=0, delay=0.0, transaction_id=1)``.

    >>> from modbus_edu.slave import Slave
    >>> from modbus_edu.links.loopback import loopback_serial
    >>> slave = Slave(unit=1)
    >>> slave.bank.holding_registers[0] = 1234
    >>> master = Master(loopback_serial(slave, baudrate=9600))
    >>> master.read_holding_registers(unit=1, address=0, count=1)
    [1234]
    >>> round(master.stats.latencies[0] * 1000, 2)   # ms on the virtual wire
    22.92
    """

    @guard_numbers
    def __init__(
        self,
        link: Link,
        *,
        timeout: float = 1.0,
        retries: int = 0,
        delay: float = 0.0,
        transaction_id: int = 1,
    ) -> None:
        if not hasattr(link, "send") or not hasattr(link, "receive"):
            raise ConfigError(f"Master needs a Link (send/receive), got {type(link).__name__}")
        if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
            raise ConfigError(f"retries must be an integer >= 0, got {shown(retries)}")
        if isinstance(transaction_id, bool) or not isinstance(transaction_id, int) \
                or not 0 <= transaction_id <= 0xFFFF:
            raise ConfigError(f"transaction_id must be 0..65535, got {shown(transaction_id)}")
        self.link = link
        self.timeout = _check_seconds("timeout", timeout)
        self.retries = retries
        self.delay = _check_seconds("delay", delay)
        self.transaction_id = transaction_id
        """The transaction id the next TCP request will carry."""
        self.last_transaction_id: int | None = None
        self.stats = MasterStats()
        self.log = TrafficLog(maxlen=MAX_LOG)
        self._last_end: float | None = None

    def __repr__(self) -> str:
        return f"<Master on {getattr(self.link, 'description', self.link)!s}: {self.stats.summary()}>"

    @property
    def mode(self) -> str:
        return self.link.mode

    @property
    def clock(self) -> Any:
        return self.link.clock

    # -- the eight functions ------------------------------------------------------------------------
    def read_coils(self, unit: int, address: int, count: int) -> list[bool]:
        """FC 1: ``count`` coils from ``address`` (exactly ``count`` bools, the padding dropped)."""
        return self._read(1, unit, address, count)

    def read_discrete_inputs(self, unit: int, address: int, count: int) -> list[bool]:
        """FC 2: ``count`` discrete inputs from ``address``."""
        return self._read(2, unit, address, count)

    def read_holding_registers(self, unit: int, address: int, count: int) -> list[int]:
        """FC 3: ``count`` holding registers from ``address`` (ints 0..65535)."""
        return self._read(3, unit, address, count)

    def read_input_registers(self, unit: int, address: int, count: int) -> list[int]:
        """FC 4: ``count`` input registers from ``address``."""
        return self._read(4, unit, address, count)

    def write_single_coil(self, unit: int, address: int, value: bool) -> None:
        """FC 5: set one coil (``True`` goes on the wire as FF 00, ``False`` as 00 00)."""
        self.execute(unit, _pdu.WriteSingleCoilRequest(address=address, value=value))

    def write_single_register(self, unit: int, address: int, value: int) -> None:
        """FC 6: set one holding register (0..65535)."""
        self.execute(unit, _pdu.WriteSingleRegisterRequest(address=address, value=value))

    def write_multiple_coils(self, unit: int, address: int, values: Any) -> None:
        """FC 15: set ``len(values)`` coils from ``address``."""
        self.execute(unit, _pdu.WriteMultipleCoilsRequest(address=address, values=values))

    def write_multiple_registers(self, unit: int, address: int, values: Any) -> None:
        """FC 16: set ``len(values)`` holding registers from ``address``."""
        self.execute(unit, _pdu.WriteMultipleRegistersRequest(address=address, values=values))

    def read_exception_status(self, unit: int) -> int:
        """FC 7 (serial lines): the device's eight exception-status bits, as an int 0..255."""
        return self._ask(unit, _pdu.ReadExceptionStatusRequest()).status

    def report_server_id(self, unit: int) -> _pdu.ReportServerIdResponse:
        """FC 17 (serial lines): what the device says it is (``.server_id`` bytes) and ``.run_indicator``."""
        return self._ask(unit, _pdu.ReportServerIdRequest())

    def mask_write_register(self, unit: int, address: int, and_mask: int, or_mask: int) -> None:
        """FC 22: change some bits of one holding register, ``(value AND and_mask) OR (or_mask AND NOT
        and_mask)`` (see :func:`modbus_edu.pdu.mask_write`), without reading it first."""
        self.execute(unit, _pdu.MaskWriteRegisterRequest(address, and_mask, or_mask))

    def read_write_multiple_registers(self, unit: int, read_address: int, read_count: int, write_address: int,
                                      values: Any) -> list[int]:
        """FC 23: write ``values`` from ``write_address``, then read ``read_count`` registers from
        ``read_address``, in one transaction; returns the registers read."""
        request = _pdu.ReadWriteMultipleRegistersRequest(read_address, read_count, write_address, values)
        return list(self._ask(unit, request).registers)

    def read_fifo_queue(self, unit: int, address: int) -> list[int]:
        """FC 24: the queue whose count is in holding register ``address`` (its values follow it)."""
        return list(self._ask(unit, _pdu.ReadFifoQueueRequest(address)).values)

    def read_device_identification(self, unit: int, read_code: int = 1, object_id: int = 0) -> dict[int, str]:
        """FC 43/14: the device's identification objects, ``{0: "vendor", 1: "product", 2: "1.0", ...}``.

        ``read_code`` 1 basic, 2 regular, 3 extended (streams from ``object_id``), 4 that one object.  A
        stream that does not fit one response comes in parts ('more follows'); this follows them to the
        end, never backwards, and within bounds a device cannot stretch: at most
        :data:`MAX_IDENTIFICATION_OBJECTS` objects in all, and no new request once
        :data:`IDENTIFICATION_TIMEOUTS` times the timeout has passed since the first (a
        :class:`~modbus_edu.errors.PduError` says what the device did)."""
        request = _pdu.ReadDeviceIdentificationRequest(read_code, object_id)  # a bad code: raise it now
        clock = self.link.clock
        start = clock.now
        deadline = start + IDENTIFICATION_TIMEOUTS * self.timeout
        objects: dict[int, str] = {}
        received = parts = 0
        while True:
            response = self._ask(unit, request)
            parts += 1
            received += len(response.objects)
            if received > MAX_IDENTIFICATION_OBJECTS:
                raise PduError(
                    f"unit {unit} sent {received} identification objects in {parts} responses, each saying "
                    f"'more follows': more than the {MAX_IDENTIFICATION_OBJECTS} object ids there are")
            objects.update((i, value.decode("utf-8", "replace")) for i, value in response.objects)
            if not response.more_follows or response.next_object_id <= request.object_id:
                return objects
            if clock.now >= deadline:
                raise PduError(
                    f"unit {unit} still said 'more follows' after {parts} responses and "
                    f"{clock.now - start:.3f} s: {IDENTIFICATION_TIMEOUTS} x the {self.timeout:g} s timeout "
                    f"is the most a device identification may take")
            request = _pdu.ReadDeviceIdentificationRequest(read_code, response.next_object_id)

    def diagnostics(self, unit: int, sub_function: int, data: bytes | int = 0) -> int | bytes:
        """FC 8 (serial lines): a diagnostics sub-function (:class:`~modbus_edu.pdu.DiagnosticSubFunction`).

        Returns the first data word of the answer (a counter, the diagnostic register) as an int, or, for
        Return Query Data (0x00), the data echoed as bytes.  Force Listen Only Mode (0x04) gets no answer:
        this returns None for it without waiting."""
        request = _pdu.DiagnosticsRequest(sub_function, data)
        if sub_function == 0x04:
            return self.execute_no_answer(unit, request)
        response = self._ask(unit, request)
        return response.data if sub_function == 0x00 else response.value

    def execute_no_answer(self, unit: int, request: Pdu) -> None:
        """Send a request that, by the spec, gets no answer (FC 8/04); count it, wait for nothing."""
        self._check_broadcast(unit, request)
        link, clock, mode = self.link, self.link.clock, self.link.mode
        tid = self._next_tid() if mode == "tcp" else 0
        frame = make_frame(mode, unit, request, tid).encode()
        self.stats.requests += 1
        self.stats.broadcasts += 1  # like a broadcast: nothing is expected back
        self.log.record(clock.now, "tx", mode, frame, "master", f"unit {unit}", pdu_note(request), "request")
        link.send(frame)
        link.flush()
        return None

    def get_comm_event_counter(self, unit: int) -> int:
        """FC 11 (serial lines): the count of messages the device completed normally."""
        return self._ask(unit, _pdu.GetCommEventCounterRequest()).event_count

    def get_comm_event_log(self, unit: int) -> _pdu.GetCommEventLogResponse:
        """FC 12 (serial lines): the event and message counts and up to 64 events, newest first."""
        return self._ask(unit, _pdu.GetCommEventLogRequest())

    def read_file_record(self, unit: int, file: int, record: int, count: int) -> list[int]:
        """FC 20: ``count`` registers of a file from record ``record`` (one sub-request)."""
        return list(self._ask(unit, _pdu.ReadFileRecordRequest(((file, record, count),))).records[0])

    def write_file_record(self, unit: int, file: int, record: int, values: Any) -> None:
        """FC 21: write ``values`` into a file from record ``record`` (one sub-request)."""
        self.execute(unit, _pdu.WriteFileRecordRequest(((file, record, tuple(values)),)))

    def _ask(self, unit: int, request: Pdu) -> Any:
        self._check_broadcast(unit, request)
        return self.execute(unit, request)

    def _is_broadcast(self, unit: int) -> bool:
        """Unit 0 on a serial line is a broadcast; on Modbus/TCP it is the device itself (no broadcast)."""
        return unit == 0 and self.link.mode != "tcp"

    def _check_broadcast(self, unit: int, request: Pdu | int) -> None:
        """Refuse a broadcast of a function that may not be broadcast
        (:data:`~modbus_edu.codes.BROADCAST_FUNCTIONS`, the table the slave follows too)."""
        if not self._is_broadcast(unit):
            return
        function = request if isinstance(request, int) else request.function_code
        if function in BROADCAST_FUNCTIONS:
            return
        if function in _READS:
            raise ConfigError("a read cannot be broadcast (unit 0): no slave answers a broadcast")
        raise ConfigError(
            f"{function_title(function)} (FC {function}) cannot be broadcast (unit 0): a broadcast may only "
            "write, with FC 5, 6, 15, 16, 21 or 22, and no slave answers it"
        )

    def _read(self, function: int, unit: int, address: int, count: int) -> list:
        return run_steps(self.link, self.read_steps(function, unit, address, count))

    def read_steps(self, function: int, unit: int, address: int, count: int) -> Steps:
        """:meth:`read_once` as steps (:mod:`modbus_edu.master_steps`): the values read, once run."""
        if function not in _READS:
            raise ConfigError(f"read_once reads with function 1, 2, 3 or 4, got {shown(function)}")
        self._check_broadcast(unit, function)
        request = _READS[function](address=address, count=count)
        response = yield from self.execute_steps(unit, request, True)
        if function in (1, 2):
            return list(response.bits[:count])  # type: ignore[attr-defined]
        return list(response.registers)  # type: ignore[attr-defined]

    def read_once(self, function: int, unit: int, address: int, count: int) -> list:
        """One read with function 1, 2, 3 or 4 (the robot test-tool paper's "read once" button)."""
        if function not in _READS:
            raise ConfigError(f"read_once reads with function 1, 2, 3 or 4, got {shown(function)}")
        return self._read(function, unit, address, count)

    def poll(
        self,
        interval: float = 1.0,
        polls: int = _DEFAULT_POLLS,
        *,
        function: int = 3,
        unit: int = 1,
        address: int = 0,
        quantity: int = 1,
        with_time: bool = False,
        **older: Any,
    ) -> list:
        """Read ``polls`` times, one poll every ``interval`` seconds on the link's clock.

        Each poll reads ``quantity`` registers (function 3 or 4) or coils / discrete inputs (1 or 2)
        from ``address`` of ``unit`` -- the spec's "quantity of registers".  Returns one result per
        poll: the values, or the :class:`~modbus_edu.errors.ModbusError` that happened (a timeout, an
        exception response, ...).  With ``with_time=True`` each result is a ``(time, result)`` pair, the
        time at which the poll started.  Polls start at fixed times ``start + i * interval``; one that
        would start late (the previous poll took longer than the interval) starts at once.  On a virtual
        clock this takes no real time at all::

            master.poll(0.5, polls=20, unit=1, address=0, quantity=2)   # 20 polls of 2 registers, 0.5 s apart

        ``count`` is not a setting of its own here: everywhere else in the library it is a quantity of
        registers or coils, so the number of polls is ``polls`` and the quantity is ``quantity``.  Two
        older spellings still work and warn: ``poll(..., count=<number of polls>)`` (a
        :class:`DeprecationWarning`) and ``poll(..., count=<quantity>, polls=<number of polls>)`` (a
        :class:`PendingDeprecationWarning`).

        Settings that cannot work (function 5, ``quantity=0``, a read of unit 0 on a serial line) raise
        :class:`~modbus_edu.errors.ConfigError` or a :class:`~modbus_edu.errors.PduError` before the first
        poll.
        """
        if older:
            polls, quantity = self._older_poll_spelling(polls, quantity, older)
        interval = _check_seconds("interval", interval)
        if isinstance(polls, bool) or not isinstance(polls, int) or polls < 0:
            raise ConfigError(f"polls (the number of polls) must be a whole number >= 0, got {shown(polls)}")
        if isinstance(quantity, bool) or not isinstance(quantity, int):
            raise ConfigError(
                f"quantity (registers or coils read by each poll) must be a whole number, got "
                f"{shown(quantity)}"
            )
        if function not in _READS:
            raise ConfigError(f"poll reads with function 1, 2, 3 or 4, got {shown(function)}")
        self._check_broadcast(unit, function)
        _READS[function](address=address, count=quantity)  # a bad address or quantity: raise it now
        clock = self.link.clock
        start = clock.now
        results: list = []
        for i in range(polls):
            due = start + i * interval
            if due > clock.now:
                clock.sleep(due - clock.now)
            began = clock.now
            try:
                result: Any = self.read_once(function, unit, address, quantity)
            except ModbusError as exc:
                result = exc
            results.append((began, result) if with_time else result)
        return results

    @staticmethod
    def _older_poll_spelling(polls: int, quantity: int, older: dict[str, Any]) -> tuple[Any, Any]:
        """(polls, quantity) from the older spellings: ``count=<number of polls>``, or, older still,
        ``count=<quantity>, polls=<number of polls>``."""
        unknown = sorted(set(older) - {"count"})
        if unknown:
            raise ConfigError(
                f"poll() has no setting {', '.join(unknown)}; its settings are {_POLL_SETTINGS}"
            )
        count = older["count"]
        if polls is _DEFAULT_POLLS:  # poll(count=N): N was the number of polls
            warnings.warn("poll(count=<number of polls>) is now poll(polls=<number of polls>): count is a "
                          "quantity of registers everywhere else", DeprecationWarning, stacklevel=3)
            return count, quantity
        if quantity != 1:  # the oldest form: count was the quantity
            raise ConfigError(
                "poll(): with polls= given, an older count= is the quantity; give either count= and "
                "polls= (older) or polls= and quantity="
            )
        warnings.warn(
            "poll(count=<quantity>, polls=<number of polls>) is the older spelling: write "
            "poll(interval, polls=<number of polls>, quantity=<registers or coils per poll>)",
            PendingDeprecationWarning,
            stacklevel=3,
        )
        return polls, count

    # -- the general path ----------------------------------------------------------------------------
    def execute(self, unit: int, request: Pdu, *, check: bool = True) -> Pdu | None:
        """Send ``request`` (a request PDU) to ``unit`` and return the response PDU.

        Exception responses raise :class:`~modbus_edu.errors.ModbusExceptionError`, unless
        ``check=False`` (then the :class:`~modbus_edu.pdu.ExceptionResponse` is returned).  A broadcast
        (unit 0 on a serial line) returns ``None``; on Modbus/TCP unit 0 is the device itself and is
        answered.  See the module's documentation for timeouts, retries and mismatches.
        """
        return run_steps(self.link, self.execute_steps(unit, request, check))

    def execute_steps(self, unit: int, request: Pdu, check: bool) -> Steps:
        """:meth:`execute` as steps (:mod:`modbus_edu.master_steps`): run by ``execute`` (blocking) and by
        ``aexecute`` (awaited) alike, so the two cannot drift apart."""
        if not isinstance(request, Pdu) or getattr(request, "role", None) != "request":
            raise ConfigError(f"execute() takes a request PDU, got {type(request).__name__}")
        self._check_broadcast(unit, request)
        error: ModbusError | None = None
        for attempt in range(self.retries + 1):
            if attempt:
                self.stats.retries += 1
            try:
                response = yield from self._attempt(unit, request)
            except (ModbusTimeoutError, TransactionMismatchError, FrameError, PduError) as exc:
                error = exc
                continue
            if isinstance(response, ExceptionResponse) and check:
                raise ModbusExceptionError(response.function, response.code)
            return response
        assert error is not None
        raise error

    def _next_tid(self) -> int:
        tid = self.transaction_id
        self.transaction_id = (tid + 1) & 0xFFFF
        self.last_transaction_id = tid
        return tid

    def _attempt(self, unit: int, request: Pdu) -> Steps:
        link, clock, mode, stats, log = self.link, self.link.clock, self.link.mode, self.stats, self.log
        # 1. turnaround delay since the previous transaction
        if self._last_end is not None and self.delay:
            due = self._last_end + self.delay
            if due > clock.now:
                yield SLEEP, due - clock.now
        # 2. stale frames (at most MAX_STALE: a peer that never stops sending cannot hold the master here)
        for _ in range(MAX_STALE):
            stale = link.receive(0)
            if stale is None:
                break
            stats.mismatches += 1
            log.record(clock.now, "rx", mode, stale, source=self._source(stale), dest="master",
                       role="response", note="stale: arrived after its request had given up; discarded")
        # 3. send
        if mode == "tcp":
            tid = self._next_tid()
            frame = make_frame(mode, unit, request, tid).encode()
        else:
            tid = 0
            try:
                frame = _request_frame(mode, unit, request)
            except TypeError:  # an unhashable request (a PDU class of one's own): build it each time
                frame = make_frame(mode, unit, request, 0).encode()
        sent = clock.now
        stats.requests += 1
        broadcast = unit == 0 and mode != "tcp"  # Modbus/TCP has no broadcast: unit 0 is the device itself
        # source, dest, note, role (positional: this runs on every poll)
        log.record(sent, "tx", mode, frame, "master", "broadcast" if broadcast else f"unit {unit}",
                   pdu_note(request), "request")
        link.send(frame)
        if broadcast:
            stats.broadcasts += 1
            yield FLUSH, None
            if self.delay:
                yield SLEEP, self.delay
            self._last_end = clock.now
            return None
        # 4. wait for the answer
        try:
            return (yield from self._wait(unit, request, tid, sent))
        finally:
            self._last_end = clock.now

    def _source(self, data: bytes) -> str:
        return _source(data, self.link.mode)

    def _wait(self, unit: int, request: Pdu, tid: int, sent: float) -> Steps:
        """Receive until the response to ``request`` comes (or the deadline passes): what arrives is
        judged by :func:`classify_response`; this loop counts, logs and waits on."""
        clock, mode, stats, log = self.link.clock, self.link.mode, self.stats, self.log
        deadline = sent + self.timeout  # absolute: whatever arrives meanwhile, the wait ends here
        mismatched: list[str] = []  # the first MAX_MISMATCH_NOTES reasons; `ignored` counts them all
        ignored = 0
        while True:
            remaining = deadline - clock.now
            data = (yield RECEIVE, remaining) if remaining > 0 else None
            if data is None:
                stats.timeouts += 1
                raise self._no_response(unit, request, clock.now - sent, ignored, mismatched)
            now = clock.now
            verdict = classify_response(data, mode, request, unit, tid)
            kind = verdict.kind
            # source, dest, note, role (positional: this runs on every poll)
            log.record(now, "rx", mode, data, verdict.source, "master", verdict.note, "response")
            if kind == "mismatch":
                stats.mismatches += 1
                ignored += 1
                if len(mismatched) < MAX_MISMATCH_NOTES:
                    mismatched.append(verdict.why)
                continue
            if kind == "valid" or kind == "exception":
                if kind == "valid":
                    stats.valid_responses += 1
                else:
                    stats.exceptions += 1
                stats.latencies.append(now - sent)
                return verdict.response  # type: ignore[return-value]
            if kind == "checksum":
                stats.checksum_errors += 1
            else:
                stats.bad_responses += 1
            raise verdict.error  # type: ignore[misc]

    def _no_response(self, unit: int, request: Pdu, waited: float, ignored: int,
                     mismatched: list[str]) -> ModbusError:
        """The error of a wait that ended without the response: frames that did not belong to the
        request, if any came, else a timeout."""
        if ignored:
            more = f"; and {ignored - len(mismatched)} more" if ignored > len(mismatched) else ""
            return TransactionMismatchError(
                f"no response to {request.title} for unit {unit} within {self.timeout:g} s "
                f"(waited {waited:.6f} s); {ignored} frame(s) came that did not belong to "
                f"it: {'; '.join(mismatched)}{more}"
            )
        hint = getattr(self.link, "silence_hint", None)  # a link that can tell why (the browser's port)
        hint = hint() if callable(hint) else ""
        return ModbusTimeoutError(
            f"no response from unit {unit} to {request.title} within {self.timeout:g} s "
            f"(waited {waited:.6f} s on the link's clock){'; ' + hint if hint else ''}"
        )
