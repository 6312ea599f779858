"""Bit access (specification sections 6.1, 6.2, 6.5, 6.11): Read Coils (FC 1), Read Discrete Inputs (FC 2),
Write Single Coil (FC 5) and Write Multiple Coils (FC 15)."""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import ClassVar

from ..errors import (
    AddressRangeError,
    ByteCountError,
    QuantityError,
    ValueRangeError,
    shown,
)
from .base import (
    MAX_READ_BITS,
    MAX_WRITE_COILS,
    RESPONSE_CLASSES,
    Field,
    Pdu,
    _check_address,
    _check_bits,
    _check_quantity,
    _check_span,
    _count_echo_misfit,
    _expect_byte_count,
    _expect_length,
    _expect_minimum,
    _ReadRequest,
    _value_echo_misfit,
    _WriteMultipleResponse,
    pack_bits,
    unpack_bits,
)

COIL_ON = 0xFF00


COIL_OFF = 0x0000


@dataclass(frozen=True, slots=True)
class _ReadBitsRequest(_ReadRequest):
    @classmethod
    def _pack_reply(cls, values: bytearray) -> bytes:
        """Function code, byte count and the bits (0/1 bytes), eight to a byte."""
        packed = pack_bits(values)
        return bytes((cls.function_code, len(packed))) + packed

    @classmethod
    def reply_note(cls, request: bytes, reply: bytes) -> str:
        """The response object the general way builds holds the bits asked for, not the padding."""
        count = int.from_bytes(request[3:5], "big")
        return RESPONSE_CLASSES[cls.function_code](bits=unpack_bits(reply[2:])[:count]).summary()

    def misfit(self, response: Pdu) -> str:
        """A read-bits response carries ceil(count / 8) data bytes."""
        needed = (self.count + 7) // 8
        if len(response.bits) != 8 * needed:
            return f"{len(response.bits) // 8} data bytes for {self.count} bits, expected {needed}"
        return ""


@dataclass(frozen=True, slots=True)
class _ReadBitsResponse(Pdu):
    bits: tuple[bool, ...]

    role: ClassVar[str] = "response"
    byte_count_at: ClassVar[int | None] = 1

    @classmethod
    def plausible(cls, data: bytes) -> bool:
        return 1 <= data[1] <= 250

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
class ReadCoilsRequest(_ReadBitsRequest):
    """Read Coils (FC 01) request: read 1 to 2000 contiguous coils::

        offset  size  field
        0       1     function code 0x01
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of coils (1-2000)
    """

    function_code: ClassVar[int] = 0x01
    limit: ClassVar[int] = MAX_READ_BITS
    what: ClassVar[str] = "coils"
    table: ClassVar[str] = "coils"


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
class ReadDiscreteInputsRequest(_ReadBitsRequest):
    """Read Discrete Inputs (FC 02) request::

        offset  size  field
        0       1     function code 0x02
        1       2     starting address (0x0000-0xFFFF)
        3       2     quantity of inputs (1-2000)
    """

    function_code: ClassVar[int] = 0x02
    limit: ClassVar[int] = MAX_READ_BITS
    what: ClassVar[str] = "discrete inputs"
    table: ClassVar[str] = "discrete_inputs"


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
class _WriteSingleCoil(Pdu):
    address: int
    value: bool

    function_code: ClassVar[int] = 0x05
    fixed_size: ClassVar[int | None] = 5

    def __post_init__(self) -> None:
        object.__setattr__(self, "address", _check_address(self.address))
        if self.value not in (0, 1) or not isinstance(self.value, (bool, int)):
            raise ValueRangeError(f"coil value {shown(self.value)} must be True (ON) or False (OFF)")
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

    def misfit(self, response: Pdu) -> str:
        return _value_echo_misfit(self, response)


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
    byte_count_at: ClassVar[int | None] = 5
    role: ClassVar[str] = "request"

    @classmethod
    def plausible(cls, data: bytes) -> bool:
        """The byte count is ceil(quantity / 8)."""
        return len(data) < 6 or data[5] == (int.from_bytes(data[3:5], "big") + 7) // 8

    def misfit(self, response: Pdu) -> str:
        return _count_echo_misfit(self, response)

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
