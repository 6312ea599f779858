"""File record access (specification sections 6.14, 6.15): Read File Record (FC 20) and Write File Record
(FC 21)."""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Any, ClassVar

from ..codes import (
    MAX_PDU_SIZE,
)
from ..errors import (
    AddressRangeError,
    ByteCountError,
    QuantityError,
    TruncatedError,
    ValueRangeError,
)
from .base import (
    Field,
    Pdu,
    _check_int,
    _check_registers,
    _expect_byte_count,
    _expect_minimum,
)

MAX_RECORD_NUMBER = 9999
"""File records are numbered 0 to 9999 (0x270F) within a file; files are numbered 1 to 65535."""


def _check_file_reference(file: Any, record: Any) -> None:
    if not 1 <= _check_int(file, "file number") <= 0xFFFF:
        raise AddressRangeError(f"file number {file}: expected 1 to 65535")
    if not 0 <= _check_int(record, "record number") <= MAX_RECORD_NUMBER:
        raise AddressRangeError(f"record number {record}: expected 0 to 9999 (0x270F)")


def _records_text(records: tuple[tuple[int, int, tuple[int, ...]], ...]) -> str:
    return "; ".join(f"{file}, {record}, {list(values)}" for file, record, values in records)


@dataclass(frozen=True, slots=True)
class ReadFileRecordRequest(Pdu):
    """Read File Record (FC 20, 0x14) request: one or more sub-requests, each a run of records::

        offset  size  field
        0       1     function code 0x14
        1       1     byte count 7 x N (0x07 to 0xF5)
        then N sub-requests of 7 bytes:
                1     reference type 6
                2     file number (1-65535)
                2     record number (0-9999)
                2     record length (registers to read)
    """

    records: tuple[tuple[int, int, int], ...]

    function_code: ClassVar[int] = 0x14
    byte_count_at: ClassVar[int | None] = 1
    role: ClassVar[str] = "request"

    def __post_init__(self) -> None:
        records = tuple(tuple(item) for item in self.records)
        if not 1 <= len(records) <= 35:
            raise QuantityError(f"{len(records)} sub-requests: expected 1 to 35 (byte count 7 x N <= 0xF5)")
        for file, record, length in records:
            _check_file_reference(file, record)
            if not 1 <= _check_int(length, "record length") or record + length - 1 > MAX_RECORD_NUMBER:
                raise QuantityError(f"record length {length} from record {record}: runs past record 9999")
        if 2 + sum(2 + 2 * length for _, _, length in records) > MAX_PDU_SIZE:
            raise QuantityError("the records asked for do not fit one response (253 bytes)")
        object.__setattr__(self, "records", records)

    def encode(self) -> bytes:
        body = b"".join(struct.pack(">BHHH", 6, f, r, n) for f, r, n in self.records)
        return bytes([0x14, len(body)]) + body

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read File Record request"
        _expect_minimum(data, 2, name, offset)
        count = data[1]
        if not 7 <= count <= 0xF5 or count % 7:
            raise ByteCountError(f"at byte {offset + 1}: byte count {count}, expected a multiple of 7 from 7 "
                                 "to 245")
        _expect_byte_count(data, 2, count, name, offset)
        records = []
        for at in range(2, 2 + count, 7):
            if data[at] != 6:
                raise ValueRangeError(f"at byte {offset + at}: reference type {data[at]}, expected 6")
            records.append(struct.unpack(">HHH", data[at + 1:at + 7]))
        return cls(tuple(records))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw), Field(1, raw[1:2], "byte count", raw[1], "7 per sub-request")]
        for index, (file, record, length) in enumerate(self.records):
            at = 2 + 7 * index
            rows.append(Field(at, raw[at:at + 7], f"sub-request {index}", f"file {file}, record {record}",
                              f"reference type 6, {length} registers"))
        return rows

    def misfit(self, response: Pdu) -> str:
        """One sub-response per sub-request, each as long as its record length asked."""
        asked = [length for _, _, length in self.records]
        got = [len(values) for values in response.records]
        if got != asked:
            return (f"{len(got)} record(s) of {got} registers, expected {len(asked)} of {asked} (the "
                    "record lengths asked)")
        return ""

    def _summary_items(self):
        return [("records", list(self.records))]


@dataclass(frozen=True, slots=True)
class ReadFileRecordResponse(Pdu):
    """Read File Record (FC 20, 0x14) response: one sub-response per sub-request::

        offset  size  field
        0       1     function code 0x14
        1       1     response data length (the sub-responses' bytes)
        then per sub-response:
                1     sub-response length 1 + 2N
                1     reference type 6
                2N    the record data (registers, high byte first)
    """

    records: tuple[tuple[int, ...], ...]

    function_code: ClassVar[int] = 0x14
    byte_count_at: ClassVar[int | None] = 1
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        records = tuple(_check_registers(values, "records") for values in self.records)
        if not records or 2 + sum(2 + 2 * len(values) for values in records) > MAX_PDU_SIZE:
            raise QuantityError("a Read File Record response holds 1 or more records, within 253 bytes")
        object.__setattr__(self, "records", records)

    def encode(self) -> bytes:
        body = b"".join(bytes([1 + 2 * len(v), 6]) + struct.pack(f">{len(v)}H", *v) for v in self.records)
        return bytes([0x14, len(body)]) + body

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read File Record response"
        _expect_minimum(data, 2, name, offset)
        _expect_byte_count(data, 2, data[1], name, offset)
        records, at = [], 2
        while at < len(data):
            size = data[at]
            if size < 1 or size % 2 == 0 or at + 1 + size > len(data):
                raise ByteCountError(f"at byte {offset + at}: sub-response length {size}, expected 1 + 2N "
                                     "within the response")
            if data[at + 1] != 6:
                raise ValueRangeError(f"at byte {offset + at + 1}: reference type {data[at + 1]}, expected 6")
            records.append(struct.unpack(f">{(size - 1) // 2}H", data[at + 2:at + 1 + size]))
            at += 1 + size
        return cls(tuple(records))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw), Field(1, raw[1:2], "response data length", raw[1], "")]
        at = 2
        for index, values in enumerate(self.records):
            size = 2 + 2 * len(values)
            rows.append(Field(at, raw[at:at + size], f"sub-response {index}", list(values),
                              f"{len(values)} registers, reference type 6"))
            at += size
        return rows

    def _summary_items(self):
        return [("records", [list(v) for v in self.records])]


@dataclass(frozen=True, slots=True)
class _WriteFileRecord(Pdu):
    records: tuple[tuple[int, int, tuple[int, ...]], ...]

    function_code: ClassVar[int] = 0x15
    byte_count_at: ClassVar[int | None] = 1

    def __post_init__(self) -> None:
        records = []
        for file, record, values in self.records:
            _check_file_reference(file, record)
            values = _check_registers(values, "record values")
            if not values or record + len(values) - 1 > MAX_RECORD_NUMBER:
                raise QuantityError(f"{len(values)} values from record {record}: 1 or more, up to record "
                                    "9999")
            records.append((file, record, values))
        if not records or 2 + sum(7 + 2 * len(v) for _, _, v in records) > MAX_PDU_SIZE:
            raise QuantityError("a Write File Record request holds 1 or more records, within 253 bytes")
        object.__setattr__(self, "records", tuple(records))

    def encode(self) -> bytes:
        body = b"".join(struct.pack(f">BHHH{len(v)}H", 6, f, r, len(v), *v) for f, r, v in self.records)
        return bytes([0x15, len(body)]) + body

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = f"Write File Record {cls.role}"
        _expect_minimum(data, 2, name, offset)
        _expect_byte_count(data, 2, data[1], name, offset)
        records, at = [], 2
        while at < len(data):
            if at + 7 > len(data):
                raise TruncatedError(f"{name} is truncated: a sub-request header from byte {offset + at}")
            kind, file, record, length = struct.unpack(">BHHH", data[at:at + 7])
            if kind != 6:
                raise ValueRangeError(f"at byte {offset + at}: reference type {kind}, expected 6")
            end = at + 7 + 2 * length
            if end > len(data):
                raise TruncatedError(f"{name} is truncated: record length {length} runs past byte "
                                     f"{len(data)}")
            records.append((file, record, struct.unpack(f">{length}H", data[at + 7:end])))
            at = end
        return cls(tuple(records))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw), Field(1, raw[1:2], "byte count", raw[1], "")]
        at = 2
        for index, (file, record, values) in enumerate(self.records):
            size = 7 + 2 * len(values)
            rows.append(Field(at, raw[at:at + size], f"sub-request {index}", f"file {file}, record {record}",
                              f"reference type 6, values {list(values)}"))
            at += size
        return rows

    def _summary_items(self):
        return [("records", [(f, r, list(v)) for f, r, v in self.records])]


@dataclass(frozen=True, slots=True)
class WriteFileRecordRequest(_WriteFileRecord):
    """Write File Record (FC 21, 0x15) request::

        offset  size  field
        0       1     function code 0x15
        1       1     byte count
        then per sub-request: reference type 6 (1), file number (2), record number (2),
                record length N (2), record data (2N)
    """

    role: ClassVar[str] = "request"

    def misfit(self, response: Pdu) -> str:
        """The response echoes the request: every file, record and value."""
        if response.records != self.records:
            return (f"the echo says (file, record, values) {_records_text(response.records)}, the request "
                    f"was {_records_text(self.records)}")
        return ""


@dataclass(frozen=True, slots=True)
class WriteFileRecordResponse(_WriteFileRecord):
    """Write File Record (FC 21, 0x15) response: an echo of the request (same layout)."""

    role: ClassVar[str] = "response"
