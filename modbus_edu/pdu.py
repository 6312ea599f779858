"""The protocol data unit (PDU): a function code and its data.

A PDU is the part of a Modbus message that is the same in every mode (RTU, ASCII, TCP)::

    +---------------+-----------------------------+
    | function code | data (0 to 252 bytes)       |
    |   1 byte      | layout depends on function  |
    +---------------+-----------------------------+

The first byte says what to do; for a response with its top bit set (function code + 0x80) it says
"this is an exception response" instead.  Every field wider than one byte is big-endian (high byte
first).  This module has one request class and one response class per function code, each documenting
its byte layout, plus :class:`ExceptionResponse`.  Constructors check every rule of the specification
(quantity limits, address range, value ranges) and ``decode`` checks the bytes (byte counts, truncated
and trailing data); a broken rule raises a :class:`~modbus_edu.errors.PduError` subclass whose message
says what was wrong, at which byte, and what was expected.

Byte offsets in error messages count from the first byte of the PDU (the function code) unless the
caller passes ``offset`` to :func:`decode_pdu` so that they count from the start of the whole frame.
"""

from __future__ import annotations

import dataclasses
import functools
import struct
from collections.abc import Iterable, Mapping
from collections.abc import Set as AbstractSet
from dataclasses import dataclass
from enum import IntEnum
from typing import Any, ClassVar

from .codes import (
    MAX_PDU_SIZE,
    ROLES,
    SERIAL_LINE_ONLY,
    ExceptionCode,  # noqa: F401 (modbus_edu.pdu re-exports it)
    FunctionCode,
    _hex,
    exception_meaning,
    function_title,
)
from .errors import (
    AddressRangeError,
    ByteCountError,
    ConfigError,
    PduError,
    QuantityError,
    TrailingBytesError,
    TruncatedError,
    UnknownFunctionError,
    ValueRangeError,
    shown,
)

MAX_READ_BITS = 2000
"""Read Coils / Read Discrete Inputs: 1 to 2000 bits per request (250 data bytes in the response)."""
MAX_READ_REGISTERS = 125
"""Read Holding / Input Registers: 1 to 125 registers per request (250 data bytes in the response)."""
MAX_WRITE_COILS = 1968
"""Write Multiple Coils: 1 to 1968 coils (0x7B0) per request (246 data bytes)."""
MAX_WRITE_REGISTERS = 123
"""Write Multiple Registers: 1 to 123 registers (0x7B) per request (246 data bytes)."""
MAX_READ_WRITE_REGISTERS = 121
"""Read/Write Multiple Registers (FC 23): 1 to 121 registers written per request (0x79)."""
COIL_ON = 0xFF00
COIL_OFF = 0x0000


@dataclass(frozen=True)
class Field:
    """One field of a PDU, for dissection tables: where it is, its bytes, its name, value and meaning."""

    offset: int
    raw: bytes
    name: str
    value: Any
    meaning: str


# --- checks shared by the classes -------------------------------------------------------------------

def _check_int(value: Any, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueRangeError(f"{name} must be an integer, got {shown(value)}")
    if value.bit_length() > 64:
        raise ValueRangeError(f"{name} is {shown(value)}: far outside any Modbus field")
    return value


def _check_address(address: Any) -> int:
    address = _check_int(address, "address")
    if not 0 <= address <= 0xFFFF:
        raise ValueRangeError(f"address {address} is outside 0..65535 (a 16-bit field)")
    return address


def _check_quantity(count: Any, limit: int, what: str, name: str = "count") -> int:
    count = _check_int(count, name)
    if not 1 <= count <= limit:
        raise QuantityError(f"quantity of {what} is {count}, expected 1 to {limit}")
    return count


def _check_span(address: int, count: int, what: str) -> None:
    if address + count > 0x10000:
        raise AddressRangeError(
            f"address {address} + quantity {count} = {address + count} runs past the last {what} address "
            f"65535 (address + quantity must be <= 65536)")


def _check_register(value: Any, index: int | None = None) -> int:
    label = "register value" if index is None else f"register value #{index}"
    value = _check_int(value, label)
    if not 0 <= value <= 0xFFFF:
        raise ValueRangeError(f"{label} {value} is outside 0..65535 (registers are unsigned 16-bit)")
    return value


def _check_sequence(values: Any, name: str, what: str) -> None:
    """A mapping or a set is iterable but has no order of values: refuse it, as a plain value."""
    if isinstance(values, (Mapping, AbstractSet, str, bytes)) or not isinstance(values, Iterable):
        raise ValueRangeError(f"{name} must be a sequence (list or tuple) of {what}, "
                              f"got {type(values).__name__} {values!r}")


def _check_bits(values: Any, name: str) -> tuple[bool, ...]:
    _check_sequence(values, name, "booleans")
    try:
        items = tuple(values)
    except TypeError:
        raise ValueRangeError(f"{name} must be a sequence of booleans, got {values!r}") from None
    for index, item in enumerate(items):
        if item not in (0, 1) or not isinstance(item, (bool, int)):
            raise ValueRangeError(f"{name}[{index}] is {item!r}, expected True/False (or 1/0)")
    return tuple(bool(item) for item in items)


def _check_registers(values: Any, name: str) -> tuple[int, ...]:
    if type(values) not in (list, tuple):
        _check_sequence(values, name, "integers")
    try:
        items = tuple(values)
    except TypeError:
        raise ValueRangeError(f"{name} must be a sequence of integers, got {values!r}") from None
    if all(type(item) is int and 0 <= item <= 0xFFFF for item in items):
        return items
    return tuple(_check_register(item, index) for index, item in enumerate(items))


def pack_bits(bits: tuple[bool, ...]) -> bytes:
    """Pack bits eight to a byte, the first bit in the least significant position; pad with zeros."""
    out = bytearray((len(bits) + 7) // 8)
    for index, bit in enumerate(bits):
        if bit:
            out[index >> 3] |= 1 << (index & 7)
    return bytes(out)


def unpack_bits(data: bytes) -> tuple[bool, ...]:
    """Every bit of ``data``, least significant bit of the first byte first (8 per byte)."""
    return tuple(bool(byte >> bit & 1) for byte in data for bit in range(8))


def _expect_length(data: bytes, length: int, name: str, base: int) -> None:
    if len(data) < length:
        where = f"byte {base}" if len(data) == 1 else f"bytes {base}-{base + len(data) - 1}"
        raise TruncatedError(
            f"{name} is truncated: {len(data)} byte{'s' if len(data) != 1 else ''} at {where}, "
            f"expected {length} bytes (the PDU ends at byte {base + length - 1})")
    if len(data) > length:
        raise TrailingBytesError(
            f"{name} has {len(data) - length} trailing byte(s) from byte {base + length}: "
            f"expected exactly {length} bytes")


def _pdu_bytes(data: Any, offset: int) -> bytes:
    """The PDU as bytes; text or an empty PDU is a teaching error, not a TypeError."""
    if isinstance(data, str):
        raise PduError(f"a PDU is bytes, got the text {data[:30]!r}: turn hex text into bytes first, "
                       f"e.g. bytes.fromhex('03 00 00 00 01')")
    if isinstance(data, int):  # bytes(5) would be five zero bytes, not the byte 5
        raise PduError(f"a PDU is bytes, got the number {data!r}: write bytes([{data}]) for one byte")
    try:
        data = bytes(data)
    except (TypeError, ValueError):
        raise PduError(f"a PDU is bytes (values 0..255), got {type(data).__name__}") from None
    if not data:
        raise TruncatedError(f"empty PDU at byte {offset}: expected at least a function code")
    return data


# --- the classes -----------------------------------------------------------------------------------

@functools.cache
def _field_names(cls: type) -> tuple[str, ...]:
    return tuple(item.name for item in dataclasses.fields(cls))


class Pdu:
    """Base of every PDU class.

    ``function_code`` is the first byte, ``role`` says whether the class is a request or a response.
    ``encode()`` gives the bytes (function code first); ``decode(data)`` is the inverse and is strict.
    """

    function_code: ClassVar[int]
    role: ClassVar[str]
    __slots__ = ()

    @property
    def title(self) -> str:
        return function_title(self.function_code)

    def encode(self) -> bytes:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    @classmethod
    def decode(cls, data: bytes, offset: int = 0) -> Pdu:
        """Decode this class's PDU from ``data`` (function code first); strict about every byte.

        ``offset`` is added to byte positions in error messages.  :func:`decode_pdu` picks the class
        from the function code; calling a class's ``decode`` directly checks that the code is its own.
        """
        data = _pdu_bytes(data, offset)
        if data[0] != cls.function_code:
            raise UnknownFunctionError(
                f"at byte {offset}: function code 0x{data[0]:02X}, but {cls.__name__} has function code "
                f"0x{cls.function_code:02X}; use decode_pdu(data, role) to pick the class from the code",
                function=data[0])
        return cls._decode(data, offset)

    @classmethod
    def _decode(cls, data: bytes, offset: int) -> Pdu:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def fields(self) -> list[Field]:  # pragma: no cover
        raise NotImplementedError

    def _function_field(self, raw: bytes) -> Field:
        note = "; the spec defines it for serial lines only" if self.function_code in SERIAL_LINE_ONLY else ""
        return Field(0, raw[:1], "function code", self.function_code,
                     f"{function_title(self.function_code)} ({self.role}){note}")

    @classmethod
    def _from_wire(cls, *values: Any) -> Pdu:
        """Build an instance from fields that ``decode`` has already checked, skipping the checks again."""
        obj = object.__new__(cls)
        for name, value in zip(_field_names(cls), values):
            object.__setattr__(obj, name, value)
        return obj

    def _repr_html_(self) -> str:
        """In a notebook a PDU shows as its dissection table (:func:`modbus_edu.explain.explain_pdu`)."""
        from .explain import explain_pdu

        return explain_pdu(self)._repr_html_()

    def summary(self) -> str:
        """One line such as ``Read Holding Registers request: address 0, count 1``."""
        parts = [f"{name} {value}" for name, value in self._summary_items()]
        return f"{self.title} {self.role}" + (": " + ", ".join(parts) if parts else "")

    def _summary_items(self) -> list[tuple[str, Any]]:  # pragma: no cover
        return []


@dataclass(frozen=True, slots=True)
class _ReadRequest(Pdu):
    address: int
    count: int

    role: ClassVar[str] = "request"
    limit: ClassVar[int]
    what: ClassVar[str]

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        object.__setattr__(self, "count", _check_quantity(self.count, self.limit, self.what))
        _check_span(self.address, self.count, self.what[:-1] if self.what.endswith("s") else self.what)

    def encode(self) -> bytes:
        return struct.pack(">BHH", self.function_code, self.address, self.count)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 5, f"{function_title(cls.function_code)} request", offset)
        _fc, address, count = struct.unpack(">BHH", data)
        try:
            return cls(address, count)
        except QuantityError as exc:
            raise QuantityError(f"at bytes {offset + 3}-{offset + 4}: {exc}") from None
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 4}: {exc}") from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [
            self._function_field(raw),
            Field(1, raw[1:3], "starting address", self.address,
                  f"0-based {self.what[:-1] if self.what.endswith('s') else self.what} address"),
            Field(3, raw[3:5], "quantity", self.count, f"number of {self.what} to read (1-{self.limit})"),
        ]

    def _summary_items(self):
        return [("address", self.address), ("count", self.count)]


@dataclass(frozen=True, slots=True)
class _ReadBitsResponse(Pdu):
    bits: tuple[bool, ...]

    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        bits = _check_bits(self.bits, "bits")
        if not 1 <= len(bits) <= 8 * 250:
            raise QuantityError(f"a read-bits response carries 1 to 2000 bits (250 bytes), got {len(bits)}")
        object.__setattr__(self, "bits", bits)

    @property
    def byte_count(self) -> int:
        return (len(self.bits) + 7) // 8

    def encode(self) -> bytes:
        return bytes((self.function_code, self.byte_count)) + pack_bits(self.bits)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = cls  # named in a message only if a check fails
        _expect_minimum(data, 2, name, offset)
        byte_count = data[1]
        if not 1 <= byte_count <= 250:
            raise ByteCountError(
                f"at byte {offset + 1}: byte count {byte_count}, expected 1 to 250 (ceil(quantity / 8))")
        _expect_byte_count(data, 2, byte_count, name, offset)
        return cls(unpack_bits(data[2:]))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:2], "byte count", self.byte_count, "number of data bytes that follow")]
        for index in range(self.byte_count):
            chunk = self.bits[index * 8:index * 8 + 8]
            shown = "".join("1" if bit else "0" for bit in reversed(chunk))
            rows.append(Field(2 + index, raw[2 + index:3 + index], f"bits {index * 8}-{index * 8 + 7}",
                              shown, "first bit in the least significant position (rightmost)"))
        return rows

    def _summary_items(self):
        return [("bits", "".join("1" if bit else "0" for bit in self.bits))]


@dataclass(frozen=True, slots=True)
class _ReadRegistersResponse(Pdu):
    registers: tuple[int, ...]

    role: ClassVar[str] = "response"

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


def _label(name: str | type[Pdu]) -> str:
    """A PDU's name for a message: the string itself, or "<Function Title> <role>" of a class."""
    return name if isinstance(name, str) else f"{function_title(name.function_code)} {name.role}"


_REGISTERS_LAYOUT = tuple(struct.Struct(f">BB{count}H") for count in range(MAX_READ_REGISTERS + 1))
"""function code, byte count, then ``count`` big-endian registers: one compiled layout per count."""


def _expect_minimum(data: bytes, length: int, name: str | type[Pdu], base: int) -> None:
    if len(data) < length:
        raise TruncatedError(
            f"{_label(name)} is truncated: {len(data)} byte(s), expected at least {length} "
            f"(bytes {base}-{base + length - 1})")


def _expect_byte_count(data: bytes, header: int, byte_count: int, name: str | type[Pdu],
                       base: int) -> None:
    present = len(data) - header
    if present < byte_count:
        raise TruncatedError(
            f"{_label(name)} is truncated: byte count at byte {base + header - 1} announces "
            f"{byte_count} data bytes, only {present} follow")
    if present > byte_count:
        raise TrailingBytesError(
            f"{_label(name)} has {present - byte_count} trailing byte(s) from byte "
            f"{base + header + byte_count}: the byte count announces {byte_count} data bytes")


@dataclass(frozen=True, slots=True)
class ReadCoilsRequest(_ReadRequest):
    """Read Coils (FC 01) request: read 1 to 2000 contiguous coils::

        offset  size  field
        0       1     function code 0x01
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of coils (1-2000)
    """

    function_code: ClassVar[int] = 0x01
    limit: ClassVar[int] = MAX_READ_BITS
    what: ClassVar[str] = "coils"


@dataclass(frozen=True, slots=True)
class ReadCoilsResponse(_ReadBitsResponse):
    """Read Coils (FC 01) response::

        offset  size  field
        0       1     function code 0x01
        1       1     byte count N = ceil(quantity / 8)
        2       N     coil status, 8 coils per byte, first coil in the least significant bit;
                      unused high bits of the last byte are 0

    Decoded from bytes alone, ``bits`` holds all 8 x N bits, padding included (the response does not
    say how many coils were asked for; the request does).
    """

    function_code: ClassVar[int] = 0x01


@dataclass(frozen=True, slots=True)
class ReadDiscreteInputsRequest(_ReadRequest):
    """Read Discrete Inputs (FC 02) request::

        offset  size  field
        0       1     function code 0x02
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of inputs (1-2000)
    """

    function_code: ClassVar[int] = 0x02
    limit: ClassVar[int] = MAX_READ_BITS
    what: ClassVar[str] = "discrete inputs"


@dataclass(frozen=True, slots=True)
class ReadDiscreteInputsResponse(_ReadBitsResponse):
    """Read Discrete Inputs (FC 02) response::

        offset  size  field
        0       1     function code 0x02
        1       1     byte count N = ceil(quantity / 8)
        2       N     input status, 8 per byte, first input in the least significant bit
    """

    function_code: ClassVar[int] = 0x02


@dataclass(frozen=True, slots=True)
class ReadHoldingRegistersRequest(_ReadRequest):
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
class ReadInputRegistersRequest(_ReadRequest):
    """Read Input Registers (FC 04) request::

        offset  size  field
        0       1     function code 0x04
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of input registers (1-125)
    """

    function_code: ClassVar[int] = 0x04
    limit: ClassVar[int] = MAX_READ_REGISTERS
    what: ClassVar[str] = "input registers"


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
class _WriteSingleCoil(Pdu):
    address: int
    value: bool

    function_code: ClassVar[int] = 0x05

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        if self.value not in (0, 1) or not isinstance(self.value, (bool, int)):
            raise ValueRangeError(f"coil value {self.value!r} must be True (ON) or False (OFF)")
        object.__setattr__(self, "value", bool(self.value))

    def encode(self) -> bytes:
        return struct.pack(">BHH", 0x05, self.address, COIL_ON if self.value else COIL_OFF)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 5, f"Write Single Coil {cls.role}", offset)
        _fc, address, raw = struct.unpack(">BHH", data)
        if raw not in (COIL_ON, COIL_OFF):
            raise ValueRangeError(
                f"at bytes {offset + 3}-{offset + 4}: coil value 0x{raw:04X}, expected 0xFF00 (ON) or "
                f"0x0000 (OFF)")
        return cls(address, raw == COIL_ON)

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "output address", self.address, "0-based coil address"),
                Field(3, raw[3:5], "output value", "ON" if self.value else "OFF",
                      "0xFF00 = ON, 0x0000 = OFF (no other value is allowed)")]

    def _summary_items(self):
        return [("address", self.address), ("value", "ON" if self.value else "OFF")]


@dataclass(frozen=True, slots=True)
class WriteSingleCoilRequest(_WriteSingleCoil):
    """Write Single Coil (FC 05) request::

        offset  size  field
        0       1     function code 0x05
        1       2     output address (0x0000-0xFFFF)
        3       2     output value: FF 00 = ON, 00 00 = OFF

    ``value`` is a bool.  Example: ``05 00 AC FF 00`` switches coil 172 ON.
    """

    role: ClassVar[str] = "request"


@dataclass(frozen=True, slots=True)
class WriteSingleCoilResponse(_WriteSingleCoil):
    """Write Single Coil (FC 05) response: an echo of the request::

        offset  size  field
        0       1     function code 0x05
        1       2     output address
        3       2     output value: FF 00 = ON, 00 00 = OFF
    """

    role: ClassVar[str] = "response"


@dataclass(frozen=True, slots=True)
class _WriteSingleRegister(Pdu):
    address: int
    value: int

    function_code: ClassVar[int] = 0x06

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
class WriteMultipleCoilsRequest(Pdu):
    """Write Multiple Coils (FC 15) request::

        offset  size  field
        0       1     function code 0x0F
        1       2     starting address
        3       2     quantity of outputs (1-1968)
        5       1     byte count N = ceil(quantity / 8)
        6       N     output values, 8 per byte, first coil in the least significant bit,
                      unused high bits of the last byte 0

    Example: ``0F 00 13 00 0A 02 CD 01`` writes 10 coils from address 19.
    """

    address: int
    values: tuple[bool, ...]

    function_code: ClassVar[int] = 0x0F
    role: ClassVar[str] = "request"

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        values = _check_bits(self.values, "values")
        _check_quantity(len(values), MAX_WRITE_COILS, "coils", "len(values)")
        _check_span(self.address, len(values), "coil")
        object.__setattr__(self, "values", values)

    def encode(self) -> bytes:
        packed = pack_bits(self.values)
        return struct.pack(">BHHB", 0x0F, self.address, len(self.values), len(packed)) + packed

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Write Multiple Coils request"
        _expect_minimum(data, 6, name, offset)
        _fc, address, count, byte_count = struct.unpack(">BHHB", data[:6])
        if not 1 <= count <= MAX_WRITE_COILS:
            raise QuantityError(
                f"at bytes {offset + 3}-{offset + 4}: quantity of coils is {count}, expected 1 to 1968")
        expected = (count + 7) // 8
        if byte_count != expected:
            raise ByteCountError(
                f"at byte {offset + 5}: byte count {byte_count}, expected {expected} for {count} coils "
                f"(ceil({count} / 8))")
        _expect_byte_count(data, 6, byte_count, name, offset)
        bits = unpack_bits(data[6:])
        if any(bits[count:]):
            raise ValueRangeError(
                f"at byte {offset + 5 + byte_count}: padding bits above coil {count - 1} are not 0 "
                f"(last data byte 0x{data[-1]:02X}); unused bits must be zero")
        try:
            return cls(address, bits[:count])
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 4}: {exc}") from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:3], "starting address", self.address, "0-based coil address"),
                Field(3, raw[3:5], "quantity of outputs", len(self.values), "number of coils (1-1968)"),
                Field(5, raw[5:6], "byte count", raw[5], "ceil(quantity / 8)")]
        for index in range(raw[5]):
            chunk = self.values[index * 8:index * 8 + 8]
            shown = "".join("1" if bit else "0" for bit in reversed(chunk))
            name = f"coils {index * 8}-{index * 8 + len(chunk) - 1}"
            rows.append(Field(6 + index, raw[6 + index:7 + index], name, shown,
                              "first coil in the least significant position (rightmost)"))
        return rows

    def _summary_items(self):
        return [("address", self.address), ("values", "".join("1" if v else "0" for v in self.values))]


@dataclass(frozen=True, slots=True)
class _WriteMultipleResponse(Pdu):
    address: int
    count: int

    role: ClassVar[str] = "response"
    limit: ClassVar[int]
    what: ClassVar[str]

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        object.__setattr__(self, "count", _check_quantity(self.count, self.limit, self.what))
        _check_span(self.address, self.count, self.what[:-1])

    def encode(self) -> bytes:
        return struct.pack(">BHH", self.function_code, self.address, self.count)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 5, f"{function_title(cls.function_code)} response", offset)
        _fc, address, count = struct.unpack(">BHH", data)
        try:
            return cls(address, count)
        except QuantityError as exc:
            raise QuantityError(f"at bytes {offset + 3}-{offset + 4}: {exc}") from None
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 4}: {exc}") from None

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "starting address", self.address, f"0-based {self.what[:-1]} address"),
                Field(3, raw[3:5], "quantity", self.count, f"number of {self.what} written")]

    def _summary_items(self):
        return [("address", self.address), ("count", self.count)]


@dataclass(frozen=True, slots=True)
class WriteMultipleCoilsResponse(_WriteMultipleResponse):
    """Write Multiple Coils (FC 15) response::

        offset  size  field
        0       1     function code 0x0F
        1       2     starting address
        3       2     quantity of outputs written (1-1968)
    """

    function_code: ClassVar[int] = 0x0F
    limit: ClassVar[int] = MAX_WRITE_COILS
    what: ClassVar[str] = "coils"


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
    role: ClassVar[str] = "request"

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
class ExceptionResponse(Pdu):
    """Exception response: the server could not carry out the request::

        offset  size  field
        0       1     function code of the request + 0x80 (its most significant bit set)
        1       1     exception code (01 illegal function, 02 illegal data address,
                      03 illegal data value, 04 server device failure, ...)

    ``function`` is the request's function code (1-127); ``function_code`` is the byte on the wire.
    Example: ``83 02`` answers a Read Holding Registers request whose addresses do not exist.
    """

    function: int
    code: int

    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        function = _check_int(self.function, "function")
        if function & 0x80 and 0x81 <= function <= 0xFF:
            function &= 0x7F
        if not 1 <= function <= 0x7F:
            raise ValueRangeError(f"exception response for function {function}: expected a code 1 to 127")
        code = _check_int(self.code, "exception code")
        if not 1 <= code <= 0xFF:
            raise ValueRangeError(f"exception code {code} is outside 1..255")
        object.__setattr__(self, "function", function)
        object.__setattr__(self, "code", code)

    @property
    def function_code(self) -> int:  # type: ignore[override]
        return self.function | 0x80

    @property
    def title(self) -> str:
        return f"Exception ({function_title(self.function)})"

    @property
    def meaning(self) -> str:
        return exception_meaning(self.code)

    def encode(self) -> bytes:
        return bytes((self.function | 0x80, self.code))

    @classmethod
    def decode(cls, data: bytes, offset: int = 0):
        data = _pdu_bytes(data, offset)
        _expect_length(data, 2, "exception response", offset)
        if not data[0] & 0x80:
            raise UnknownFunctionError(
                f"at byte {offset}: 0x{data[0]:02X} is not an exception function code (expected 0x81-0xFF)",
                function=data[0])
        if data[0] == 0x80:
            raise UnknownFunctionError(
                f"at byte {offset}: function code 0x80 would be an exception response to function 0, "
                f"which does not exist (expected 0x81-0xFF)", function=0x80)
        if data[1] == 0:
            raise ValueRangeError(f"at byte {offset + 1}: exception code 0x00, expected 0x01-0xFF")
        return cls(data[0] & 0x7F, data[1])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [Field(0, raw[:1], "function code", raw[0],
                      f"0x{self.function:02X} + 0x80: exception response to {function_title(self.function)}"),
                Field(1, raw[1:2], "exception code", self.code, self.meaning)]

    def summary(self) -> str:
        return f"Exception response to {function_title(self.function)}: code {self.code:02X}, {self.meaning}"


# --- beyond the eight: FC 7, 17, 22, 23 -----------------------------------------------------------------

class _NoDataRequest(Pdu):
    """A request that is its function code alone (FC 7, FC 17)."""

    __slots__ = ()
    role: ClassVar[str] = "request"
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


@dataclass(frozen=True, slots=True)
class ReportServerIdResponse(Pdu):
    """Report Server ID (FC 17, 0x11) response: what the device says it is, and whether it runs::

        offset  size  field
        0       1     function code 0x11
        1       1     byte count N + 1
        2       N     server ID (device specific bytes)
        2+N     1     run indicator status: 0xFF ON, 0x00 OFF
    """

    server_id: bytes
    run_indicator: bool = True

    function_code: ClassVar[int] = 0x11
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        if not isinstance(self.server_id, (bytes, bytearray)):
            raise ValueRangeError(f"server_id must be bytes, got {shown(self.server_id)}")
        if len(self.server_id) > 250:
            raise ValueRangeError(f"server_id has {len(self.server_id)} bytes: at most 250 fit a response")
        if not isinstance(self.run_indicator, bool):
            raise ValueRangeError(f"run_indicator must be True or False, got {shown(self.run_indicator)}")
        object.__setattr__(self, "server_id", bytes(self.server_id))

    def encode(self) -> bytes:
        run = b"\xff" if self.run_indicator else b"\x00"
        return bytes([0x11, len(self.server_id) + 1]) + self.server_id + run

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Report Server ID response"
        _expect_minimum(data, 3, name, offset)
        _expect_byte_count(data, 2, data[1], name, offset)
        run = data[-1]
        if run not in (0x00, 0xFF):
            raise ValueRangeError(f"at byte {offset + len(data) - 1}: run indicator 0x{run:02X}, expected "
                                  "0xFF (ON) or 0x00 (OFF)")
        return cls(bytes(data[2:-1]), run == 0xFF)

    def fields(self) -> list[Field]:
        raw = self.encode()
        end = 2 + len(self.server_id)
        text = self.server_id.decode("ascii", "replace")
        return [self._function_field(raw),
                Field(1, raw[1:2], "byte count", raw[1], "server ID + run indicator"),
                Field(2, raw[2:end], "server ID", _hex(self.server_id), f"as text: {text!r}"),
                Field(end, raw[end:], "run indicator", self.run_indicator,
                      "0xFF: ON, the device runs" if self.run_indicator else "0x00: OFF")]

    def _summary_items(self):
        return [("server_id", self.server_id), ("run_indicator", self.run_indicator)]


@dataclass(frozen=True, slots=True)
class _MaskWriteRegister(Pdu):
    address: int
    and_mask: int
    or_mask: int

    function_code: ClassVar[int] = 0x16

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
    role: ClassVar[str] = "request"

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


MEI_READ_DEVICE_ID = 0x0E
"""FC 43's MEI type for Read Device Identification (the only MEI type this library speaks)."""

DEVICE_ID_OBJECTS = {0x00: "VendorName", 0x01: "ProductCode", 0x02: "MajorMinorRevision",
                     0x03: "VendorUrl", 0x04: "ProductName", 0x05: "ModelName", 0x06: "UserApplicationName"}
"""The specification's standard objects: 0-2 basic (mandatory), 3-6 regular; 0x80-0xFF are extended."""

READ_DEVICE_ID_CODES = {1: "basic (stream)", 2: "regular (stream)", 3: "extended (stream)", 4: "one object"}


@dataclass(frozen=True, slots=True)
class ReadDeviceIdentificationRequest(Pdu):
    """Read Device Identification (FC 43, 0x2B, MEI type 0x0E) request::

        offset  size  field
        0       1     function code 0x2B
        1       1     MEI type 0x0E
        2       1     read device ID code: 1 basic, 2 regular, 3 extended (stream access), 4 one object
        3       1     object id: where the stream starts, or the one object wanted
    """

    read_code: int = 1
    object_id: int = 0

    function_code: ClassVar[int] = 0x2B
    role: ClassVar[str] = "request"

    def __post_init__(self) -> None:
        if _check_int(self.read_code, "read_code") not in READ_DEVICE_ID_CODES:
            raise ValueRangeError(f"read device ID code {self.read_code}: expected 1 (basic), 2 (regular), "
                                  "3 (extended) or 4 (one object)")
        if not 0 <= _check_int(self.object_id, "object_id") <= 0xFF:
            raise ValueRangeError(f"object id {self.object_id} does not fit its one byte: expected 0..255")

    def encode(self) -> bytes:
        return bytes([0x2B, MEI_READ_DEVICE_ID, self.read_code, self.object_id])

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        _expect_length(data, 4, "Read Device Identification request", offset)
        if data[1] != MEI_READ_DEVICE_ID:
            raise UnknownFunctionError(f"at byte {offset + 1}: MEI type 0x{data[1]:02X}; this library reads "
                                       "device identification only (MEI type 0x0E)", function=0x2B)
        if data[2] not in READ_DEVICE_ID_CODES:
            raise ValueRangeError(f"at byte {offset + 2}: read device ID code {data[2]}, expected 1 to 4")
        return cls(data[2], data[3])

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:2], "MEI type", 0x0E, "Read Device Identification"),
                Field(2, raw[2:3], "read device ID code", self.read_code,
                      READ_DEVICE_ID_CODES[self.read_code]),
                Field(3, raw[3:4], "object id", self.object_id,
                      DEVICE_ID_OBJECTS.get(self.object_id, "extended object" if self.object_id >= 0x80
                                            else "reserved object id"))]

    def _summary_items(self):
        return [("read_code", self.read_code), ("object_id", self.object_id)]


@dataclass(frozen=True, slots=True)
class ReadDeviceIdentificationResponse(Pdu):
    """Read Device Identification (FC 43, 0x2B, MEI type 0x0E) response::

        offset  size  field
        0       1     function code 0x2B
        1       1     MEI type 0x0E
        2       1     read device ID code (as in the request)
        3       1     conformity level (0x01-0x03, +0x80 if objects can be read one by one)
        4       1     more follows: 0xFF if the objects go on in another response, else 0x00
        5       1     next object id (where the next request starts when more follows)
        6       1     number of objects N
        7...          N objects, each: object id (1), length L (1), value (L bytes)
    """

    read_code: int
    conformity: int
    more_follows: bool
    next_object_id: int
    objects: tuple[tuple[int, bytes], ...]

    function_code: ClassVar[int] = 0x2B
    role: ClassVar[str] = "response"

    def __post_init__(self) -> None:
        objects = []
        for item in self.objects:
            object_id, value = item
            value = value.encode() if isinstance(value, str) else value
            object_id = _check_int(object_id, "object id")
            if not isinstance(value, (bytes, bytearray)) or not 0 <= object_id <= 0xFF:
                raise ValueRangeError(f"an object is (id 0..255, bytes or text), got {shown(item)}")
            objects.append((object_id, bytes(value)))
        object.__setattr__(self, "objects", tuple(objects))
        if 7 + sum(2 + len(value) for _, value in objects) > MAX_PDU_SIZE:
            raise ValueRangeError("the objects do not fit one response (253 bytes): split them with "
                                  "more_follows")
        for name in ("read_code", "conformity", "next_object_id"):
            if not 0 <= _check_int(getattr(self, name), name) <= 0xFF:
                raise ValueRangeError(f"{name} does not fit its one byte: expected 0..255")

    def encode(self) -> bytes:
        head = bytes([0x2B, MEI_READ_DEVICE_ID, self.read_code, self.conformity,
                      0xFF if self.more_follows else 0x00, self.next_object_id, len(self.objects)])
        return head + b"".join(bytes([object_id, len(value)]) + value for object_id, value in self.objects)

    @classmethod
    def _decode(cls, data: bytes, offset: int = 0):
        name = "Read Device Identification response"
        _expect_minimum(data, 7, name, offset)
        if data[1] != MEI_READ_DEVICE_ID:
            raise UnknownFunctionError(f"at byte {offset + 1}: MEI type 0x{data[1]:02X}, expected 0x0E",
                                       function=0x2B)
        if data[4] not in (0x00, 0xFF):
            raise ValueRangeError(f"at byte {offset + 4}: more follows is 0x{data[4]:02X}, expected 0x00 or "
                                  "0xFF")
        objects, at, size = [], 7, len(data)
        for _ in range(data[6]):
            end = at + 2 + data[at + 1] if at + 2 <= size else size + 1
            if end > size:
                raise TruncatedError(f"{name} is truncated: object {len(objects) + 1} of {data[6]} runs past "
                                     f"its {size} bytes (from byte {offset + at})")
            objects.append((data[at], data[at + 2:end]))
            at = end
        if at != size:
            raise TrailingBytesError(f"{name} has {size - at} trailing byte(s) from byte {offset + at}")
        # every field was checked above: build without checking again
        return cls._from_wire(data[2], data[3], data[4] == 0xFF, data[5], tuple(objects))

    def fields(self) -> list[Field]:
        raw = self.encode()
        rows = [self._function_field(raw),
                Field(1, raw[1:2], "MEI type", 0x0E, "Read Device Identification"),
                Field(2, raw[2:3], "read device ID code", self.read_code,
                      READ_DEVICE_ID_CODES.get(self.read_code, "unknown")),
                Field(3, raw[3:4], "conformity level", self.conformity, f"0x{self.conformity:02X}"),
                Field(4, raw[4:5], "more follows", self.more_follows,
                      "0xFF: ask again from the next object id" if self.more_follows
                      else "0x00: the last part"),
                Field(5, raw[5:6], "next object id", self.next_object_id, "where the next request starts"),
                Field(6, raw[6:7], "number of objects", len(self.objects), "")]
        at = 7
        for object_id, value in self.objects:
            label = DEVICE_ID_OBJECTS.get(object_id, f"object 0x{object_id:02X}")
            rows.append(Field(at, raw[at:at + 2 + len(value)], label, value.decode("ascii", "replace"),
                              f"object id {object_id}, {len(value)} bytes"))
            at += 2 + len(value)
        return rows

    def _summary_items(self):
        objects = {object_id: value.decode("ascii", "replace") for object_id, value in self.objects}
        return [("objects", objects),
                ("more_follows", self.more_follows)]


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


@dataclass(frozen=True, slots=True)
class _Diagnostics(Pdu):
    sub_function: int
    data: bytes = b"\x00\x00"

    function_code: ClassVar[int] = 0x08

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


MAX_RECORD_NUMBER = 9999
"""File records are numbered 0 to 9999 (0x270F) within a file; files are numbered 1 to 65535."""


def _check_file_reference(file: Any, record: Any) -> None:
    if not 1 <= _check_int(file, "file number") <= 0xFFFF:
        raise AddressRangeError(f"file number {file}: expected 1 to 65535")
    if not 0 <= _check_int(record, "record number") <= MAX_RECORD_NUMBER:
        raise AddressRangeError(f"record number {record}: expected 0 to 9999 (0x270F)")


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


@dataclass(frozen=True, slots=True)
class WriteFileRecordResponse(_WriteFileRecord):
    """Write File Record (FC 21, 0x15) response: an echo of the request (same layout)."""

    role: ClassVar[str] = "response"


REQUEST_CLASSES: dict[int, type[Pdu]] = {cls.function_code: cls for cls in (
    ReadCoilsRequest, ReadDiscreteInputsRequest, ReadHoldingRegistersRequest, ReadInputRegistersRequest,
    WriteSingleCoilRequest, WriteSingleRegisterRequest, WriteMultipleCoilsRequest,
    WriteMultipleRegistersRequest, ReadExceptionStatusRequest, ReportServerIdRequest,
    MaskWriteRegisterRequest, ReadWriteMultipleRegistersRequest, ReadFifoQueueRequest,
    ReadDeviceIdentificationRequest, DiagnosticsRequest, GetCommEventCounterRequest, GetCommEventLogRequest,
    ReadFileRecordRequest, WriteFileRecordRequest)}
RESPONSE_CLASSES: dict[int, type[Pdu]] = {cls.function_code: cls for cls in (
    ReadCoilsResponse, ReadDiscreteInputsResponse, ReadHoldingRegistersResponse, ReadInputRegistersResponse,
    WriteSingleCoilResponse, WriteSingleRegisterResponse, WriteMultipleCoilsResponse,
    WriteMultipleRegistersResponse, ReadExceptionStatusResponse, ReportServerIdResponse,
    MaskWriteRegisterResponse, ReadWriteMultipleRegistersResponse, ReadFifoQueueResponse,
    ReadDeviceIdentificationResponse, DiagnosticsResponse, GetCommEventCounterResponse,
    GetCommEventLogResponse, ReadFileRecordResponse, WriteFileRecordResponse)}

def _check_role(role: object) -> str:
    """The role, checked: ``"request"`` or ``"response"``."""
    if role not in ROLES:
        raise ConfigError(f"role must be 'request' or 'response', got {role!r}")
    return role  # type: ignore[return-value]


def _unknown(function: int, offset: int, role: str) -> UnknownFunctionError:
    known = ", ".join(str(int(code)) for code in FunctionCode)
    hint = ""
    if function >= 0x80:
        hint = " (codes 128-255 are exception responses, never requests)" if role == "request" else ""
    elif function == 0:
        hint = " (0 is not a valid function code)"
    return UnknownFunctionError(
        f"at byte {offset}: function code 0x{function:02X} ({function}) is not supported; "
        f"this library implements {known}{hint}", function=function)


def request_class(function: int) -> type[Pdu]:
    """The request class of a function code; UnknownFunctionError for codes not implemented."""
    try:
        return REQUEST_CLASSES[function]
    except (KeyError, TypeError):
        raise _unknown(int(function) if isinstance(function, int) else -1, 0, "request") from None


def response_class(function: int) -> type[Pdu]:
    """The (normal) response class of a function code."""
    try:
        return RESPONSE_CLASSES[function]
    except (KeyError, TypeError):
        raise _unknown(int(function) if isinstance(function, int) else -1, 0, "response") from None


def decode_pdu(data: bytes, role: str, offset: int = 0) -> Pdu:
    """Decode PDU bytes (function code first) as a request or a response.

    In a response, a function code with its top bit set is an :class:`ExceptionResponse`.  ``offset`` is
    added to the byte positions in error messages (the PDU's place in the frame).
    """
    _check_role(role)
    data = _pdu_bytes(data, offset)
    function = data[0]
    if role == "response" and function & 0x80:
        return ExceptionResponse.decode(data, offset)
    table = REQUEST_CLASSES if role == "request" else RESPONSE_CLASSES
    cls = table.get(function)
    if cls is None:
        raise _unknown(function, offset, role)
    return cls._decode(data, offset)


def pdu_length(data: bytes, role: str) -> int | None:
    """The total length of the PDU that starts ``data``, or None if more bytes are needed to know.

    Requests of functions 1-6 are 5 bytes; FC 15 and 16 requests are 6 + byte count, FC 23 10 + byte
    count, FC 22 seven bytes, FC 7 and 17 one.  Responses of functions 1-4, 17 and 23 are 2 + byte
    count; of 5, 6, 15, 16 five bytes; FC 22 seven, FC 7 two; exception responses two.  This is how
    a receiver finds the end of an RTU frame without relying on silence on the line.
    """
    _check_role(role)
    if isinstance(data, (bytes, bytearray, memoryview)) and not len(data):
        return None
    data = _pdu_bytes(data, 0)
    function = data[0]
    if role == "response":
        if function & 0x80:
            return 2
        if function in (1, 2, 3, 4, 0x11, 0x17):
            return 2 + data[1] if len(data) >= 2 else None
        if function in (5, 6, 15, 16):
            return 5
        if function == 0x07:
            return 2
        if function == 0x16:
            return 7
        if function == 0x18:
            return 3 + int.from_bytes(data[1:3], "big") if len(data) >= 3 else None
        if function == 0x2B:
            return _device_id_length(data)
        if function == 0x08:
            return 5
        if function == 0x0B:
            return 5
        if function in (0x0C, 0x14, 0x15):
            return 2 + data[1] if len(data) >= 2 else None
    else:
        if function in (1, 2, 3, 4, 5, 6):
            return 5
        if function in (15, 16):
            return 6 + data[5] if len(data) >= 6 else None
        if function in (0x07, 0x11):
            return 1
        if function == 0x16:
            return 7
        if function == 0x17:
            return 10 + data[9] if len(data) >= 10 else None
        if function == 0x18:
            return 3
        if function == 0x2B:
            return 4
        if function == 0x08:
            return 5  # one data word: what nearly every diagnostics request carries
        if function in (0x0B, 0x0C):
            return 1
        if function in (0x14, 0x15):
            return 2 + data[1] if len(data) >= 2 else None
    raise _unknown(function, 0, role)


def _device_id_length(data: bytes) -> int | None:
    """The length of a Read Device Identification response: its objects say (None: need more bytes)."""
    if len(data) < 7:
        return None
    at = 7
    for _ in range(data[6]):
        if at + 2 > len(data):  # the next object's header has not come yet (or cannot, past a PDU)
            return None if len(data) < MAX_PDU_SIZE else MAX_PDU_SIZE + 1
        at += 2 + data[at + 1]
        if at > MAX_PDU_SIZE:
            return at  # longer than a PDU: the caller refuses it
    return at
