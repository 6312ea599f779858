"""Register access (specification sections 6.3, 6.4, 6.6, 6.12, 6.16, 6.17, 6.18): Read Holding Registers
(FC 3), Read Input Registers (FC 4), Write Single Register (FC 6), Write Multiple Registers (FC 16), Mask
Write Register (FC 22), Read/Write Multiple Registers (FC 23) and Read FIFO Queue (FC 24)."""

from __future__ import annotations

import struct
import sys
from array import array
from dataclasses import dataclass
from typing import ClassVar

from ..errors import (
    AddressRangeError,
    ByteCountError,
    QuantityError,
)
from .base import (
    MAX_READ_REGISTERS,
    MAX_READ_WRITE_REGISTERS,
    MAX_WRITE_REGISTERS,
    Field,
    Pdu,
    _check_address,
    _check_quantity,
    _check_register,
    _check_registers,
    _check_span,
    _count_echo_misfit,
    _expect_byte_count,
    _expect_length,
    _expect_minimum,
    _ReadRequest,
    _value_echo_misfit,
    _WriteMultipleResponse,
)

_LITTLE_ENDIAN = sys.byteorder == "little"
"""An ``array('H')`` keeps registers in the machine's byte order; the wire wants the high byte first."""


@dataclass(frozen=True, slots=True)
class _ReadRegistersRequest(_ReadRequest):
    @classmethod
    def _pack_reply(cls, values: array) -> bytes:
        """Function code, byte count and the registers (an ``array('H')``), high byte first."""
        if _LITTLE_ENDIAN:
            values.byteswap()
        return bytes((cls.function_code, 2 * len(values))) + values.tobytes()

    def misfit(self, response: Pdu) -> str:
        """A read-registers response carries ``count`` registers."""
        if len(response.registers) != self.count:
            return f"{len(response.registers)} registers, expected {self.count}"
        return ""


@dataclass(frozen=True, slots=True)
class _ReadRegistersResponse(Pdu):
    registers: tuple[int, ...]

    role: ClassVar[str] = "response"
    byte_count_at: ClassVar[int | None] = 1

    @classmethod
    def plausible(cls, data: bytes) -> bool:
        return 2 <= data[1] <= 250 and data[1] % 2 == 0

    def __post_init__(self) -> None:
        registers = _check_registers(self.registers, "registers")
        if not 1 <= len(registers) <= MAX_READ_REGISTERS:
            raise QuantityError(f"a read-registers response carries 1 to 125 registers, got {len(registers)}")
        if registers is not self.registers:  # a list given: keep the checked tuple
            object.__setattr__(self, "registers", registers)

    @property
    def byte_count(self) -> int:
        return 2 * len(self.registers)

    def encode(self) -> bytes:
        count = len(self.registers)
        return _REGISTERS_LAYOUT[count].pack(self.function_code, 2 * count, *self.registers)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = cls  # named in a message only if a check fails
        _expect_minimum(data, 2, name, offset)
        byte_count = data[1]
        if byte_count % 2 or not 2 <= byte_count <= 250:
            raise ByteCountError(
                f"at byte {offset + 1}: byte count {byte_count}, expected an even number from 2 to 250 "
                f"(2 bytes per register)")
        _expect_byte_count(data, 2, byte_count, name, offset)
        return cls._from_wire(struct.unpack(f">{byte_count // 2}H", data[2:]))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:2], "byte count", self.byte_count, "2 bytes per register")]
        for index, value in enumerate(self.registers):
            at = 2 + 2 * index
            rows.append(Field(at, raw[at:at + 2], f"register {index}", value,
                              f"0x{value:04X} = {value} (high byte first)"))
        return rows

    def _summary_items(self):
        return [("registers", list(self.registers))]


_REGISTERS_LAYOUT = tuple(struct.Struct(f">BB{count}H") for count in range(MAX_READ_REGISTERS + 1))
"""function code, byte count, then ``count`` big-endian registers: one compiled layout per count."""


@dataclass(frozen=True, slots=True)
class ReadHoldingRegistersRequest(_ReadRegistersRequest):
    """Read Holding Registers (FC 03) request::

        offset  size  field
        0       1     function code 0x03
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of registers (1-125)

    Example: ``03 00 6B 00 03`` reads 3 registers from address 107 (reference numbers 40108-40110).
    """

    function_code: ClassVar[int] = 0x03
    limit: ClassVar[int] = MAX_READ_REGISTERS
    what: ClassVar[str] = "registers"
    table: ClassVar[str] = "holding_registers"


@dataclass(frozen=True, slots=True)
class ReadHoldingRegistersResponse(_ReadRegistersResponse):
    """Read Holding Registers (FC 03) response::

        offset  size  field
        0       1     function code 0x03
        1       1     byte count 2 x N
        2       2N    register values, each high byte first
    """

    function_code: ClassVar[int] = 0x03


@dataclass(frozen=True, slots=True)
class ReadInputRegistersRequest(_ReadRegistersRequest):
    """Read Input Registers (FC 04) request::

        offset  size  field
        0       1     function code 0x04
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of input registers (1-125)
    """

    function_code: ClassVar[int] = 0x04
    limit: ClassVar[int] = MAX_READ_REGISTERS
    what: ClassVar[str] = "input registers"
    table: ClassVar[str] = "input_registers"


@dataclass(frozen=True, slots=True)
class ReadInputRegistersResponse(_ReadRegistersResponse):
    """Read Input Registers (FC 04) response::

        offset  size  field
        0       1     function code 0x04
        1       1     byte count 2 x N
        2       2N    input register values, each high byte first
    """

    function_code: ClassVar[int] = 0x04


@dataclass(frozen=True, slots=True)
class _WriteSingleRegister(Pdu):
    address: int
    value: int

    function_code: ClassVar[int] = 0x06
    fixed_size: ClassVar[int | None] = 5

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        object.__setattr__(self, "value", _check_register(self.value))

    def encode(self) -> bytes:
        return struct.pack(">BHH", 0x06, self.address, self.value)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 5, f"Write Single Register {cls.role}", offset)
        _fc, address, value = struct.unpack(">BHH", data)
        return cls(address, value)

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "register address", self.address, "0-based holding register address"),
                Field(3, raw[3:5], "register value", self.value, f"0x{self.value:04X} = {self.value}")]

    def _summary_items(self):
        return [("address", self.address), ("value", self.value)]


@dataclass(frozen=True, slots=True)
class WriteSingleRegisterRequest(_WriteSingleRegister):
    """Write Single Register (FC 06) request::

        offset  size  field
        0       1     function code 0x06
        1       2     register address (0x0000-0xFFFF)
        3       2     register value (0x0000-0xFFFF)
    """

    role: ClassVar[str] = "request"

    def misfit(self, response: Pdu) -> str:
        return _value_echo_misfit(self, response)


@dataclass(frozen=True, slots=True)
class WriteSingleRegisterResponse(_WriteSingleRegister):
    """Write Single Register (FC 06) response: an echo of the request::

        offset  size  field
        0       1     function code 0x06
        1       2     register address
        3       2     register value
    """

    role: ClassVar[str] = "response"


@dataclass(frozen=True, slots=True)
class WriteMultipleRegistersRequest(Pdu):
    """Write Multiple Registers (FC 16) request::

        offset  size  field
        0       1     function code 0x10
        1       2     starting address
        3       2     quantity of registers (1-123)
        5       1     byte count 2 x N
        6       2N    register values, each high byte first

    Example: ``10 00 01 00 02 04 00 0A 01 02`` writes 0x000A and 0x0102 from address 1.
    """

    address: int
    values: tuple[int, ...]

    function_code: ClassVar[int] = 0x10
    byte_count_at: ClassVar[int | None] = 5
    role: ClassVar[str] = "request"

    @classmethod
    def plausible(cls, data: bytes) -> bool:
        """The byte count is 2 x quantity."""
        return len(data) < 6 or data[5] == 2 * int.from_bytes(data[3:5], "big")

    def misfit(self, response: Pdu) -> str:
        return _count_echo_misfit(self, response)

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        values = _check_registers(self.values, "values")
        _check_quantity(len(values), MAX_WRITE_REGISTERS, "registers", "len(values)")
        _check_span(self.address, len(values), "register")
        object.__setattr__(self, "values", values)

    def encode(self) -> bytes:
        count = len(self.values)
        return struct.pack(f">BHHB{count}H", 0x10, self.address, count, 2 * count, *self.values)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Write Multiple Registers request"
        _expect_minimum(data, 6, name, offset)
        _fc, address, count, byte_count = struct.unpack(">BHHB", data[:6])
        if not 1 <= count <= MAX_WRITE_REGISTERS:
            raise QuantityError(
                f"at bytes {offset + 3}-{offset + 4}: quantity of registers is {count}, expected 1 to 123")
        if byte_count != 2 * count:
            raise ByteCountError(
                f"at byte {offset + 5}: byte count {byte_count}, expected {2 * count} for {count} registers")
        _expect_byte_count(data, 6, byte_count, name, offset)
        try:
            return cls(address, struct.unpack(f">{count}H", data[6:]))
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 4}: {exc}") from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:3], "starting address", self.address, "0-based holding register address"),
                Field(3, raw[3:5], "quantity of registers", len(self.values), "1-123"),
                Field(5, raw[5:6], "byte count", raw[5], "2 bytes per register")]
        for index, value in enumerate(self.values):
            at = 6 + 2 * index
            rows.append(Field(at, raw[at:at + 2], f"register {index}", value,
                              f"0x{value:04X} = {value} (high byte first)"))
        return rows

    def _summary_items(self):
        return [("address", self.address), ("values", list(self.values))]


@dataclass(frozen=True, slots=True)
class WriteMultipleRegistersResponse(_WriteMultipleResponse):
    """Write Multiple Registers (FC 16) response::

        offset  size  field
        0       1     function code 0x10
        1       2     starting address
        3       2     quantity of registers written (1-123)
    """

    function_code: ClassVar[int] = 0x10
    limit: ClassVar[int] = MAX_WRITE_REGISTERS
    what: ClassVar[str] = "registers"


@dataclass(frozen=True, slots=True)
class _MaskWriteRegister(Pdu):
    address: int
    and_mask: int
    or_mask: int

    function_code: ClassVar[int] = 0x16
    fixed_size: ClassVar[int | None] = 7

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        object.__setattr__(self, "and_mask", _check_register(self.and_mask))
        object.__setattr__(self, "or_mask", _check_register(self.or_mask))

    def encode(self) -> bytes:
        return struct.pack(">BHHH", 0x16, self.address, self.and_mask, self.or_mask)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 7, f"Mask Write Register {cls.role}", offset)
        _fc, address, and_mask, or_mask = struct.unpack(">BHHH", data)
        return cls(address, and_mask, or_mask)

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "reference address", self.address, "0-based holding register address"),
                Field(3, raw[3:5], "AND mask", self.and_mask, f"0x{self.and_mask:04X}: bits kept"),
                Field(5, raw[5:7], "OR mask", self.or_mask,
                      f"0x{self.or_mask:04X}: bits set (where not kept)")]

    def _summary_items(self):
        return [("address", self.address), ("and_mask", f"0x{self.and_mask:04X}"),
                ("or_mask", f"0x{self.or_mask:04X}")]


def mask_write(current: int, and_mask: int, or_mask: int) -> int:
    """The register value after FC 22: ``(current AND and_mask) OR (or_mask AND NOT and_mask)``.

    The specification's example: ``mask_write(0x12, 0xF2, 0x25)`` is ``0x17``."""
    return (current & and_mask) | (or_mask & ~and_mask & 0xFFFF)


@dataclass(frozen=True, slots=True)
class MaskWriteRegisterRequest(_MaskWriteRegister):
    """Mask Write Register (FC 22, 0x16) request: change some bits of one holding register::

        offset  size  field
        0       1     function code 0x16
        1       2     reference address
        3       2     AND mask
        5       2     OR mask

    The register becomes ``(current AND and_mask) OR (or_mask AND NOT and_mask)`` (see :func:`mask_write`).
    """

    role: ClassVar[str] = "request"

    def misfit(self, response: Pdu) -> str:
        if response != MaskWriteRegisterResponse(self.address, self.and_mask, self.or_mask):
            return "the echo differs from the request"
        return ""


@dataclass(frozen=True, slots=True)
class MaskWriteRegisterResponse(_MaskWriteRegister):
    """Mask Write Register (FC 22, 0x16) response: an echo of the request (same layout)."""

    role: ClassVar[str] = "response"


@dataclass(frozen=True, slots=True)
class ReadWriteMultipleRegistersRequest(Pdu):
    """Read/Write Multiple Registers (FC 23, 0x17) request: a write, then a read, in one transaction::

        offset  size  field
        0       1     function code 0x17
        1       2     read starting address
        3       2     quantity to read (1-125)
        5       2     write starting address
        7       2     quantity to write (1-121)
        9       1     write byte count 2 x N
        10      2N    write register values, each high byte first

    The server writes first, then reads (the read sees the values just written).
    """

    read_address: int
    read_count: int
    write_address: int
    values: tuple[int, ...]

    function_code: ClassVar[int] = 0x17
    byte_count_at: ClassVar[int | None] = 9
    role: ClassVar[str] = "request"

    def misfit(self, response: Pdu) -> str:
        if len(response.registers) != self.read_count:
            return f"{len(response.registers)} registers, expected {self.read_count}"
        return ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "read_address", _check_address(self.read_address))
        object.__setattr__(self, "read_count", _check_quantity(self.read_count, MAX_READ_REGISTERS,
                                                                "registers to read", "read_count"))
        _check_span(self.read_address, self.read_count, "register")
        object.__setattr__(self, "write_address", _check_address(self.write_address))
        values = _check_registers(self.values, "values")
        _check_quantity(len(values), MAX_READ_WRITE_REGISTERS, "registers to write", "len(values)")
        _check_span(self.write_address, len(values), "register")
        object.__setattr__(self, "values", values)

    def encode(self) -> bytes:
        count = len(self.values)
        return struct.pack(f">BHHHHB{count}H", 0x17, self.read_address, self.read_count, self.write_address,
                           count, 2 * count, *self.values)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read/Write Multiple Registers request"
        _expect_minimum(data, 10, name, offset)
        _fc, read_address, read_count, write_address, count, byte_count = struct.unpack(">BHHHHB", data[:10])
        if not 1 <= read_count <= MAX_READ_REGISTERS:
            raise QuantityError(f"at bytes {offset + 3}-{offset + 4}: quantity to read is {read_count}, "
                                f"expected 1 to {MAX_READ_REGISTERS}")
        if not 1 <= count <= MAX_READ_WRITE_REGISTERS:
            raise QuantityError(f"at bytes {offset + 7}-{offset + 8}: quantity to write is {count}, "
                                f"expected 1 to {MAX_READ_WRITE_REGISTERS}")
        if byte_count != 2 * count:
            raise ByteCountError(f"at byte {offset + 9}: write byte count {byte_count}, expected {2 * count} "
                                 f"for {count} registers")
        _expect_byte_count(data, 10, byte_count, name, offset)
        try:
            return cls(read_address, read_count, write_address, struct.unpack(f">{count}H", data[10:]))
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 8}: {exc}") from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:3], "read starting address", self.read_address, "0-based holding register"),
                Field(3, raw[3:5], "quantity to read", self.read_count, "1-125"),
                Field(5, raw[5:7], "write starting address", self.write_address, "0-based holding register"),
                Field(7, raw[7:9], "quantity to write", len(self.values), "1-121"),
                Field(9, raw[9:10], "write byte count", raw[9], "2 bytes per register")]
        for index, value in enumerate(self.values):
            at = 10 + 2 * index
            rows.append(Field(at, raw[at:at + 2], f"write register {index}", value,
                              f"0x{value:04X} = {value} (high byte first)"))
        return rows

    def _summary_items(self):
        return [("read_address", self.read_address), ("read_count", self.read_count),
                ("write_address", self.write_address), ("values", list(self.values))]


@dataclass(frozen=True, slots=True)
class ReadWriteMultipleRegistersResponse(_ReadRegistersResponse):
    """Read/Write Multiple Registers (FC 23, 0x17) response: the registers read (after the write)::

        offset  size  field
        0       1     function code 0x17
        1       1     byte count 2 x N
        2       2N    register values, each high byte first
    """

    function_code: ClassVar[int] = 0x17


MAX_FIFO_COUNT = 31
"""Read FIFO Queue (FC 24): a queue holds at most 31 values (more is exception 03)."""


@dataclass(frozen=True, slots=True)
class ReadFifoQueueRequest(Pdu):
    """Read FIFO Queue (FC 24, 0x18) request::

        offset  size  field
        0       1     function code 0x18
        1       2     FIFO pointer address (the register that holds the queue's count)
    """

    address: int

    function_code: ClassVar[int] = 0x18
    fixed_size: ClassVar[int | None] = 3
    role: ClassVar[str] = "request"

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))

    def encode(self) -> bytes:
        return struct.pack(">BH", 0x18, self.address)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 3, "Read FIFO Queue request", offset)
        return cls(struct.unpack(">H", data[1:3])[0])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "FIFO pointer address", self.address, "the register holding the count")]

    def _summary_items(self):
        return [("address", self.address)]


@dataclass(frozen=True, slots=True)
class ReadFifoQueueResponse(Pdu):
    """Read FIFO Queue (FC 24, 0x18) response: the queue's values, oldest first::

        offset  size  field
        0       1     function code 0x18
        1       2     byte count 2 + 2N (two bytes: this function's count is a word)
        3       2     FIFO count N (0-31)
        5       2N    FIFO values, each high byte first
    """

    values: tuple[int, ...]

    function_code: ClassVar[int] = 0x18
    role: ClassVar[str] = "response"

    @classmethod
    def length_from(cls, data: bytes) -> int | None:
        """3 + its byte count, a 16-bit field (bytes 1-2)."""
        return 3 + int.from_bytes(data[1:3], "big") if len(data) >= 3 else None

    @classmethod
    def length_prefix(cls) -> int:
        return 3

    def __post_init__(self) -> None:
        values = () if self.values == () else _check_registers(self.values, "values")
        if len(values) > MAX_FIFO_COUNT:
            raise QuantityError(f"a FIFO queue holds at most {MAX_FIFO_COUNT} values, got {len(values)}")
        object.__setattr__(self, "values", tuple(values))

    def encode(self) -> bytes:
        count = len(self.values)
        return struct.pack(f">BHH{count}H", 0x18, 2 + 2 * count, count, *self.values)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read FIFO Queue response"
        _expect_minimum(data, 5, name, offset)
        byte_count, count = struct.unpack(">HH", data[1:5])
        if count > MAX_FIFO_COUNT:
            raise QuantityError(f"at bytes {offset + 3}-{offset + 4}: FIFO count {count}, expected 0 to 31")
        if byte_count != 2 + 2 * count:
            raise ByteCountError(f"at bytes {offset + 1}-{offset + 2}: byte count {byte_count}, expected "
                                 f"{2 + 2 * count} for {count} values")
        _expect_length(data, 3 + byte_count, name, offset)
        return cls(struct.unpack(f">{count}H", data[5:]))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:3], "byte count", 2 + 2 * len(self.values), "FIFO count + values (2 bytes)"),
                Field(3, raw[3:5], "FIFO count", len(self.values), "values in the queue (0-31)")]
        for index, value in enumerate(self.values):
            at = 5 + 2 * index
            rows.append(Field(at, raw[at:at + 2], f"FIFO value {index}", value, f"0x{value:04X} = {value}"))
        return rows

    def _summary_items(self):
        return [("values", list(self.values))]
