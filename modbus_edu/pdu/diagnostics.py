"""Diagnostics, serial line only (specification sections 6.7, 6.8, 6.9, 6.10, 6.13): Read Exception Status
(FC 7), Diagnostics (FC 8), Get Comm Event Counter (FC 11), Get Comm Event Log (FC 12) and Report Server ID
(FC 17)."""

from __future__ import annotations

import struct
from dataclasses import dataclass
from enum import IntEnum
from typing import ClassVar

from ..codes import (
    _hex,
    function_title,
)
from ..errors import (
    ByteCountError,
    TruncatedError,
    UnknownFunctionError,
    ValueRangeError,
    shown,
)
from .base import (
    OPEN_LENGTH,
    Field,
    Pdu,
    _check_int,
    _check_register,
    _expect_byte_count,
    _expect_length,
    _expect_minimum,
)


class _NoDataRequest(Pdu):
    """A request that is its function code alone (FC 7, FC 17)."""

    __slots__ = ()
    role: ClassVar[str] = "request"
    fixed_size: ClassVar[int | None] = 1
    function_code: ClassVar[int]

    def encode(self) -> bytes:
        return bytes([self.function_code])

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 1, f"{function_title(cls.function_code)} request", offset)
        return cls()

    def fields(self) -> list[Field]:
        return [self._function_field(self.encode())]


@dataclass(frozen=True, slots=True)
class ReadExceptionStatusRequest(_NoDataRequest):
    """Read Exception Status (FC 07) request, serial line only: the function code alone::

        offset  size  field
        0       1     function code 0x07
    """

    function_code: ClassVar[int] = 0x07


@dataclass(frozen=True, slots=True)
class ReadExceptionStatusResponse(Pdu):
    """Read Exception Status (FC 07) response: eight status bits the device defines::

        offset  size  field
        0       1     function code 0x07
        1       1     output data: the exception status byte (bit 0 = the device's first status flag)
    """

    status: int

    function_code: ClassVar[int] = 0x07
    fixed_size: ClassVar[int | None] = 2
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        status = _check_int(self.status, "status")
        if not 0 <= status <= 0xFF:
            raise ValueRangeError(f"exception status {status} does not fit its one byte: expected 0..255")

    def encode(self) -> bytes:
        return bytes([0x07, self.status])

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 2, "Read Exception Status response", offset)
        return cls(data[1])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:2], "exception status", self.status, f"bits {self.status:08b} (bit 0 last)")]

    def _summary_items(self):
        return [("status", f"0b{self.status:08b}")]


@dataclass(frozen=True, slots=True)
class ReportServerIdRequest(_NoDataRequest):
    """Report Server ID (FC 17, 0x11) request, serial line only: the function code alone::

        offset  size  field
        0       1     function code 0x11
    """

    function_code: ClassVar[int] = 0x11


_RUN = {0xFF: True, 0x00: False}
"""FC 17's run indicator byte: 0xFF ON (the device runs), 0x00 OFF."""


@dataclass(frozen=True, slots=True)
class ReportServerIdResponse(Pdu):
    """Report Server ID (FC 17, 0x11) response: what the device says it is, whether it runs, and more::

        offset  size  field
        0       1     function code 0x11
        1       1     byte count N + 1 + M
        2       N     server ID (device specific: its length too)
        2+N     1     run indicator status: 0xFF ON, 0x00 OFF
        3+N     M     additional data (device specific, e.g. a version text)

    Only the device knows how long its server ID is, so a decoder looks for the run indicator: the
    first 0x00 or 0xFF after the server ID's first byte (a libmodbus device answers ``B4 FF "LMB3.1.6"``:
    server ID 0xB4, ON, then its version).  This library's own responses split there too: a server ID
    has no 0x00 or 0xFF after its first byte (such bytes belong in ``additional_data``).  Where no such
    byte follows, the layout is the device's own: ``run_indicator`` is None and ``server_id`` holds every
    byte, unsplit.
    """

    server_id: bytes
    run_indicator: bool | None = True
    additional_data: bytes = b""

    function_code: ClassVar[int] = 0x11
    byte_count_at: ClassVar[int | None] = 1
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        for name in ("server_id", "additional_data"):
            if not isinstance(getattr(self, name), (bytes, bytearray)):
                raise ValueRangeError(f"{name} must be bytes, got {shown(getattr(self, name))}")
            object.__setattr__(self, name, bytes(getattr(self, name)))
        server_id, run, more = self.server_id, self.run_indicator, self.additional_data
        if run is not None and not isinstance(run, bool):
            raise ValueRangeError(f"run_indicator must be True or False, got {shown(run)}")
        size = len(server_id) + (run is not None) + len(more)
        if size > 251:
            raise ValueRangeError(f"server ID, run indicator and additional data are {size} bytes: at most "
                                  "251 fit a response")
        if run is None:
            if more:
                raise ValueRangeError("additional data follows the run indicator: without a run indicator "
                                      "(None: not found) every byte is the server ID, unsplit")
        elif not server_id:
            raise ValueRangeError("the server ID is at least one byte (before the run indicator)")
        inside = next((at for at in range(1, len(server_id)) if server_id[at] in _RUN), None)
        if inside is not None:
            raise ValueRangeError(
                f"server ID byte {inside} is 0x{server_id[inside]:02X}: a master takes the first 0x00 or "
                f"0xFF after the server ID's first byte as the run indicator; put such bytes in "
                f"additional_data")

    def encode(self) -> bytes:
        run = b"" if self.run_indicator is None else b"\xff" if self.run_indicator else b"\x00"
        data = self.server_id + run + self.additional_data
        return bytes([0x11, len(data)]) + data

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_minimum(data, 2, "Report Server ID response", offset)
        _expect_byte_count(data, 2, data[1], "Report Server ID response", offset)
        body = bytes(data[2:])
        at = next((at for at in range(1, len(body)) if body[at] in _RUN), None)
        if at is None:  # no run indicator: the device's own layout, shown as it came
            return cls._from_wire(body, None, b"")
        return cls._from_wire(body[:at], _RUN[body[at]], body[at + 1:])

    def fields(self) -> list[Field]:
        raw = self.encode()
        end = 2 + len(self.server_id)
        rows = [self._function_field(raw), Field(1, raw[1:2], "byte count", raw[1],
                                                 "server ID + run indicator + additional data" if raw[1]
                                                 else "0: no server ID, no run indicator")]
        if self.run_indicator is None:
            rows.append(Field(2, raw[2:], "server ID, not split", _hex(self.server_id),
                              f"no 0x00/0xFF run indicator after the first byte: the device's own layout; "
                              f"as text: {_text(self.server_id)}"))
            return rows
        rows += [Field(2, raw[2:end], "server ID", _hex(self.server_id),
                       f"device specific; as text: {_text(self.server_id)}"),
                 Field(end, raw[end:end + 1], "run indicator", self.run_indicator,
                       "0xFF: ON, the device runs" if self.run_indicator else "0x00: OFF")]
        if self.additional_data:
            rows.append(Field(end + 1, raw[end + 1:], "additional data", _hex(self.additional_data),
                              f"device specific; as text: {_text(self.additional_data)}"))
        return rows

    def _summary_items(self):
        items = [("server_id", self.server_id), ("run_indicator", self.run_indicator)]
        return items + ([("additional_data", self.additional_data)] if self.additional_data else [])


def _text(data: bytes) -> str:
    """Device bytes as text for a reader, as Python writes bytes: printable ASCII, anything else escaped
    (``'LMB3.1.6'``, ``'\\xb4'``): never a control character that would act on a terminal."""
    return repr(data)[1:]


class DiagnosticSubFunction(IntEnum):
    """FC 8's sub-functions (serial lines): a line check, and the counters the serial-line spec defines."""

    RETURN_QUERY_DATA = 0x00
    RESTART_COMMUNICATIONS_OPTION = 0x01
    RETURN_DIAGNOSTIC_REGISTER = 0x02
    CHANGE_ASCII_INPUT_DELIMITER = 0x03
    FORCE_LISTEN_ONLY_MODE = 0x04
    CLEAR_COUNTERS_AND_DIAGNOSTIC_REGISTER = 0x0A
    RETURN_BUS_MESSAGE_COUNT = 0x0B
    RETURN_BUS_COMMUNICATION_ERROR_COUNT = 0x0C
    RETURN_BUS_EXCEPTION_ERROR_COUNT = 0x0D
    RETURN_SERVER_MESSAGE_COUNT = 0x0E
    RETURN_SERVER_NO_RESPONSE_COUNT = 0x0F
    RETURN_SERVER_NAK_COUNT = 0x10
    RETURN_SERVER_BUSY_COUNT = 0x11
    RETURN_BUS_CHARACTER_OVERRUN_COUNT = 0x12
    CLEAR_OVERRUN_COUNTER_AND_FLAG = 0x14


_ECHOED = frozenset({0x00, 0x01, 0x03, 0x0A, 0x14})
"""The sub-functions whose response echoes the request's data (the others answer a counter or register)."""


@dataclass(frozen=True, slots=True)
class _Diagnostics(Pdu):
    sub_function: int
    data: bytes = b"\x00\x00"

    function_code: ClassVar[int] = 0x08

    @classmethod
    def length_from(cls, data: bytes) -> int | None:
        """One data word (5 bytes) for every sub-function but Return Query Data (0x0000), which echoes
        data of any length: its PDU does not say where it ends (:data:`OPEN_LENGTH`)."""
        if len(data) < 3:
            return None
        return OPEN_LENGTH if data[1] == 0 and data[2] == 0 else 5

    @classmethod
    def length_prefix(cls) -> int:
        return 3

    def __post_init__(self) -> None:
        try:
            DiagnosticSubFunction(_check_int(self.sub_function, "sub_function"))
        except ValueError:  # a slave answers an unsupported sub-function with exception 01, as the spec asks
            raise UnknownFunctionError(f"diagnostics sub-function 0x{self.sub_function:04X} is not one this "
                                       f"library implements (0x00-0x04, 0x0A-0x12, 0x14)", function=0x08
                                       ) from None
        data = self.data
        if isinstance(data, int) and not isinstance(data, bool):
            data = _check_register(data).to_bytes(2, "big")
        if not isinstance(data, (bytes, bytearray)) or not 2 <= len(data) <= 250 or len(data) % 2:
            raise ValueRangeError(f"diagnostics data is 2 to 250 bytes, an even number, got {shown(data)}")
        object.__setattr__(self, "data", bytes(data))

    @property
    def value(self) -> int:
        """The first data word (a counter, the diagnostic register, 0x0000 or 0xFF00)."""
        return int.from_bytes(self.data[:2], "big")

    def encode(self) -> bytes:
        return struct.pack(">BH", 0x08, self.sub_function) + self.data

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_minimum(data, 5, f"Diagnostics {cls.role}", offset)
        if len(data) % 2 == 0:
            raise TruncatedError(f"Diagnostics {cls.role}: {len(data) - 3} data bytes from byte "
                                 f"{offset + 3}, expected an even number (16-bit words)")
        sub = int.from_bytes(data[1:3], "big")
        try:
            return cls(sub, bytes(data[3:]))
        except UnknownFunctionError as exc:
            raise UnknownFunctionError(f"at bytes {offset + 1}-{offset + 2}: {exc}", function=0x08) from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        name = DiagnosticSubFunction(self.sub_function).name.replace("_", " ").lower()
        return [self._function_field(raw),
                Field(1, raw[1:3], "sub-function", self.sub_function, name),
                Field(3, raw[3:], "data", _hex(self.data), f"first word {self.value}")]

    def _summary_items(self):
        return [("sub_function", f"0x{self.sub_function:02X}"), ("data", _hex(self.data))]


@dataclass(frozen=True, slots=True)
class DiagnosticsRequest(_Diagnostics):
    """Diagnostics (FC 08) request, serial lines::

        offset  size  field
        0       1     function code 0x08
        1       2     sub-function (see DiagnosticSubFunction)
        3       2N    data: usually one word (0x0000; 0xFF00 asks Restart to clear the event log)

    Return Query Data (0x0000) asks the device to echo the data: a line check.
    """

    role: ClassVar[str] = "request"

    def misfit(self, response: Pdu) -> str:
        """The response names the same sub-function; Return Query Data, Restart Communications, Change
        ASCII Input Delimiter, Clear Counters and Clear Overrun Counter echo the request's data exactly (of
        any even length); every other sub-function answers one data word (a counter, a register)."""
        if response.sub_function != self.sub_function:
            return f"sub-function 0x{response.sub_function:04X}, expected 0x{self.sub_function:04X}"
        if self.sub_function in _ECHOED:
            if response.data != self.data:
                return (f"the echo says {_hex(response.data) or 'nothing'} ({len(response.data)} bytes), "
                        f"the request sent {_hex(self.data)} ({len(self.data)} bytes)")
        elif len(response.data) != 2:
            return f"{len(response.data)} data bytes, expected one 16-bit word (2 bytes)"
        return ""


@dataclass(frozen=True, slots=True)
class DiagnosticsResponse(_Diagnostics):
    """Diagnostics (FC 08) response: the sub-function, then its answer (an echo, or a counter)."""

    role: ClassVar[str] = "response"


@dataclass(frozen=True, slots=True)
class GetCommEventCounterRequest(_NoDataRequest):
    """Get Comm Event Counter (FC 11, 0x0B) request, serial lines: the function code alone."""

    function_code: ClassVar[int] = 0x0B


@dataclass(frozen=True, slots=True)
class GetCommEventCounterResponse(Pdu):
    """Get Comm Event Counter (FC 11, 0x0B) response::

        offset  size  field
        0       1     function code 0x0B
        1       2     status: 0xFFFF while a previous command is still being processed, else 0x0000
        3       2     event count: messages completed normally since the last restart
    """

    status: int
    event_count: int

    function_code: ClassVar[int] = 0x0B
    fixed_size: ClassVar[int | None] = 5
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        _check_register(self.status)
        _check_register(self.event_count)

    def encode(self) -> bytes:
        return struct.pack(">BHH", 0x0B, self.status, self.event_count)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 5, "Get Comm Event Counter response", offset)
        return cls(*struct.unpack(">HH", data[1:]))

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "status", self.status, "0xFFFF: busy" if self.status else "0x0000: ready"),
                Field(3, raw[3:5], "event count", self.event_count, "messages completed normally")]

    def _summary_items(self):
        return [("status", f"0x{self.status:04X}"), ("event_count", self.event_count)]


@dataclass(frozen=True, slots=True)
class GetCommEventLogRequest(_NoDataRequest):
    """Get Comm Event Log (FC 12, 0x0C) request, serial lines: the function code alone."""

    function_code: ClassVar[int] = 0x0C


@dataclass(frozen=True, slots=True)
class GetCommEventLogResponse(Pdu):
    """Get Comm Event Log (FC 12, 0x0C) response::

        offset  size  field
        0       1     function code 0x0C
        1       1     byte count 6 + N
        2       2     status (0xFFFF busy, 0x0000 ready)
        4       2     event count (as FC 11)
        6       2     message count (the bus message count of FC 8)
        8       N     events, newest first, at most 64: 0x80+ a message received, 0x40+ a response sent,
                      0x04 listen-only mode entered, 0x00 communications restarted
    """

    status: int
    event_count: int
    message_count: int
    events: bytes = b""

    function_code: ClassVar[int] = 0x0C
    byte_count_at: ClassVar[int | None] = 1
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        for name in ("status", "event_count", "message_count"):
            _check_register(getattr(self, name))
        if not isinstance(self.events, (bytes, bytearray)) or len(self.events) > 64:
            raise ValueRangeError(f"events are at most 64 bytes, got {shown(self.events)}")
        object.__setattr__(self, "events", bytes(self.events))

    def encode(self) -> bytes:
        return struct.pack(">BBHHH", 0x0C, 6 + len(self.events), self.status, self.event_count,
                           self.message_count) + self.events

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Get Comm Event Log response"
        _expect_minimum(data, 8, name, offset)
        if not 6 <= data[1] <= 70:
            raise ByteCountError(f"at byte {offset + 1}: byte count {data[1]}, expected 6 to 70")
        _expect_byte_count(data, 2, data[1], name, offset)
        status, events, messages = struct.unpack(">HHH", data[2:8])
        return cls(status, events, messages, bytes(data[8:]))

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:2], "byte count", raw[1], "6 + number of events"),
                Field(2, raw[2:4], "status", self.status, "0xFFFF: busy" if self.status else "ready"),
                Field(4, raw[4:6], "event count", self.event_count, "messages completed normally"),
                Field(6, raw[6:8], "message count", self.message_count, "messages seen on the bus"),
                Field(8, raw[8:], "events", _hex(self.events), "newest first")]

    def _summary_items(self):
        return [("event_count", self.event_count), ("message_count", self.message_count),
                ("events", _hex(self.events))]
