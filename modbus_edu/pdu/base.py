"""The shared machinery of every PDU: the :class:`Pdu` base class, the field checks, the registry of
classes by function code, :func:`decode_pdu` and :func:`pdu_length`."""

from __future__ import annotations

import dataclasses
import functools
import struct
from collections.abc import Iterable, Mapping
from collections.abc import Set as AbstractSet
from dataclasses import dataclass
from typing import Any, ClassVar

from ..codes import (
    ROLES,
    SERIAL_LINE_ONLY,
    FunctionCode,
    function_title,
)
from ..errors import (
    AddressRangeError,
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


#: What :meth:`Pdu.length_from` returns when a PDU's bytes do not say its length (FC 8 Return Query Data
#: echoes data of any length): a receiver then ends the frame by its checksum or by silence.
OPEN_LENGTH = 0


@dataclass(frozen=True)
class Field:
    """One field of a PDU, for dissection tables: where it is, its bytes, its name, value and meaning."""

    offset: int
    raw: bytes
    name: str
    value: Any
    meaning: str


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
                              f"got {type(values).__name__} {shown(values)}")


def _check_bits(values: Any, name: str) -> tuple[bool, ...]:
    _check_sequence(values, name, "booleans")
    try:
        items = tuple(values)
    except TypeError:
        raise ValueRangeError(f"{name} must be a sequence of booleans, got {shown(values)}") from None
    for index, item in enumerate(items):
        if item not in (0, 1) or not isinstance(item, (bool, int)):
            raise ValueRangeError(f"{name}[{index}] is {shown(item)}, expected True/False (or 1/0)")
    return tuple(bool(item) for item in items)


def _check_registers(values: Any, name: str) -> tuple[int, ...]:
    if type(values) not in (list, tuple):
        _check_sequence(values, name, "integers")
    try:
        items = tuple(values)
    except TypeError:
        raise ValueRangeError(f"{name} must be a sequence of integers, got {shown(values)}") from None
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
        raise PduError(f"a PDU is bytes, got the number {shown(data)}: write bytes([{data}]) for one byte")
    try:
        data = bytes(data)
    except (TypeError, ValueError):
        raise PduError(f"a PDU is bytes (values 0..255), got {type(data).__name__}") from None
    if not data:
        raise TruncatedError(f"empty PDU at byte {offset}: expected at least a function code")
    return data


REQUEST_CLASSES: dict[int, type[Pdu]] = {}
"""The request class of each function code; every class with a ``function_code`` registers itself."""
RESPONSE_CLASSES: dict[int, type[Pdu]] = {}
"""The (normal) response class of each function code."""
_EXCEPTION_RESPONSE: list[type[Pdu]] = []
"""The exception response class (one), registered by :mod:`modbus_edu.pdu.exceptions`."""


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
    is_exception: ClassVar[bool] = False
    fixed_size: ClassVar[int | None] = None
    """The PDU's length when its function fixes it (a read request: 5 bytes); None when a byte count says."""
    byte_count_at: ClassVar[int | None] = None
    """Where the byte count sits (a read response: byte 1); the PDU ends ``byte_count_at + 1 + count``."""
    __slots__ = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """A class that names its own ``function_code`` (an int) is the class of that code in its role."""
        super().__init_subclass__(**kwargs)
        if cls.__dict__.get("is_exception"):
            _EXCEPTION_RESPONSE[:] = [cls]
            return
        code = getattr(cls, "function_code", None)  # a private base class shares its code: not registered
        if isinstance(code, int) and not cls.__name__.startswith("_"):
            (REQUEST_CLASSES if cls.role == "request" else RESPONSE_CLASSES)[code] = cls

    @classmethod
    def length_from(cls, data: bytes) -> int | None:
        """This PDU's total length, read from its first bytes (function code first); None: more needed;
        :data:`OPEN_LENGTH`: the bytes do not say (only the frame's end does: a CRC, a silence).

        Every class has its rule: a fixed size, or a byte count plus what precedes it.  The splitters
        and :func:`pdu_length` ask it, so a receiver finds the end of a frame without silence on the line.
        """
        if cls.fixed_size is not None:
            return cls.fixed_size
        at = cls.byte_count_at
        if at is None:  # pragma: no cover - every class with a function code says one or the other
            raise NotImplementedError(f"{cls.__name__} has no length rule")
        return at + 1 + data[at] if len(data) > at else None

    @classmethod
    def length_prefix(cls) -> int:
        """How many first bytes :meth:`length_from` reads at most."""
        return 1 if cls.fixed_size is not None else (cls.byte_count_at or 0) + 1

    @classmethod
    def plausible(cls, data: bytes) -> bool:
        """A quick test of the first bytes (function code first) before a checksum is computed: whether
        the byte count fits the function.  True unless a class knows better."""
        return True

    @classmethod
    def answer_from_bytes(cls, pdu: bytes, bank: Any) -> bytes | None:
        """A server's fast path: the bytes of the normal response to the request ``pdu`` (function code
        first), carried out on ``bank`` (a plain :class:`~modbus_edu.datamodel.DataBank`) without
        building a PDU object, or None when this request is not one the fast path takes.

        None by default.  A class that has one (the reads, FC 1-4) takes only a well-formed request its
        bank can answer, and has no side effect before it returns None: anything else (a bad length, a
        quantity out of range, an address not in a sparse bank) goes the general way, :meth:`decode`
        and the slave's handler, which answer it with their teaching errors and exception codes.  The
        slave asks it only when nothing else would act on the request (no hooks, no subclass, a plain
        bank), and ``tests/test_fast_path.py`` holds both ways to the same bytes, counters and log.
        """
        return None

    @classmethod
    def reply_note(cls, request: bytes, reply: bytes) -> str:
        """The traffic log's note for ``reply``, which :meth:`answer_from_bytes` gave to ``request``: the
        ``summary()`` of the response object the general way would have built.  The log writes it when it
        is read, not per request."""
        return RESPONSE_CLASSES[cls.function_code]._decode(reply, 0).summary()

    def misfit(self, response: Pdu) -> str:
        """How ``response``, of this request's function, fails to fit this request ('' if it fits):
        the wrong number of values for a read, an echo that differs for a write."""
        return ""

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

    def summary(self) -> str:
        """One line such as ``Read Holding Registers request: address 0, count 1``."""
        parts = [f"{name} {value}" for name, value in self._summary_items()]
        return f"{self.title} {self.role}" + (": " + ", ".join(parts) if parts else "")

    def _summary_items(self) -> list[tuple[str, Any]]:  # pragma: no cover
        return []


@dataclass(frozen=True, slots=True)
class _AddressQuantity(Pdu):
    """A starting address and a quantity, five bytes: a read request (FC 1-4), or the response to a
    write of several coils or registers (FC 15, 16)."""

    address: int
    count: int

    fixed_size: ClassVar[int | None] = 5
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
        _expect_length(data, 5, f"{function_title(cls.function_code)} {cls.role}", offset)
        _fc, address, count = struct.unpack(">BHH", data)
        try:
            return cls(address, count)
        except QuantityError as exc:
            raise QuantityError(f"at bytes {offset + 3}-{offset + 4}: {exc}") from None
        except AddressRangeError as exc:
            raise AddressRangeError(f"at bytes {offset + 1}-{offset + 4}: {exc}") from None

    def _summary_items(self):
        return [("address", self.address), ("count", self.count)]


_ADDRESS_COUNT = struct.Struct(">HH")
"""A read request's starting address and quantity, after its function code."""


@dataclass(frozen=True, slots=True)
class _ReadRequest(_AddressQuantity):
    role: ClassVar[str] = "request"
    table: ClassVar[str]
    """The name of the :class:`~modbus_edu.datamodel.DataBank` table this function reads."""

    @classmethod
    def answer_from_bytes(cls, pdu: bytes, bank: Any) -> bytes | None:
        """A read of ``count`` values from ``address``: the same checks as :meth:`decode` (exactly five
        bytes, a quantity of 1 to the limit, no address past 65535), then the bank's table read and the
        response packed from the values as the table keeps them (:meth:`_pack_reply`)."""
        if len(pdu) != 5:
            return None
        address, count = _ADDRESS_COUNT.unpack_from(pdu, 1)
        if not 1 <= count <= cls.limit or address + count > 0x10000:
            return None
        table = getattr(bank, cls.table)
        if table.sparse and not table.is_declared(address, count):
            return None  # exception 02 and its message: the general way
        return cls._pack_reply(table.stored(address, count))

    @classmethod
    def _pack_reply(cls, values: Any) -> bytes:  # pragma: no cover - each read class packs its own
        raise NotImplementedError

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [
            self._function_field(raw),
            Field(1, raw[1:3], "starting address", self.address,
                  f"0-based {self.what[:-1]} address"),
            Field(3, raw[3:5], "quantity", self.count, f"number of {self.what} to read (1-{self.limit})"),
        ]


def _label(name: str | type[Pdu]) -> str:
    """A PDU's name for a message: the string itself, or "<Function Title> <role>" of a class."""
    return name if isinstance(name, str) else f"{function_title(name.function_code)} {name.role}"


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
class _WriteMultipleResponse(_AddressQuantity):
    role: ClassVar[str] = "response"

    def fields(self) -> list[Field]:
        raw = self.encode()
        return [self._function_field(raw),
                Field(1, raw[1:3], "starting address", self.address, f"0-based {self.what[:-1]} address"),
                Field(3, raw[3:5], "quantity", self.count, f"number of {self.what} written")]


def _check_role(role: object) -> str:
    """The role, checked: ``"request"`` or ``"response"``."""
    if role not in ROLES:
        raise ConfigError(f"role must be 'request' or 'response', got {shown(role)}")
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


def pdu_class(function: int, role: str, offset: int = 0) -> type[Pdu]:
    """The class of a PDU of ``role`` that starts with the byte ``function``.

    In a response, a code with its top bit set is an :class:`ExceptionResponse`; a code no class claims
    is an :class:`~modbus_edu.errors.UnknownFunctionError` (``offset`` places it in the frame).
    """
    if role == "response" and function & 0x80:
        return _EXCEPTION_RESPONSE[0]
    cls = (REQUEST_CLASSES if role == "request" else RESPONSE_CLASSES).get(function)
    if cls is None:
        raise _unknown(function, offset, role)
    return cls


def decode_pdu(data: bytes, role: str, offset: int = 0) -> Pdu:
    """Decode PDU bytes (function code first) as a request or a response.

    In a response, a function code with its top bit set is an :class:`ExceptionResponse`.  ``offset`` is
    added to the byte positions in error messages (the PDU's place in the frame).
    """
    _check_role(role)
    data = _pdu_bytes(data, offset)
    cls = pdu_class(data[0], role, offset)
    return cls.decode(data, offset) if cls.is_exception else cls._decode(data, offset)


def pdu_length(data: bytes, role: str) -> int | None:
    """The total length of the PDU that starts ``data``, or None if more bytes are needed to know.

    The class of the function code says (:meth:`Pdu.length_from`): a fixed size (a read request is 5
    bytes, an exception response 2), or a byte count plus what precedes it (a read response is 2 + byte
    count, an FC 15 or 16 request 6 + byte count).  This is how a receiver finds the end of an RTU frame
    without relying on silence on the line.
    """
    _check_role(role)
    if isinstance(data, (bytes, bytearray, memoryview)) and not len(data):
        return None
    data = _pdu_bytes(data, 0)
    size = pdu_class(data[0], role).length_from(data)
    return None if size == OPEN_LENGTH else size


def _count_echo_misfit(request: Any, response: Any) -> str:
    """FC 15 and 16: the response echoes the starting address and the quantity written."""
    if (response.address, response.count) != (request.address, len(request.values)):
        return (f"the echo says address {response.address} count {response.count}, the request was "
                f"address {request.address} count {len(request.values)}")
    return ""


def _value_echo_misfit(request: Any, response: Any) -> str:
    """FC 5 and 6: the response echoes the request's address and value."""
    if (response.address, response.value) != (request.address, request.value):
        return (f"the echo says address {response.address} value {response.value!r}, the request "
                f"was address {request.address} value {request.value!r}")
    return ""
