"""The PDU layer: every class round-trips, matches the specification's byte layouts, and every rule of
the specification, when broken, raises the right PduError with a message that says where and what."""

from __future__ import annotations

import dataclasses
import re
from contextlib import contextmanager

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modbus_edu.errors import (
    AddressRangeError,
    ByteCountError,
    ConfigError,
    ModbusError,
    PduError,
    QuantityError,
    TrailingBytesError,
    TruncatedError,
    UnknownFunctionError,
    ValueRangeError,
)
from modbus_edu.pdu import (
    MAX_PDU_SIZE,
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_WRITE_COILS,
    MAX_WRITE_REGISTERS,
    ExceptionCode,
    ExceptionResponse,
    Field,
    FunctionCode,
    Pdu,
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    ReadInputRegistersRequest,
    ReadInputRegistersResponse,
    WriteMultipleCoilsRequest,
    WriteMultipleCoilsResponse,
    WriteMultipleRegistersRequest,
    WriteMultipleRegistersResponse,
    WriteSingleCoilRequest,
    WriteSingleCoilResponse,
    WriteSingleRegisterRequest,
    WriteSingleRegisterResponse,
    decode_pdu,
    pdu_length,
    request_class,
    response_class,
)

SETTINGS = settings(max_examples=200, deadline=None)


def h(text: str) -> bytes:
    return bytes.fromhex(text.replace(" ", ""))


@contextmanager
def raises(exc_type: type[BaseException], *fragments: str):
    """pytest.raises that also checks that the message contains every fragment (case-insensitive)."""
    with pytest.raises(exc_type) as info:
        yield info
    message = str(info.value).lower()
    missing = [f for f in fragments if f.lower() not in message]
    assert not missing, f"message {str(info.value)!r} lacks {missing}"


# --- strategies ------------------------------------------------------------------------------------
def span(limit: int) -> st.SearchStrategy[tuple[int, int]]:
    """(address, count) with 1 <= count <= limit and address + count <= 65536."""
    return st.integers(1, limit).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), st.just(n)))


ADDRESS = st.integers(0, 0xFFFF)
REGISTER = st.integers(0, 0xFFFF)


def bits_of(data: bytes) -> list[bool]:
    """The bits of some bytes, least significant bit of the first byte first."""
    return [bool(byte >> bit & 1) for byte in data for bit in range(8)]


def bit_lists(n: int) -> st.SearchStrategy[list[bool]]:
    """Exactly n random bits (drawn as bytes: much faster than n booleans)."""
    return st.binary(min_size=(n + 7) // 8, max_size=(n + 7) // 8).map(lambda b: bits_of(b)[:n])


def bit_values(limit: int) -> st.SearchStrategy[tuple[int, list[bool]]]:
    return st.integers(1, limit).flatmap(lambda n: st.tuples(st.integers(0, 65536 - n), bit_lists(n)))


def register_values(limit: int) -> st.SearchStrategy[tuple[int, list[int]]]:
    return st.integers(1, limit).flatmap(
        lambda n: st.tuples(st.integers(0, 65536 - n), st.lists(REGISTER, min_size=n, max_size=n)))


READ_REQUESTS = [
    (ReadCoilsRequest, MAX_READ_BITS),
    (ReadDiscreteInputsRequest, MAX_READ_BITS),
    (ReadHoldingRegistersRequest, MAX_READ_REGISTERS),
    (ReadInputRegistersRequest, MAX_READ_REGISTERS),
]
BITS_RESPONSES = [ReadCoilsResponse, ReadDiscreteInputsResponse]
REGISTER_RESPONSES = [ReadHoldingRegistersResponse, ReadInputRegistersResponse]
WRITE_RESPONSES = [
    (WriteMultipleCoilsResponse, MAX_WRITE_COILS),
    (WriteMultipleRegistersResponse, MAX_WRITE_REGISTERS),
]
WRITE_REQUESTS = [WriteMultipleCoilsRequest, WriteMultipleRegistersRequest]

STRATEGIES: dict[type, st.SearchStrategy[Pdu]] = {}
for _cls, _limit in READ_REQUESTS:
    STRATEGIES[_cls] = span(_limit).map(lambda ac, c=_cls: c(address=ac[0], count=ac[1]))
for _cls in BITS_RESPONSES:
    STRATEGIES[_cls] = st.binary(min_size=1, max_size=250).map(lambda b, c=_cls: c(bits=bits_of(b)))
for _cls in REGISTER_RESPONSES:
    STRATEGIES[_cls] = st.lists(REGISTER, min_size=1, max_size=125).map(lambda r, c=_cls: c(registers=r))
for _cls in (WriteSingleCoilRequest, WriteSingleCoilResponse):
    STRATEGIES[_cls] = st.builds(_cls, address=ADDRESS, value=st.booleans())
for _cls in (WriteSingleRegisterRequest, WriteSingleRegisterResponse):
    STRATEGIES[_cls] = st.builds(_cls, address=ADDRESS, value=REGISTER)
STRATEGIES[WriteMultipleCoilsRequest] = bit_values(MAX_WRITE_COILS).map(
    lambda av: WriteMultipleCoilsRequest(address=av[0], values=av[1]))
STRATEGIES[WriteMultipleRegistersRequest] = register_values(MAX_WRITE_REGISTERS).map(
    lambda av: WriteMultipleRegistersRequest(address=av[0], values=av[1]))
for _cls, _limit in WRITE_RESPONSES:
    STRATEGIES[_cls] = span(_limit).map(lambda ac, c=_cls: c(address=ac[0], count=ac[1]))
STRATEGIES[ExceptionResponse] = st.builds(
    ExceptionResponse, function=st.integers(1, 127), code=st.integers(1, 255))

ALL_CLASSES = list(STRATEGIES)
REQUEST_CLASSES = [c for c in ALL_CLASSES if c.role == "request"]
RESPONSE_CLASSES = [c for c in ALL_CLASSES if c.role == "response"]


def test_every_class_is_covered() -> None:
    assert len(REQUEST_CLASSES) == 8
    assert len(RESPONSE_CLASSES) == 9  # eight normal responses and the exception response
    for cls in ALL_CLASSES:
        assert issubclass(cls, Pdu)


# --- round trips and structure (every class) ---------------------------------------------------------
def _prefix_lengths(n: int) -> list[int]:
    if n <= 24:
        return list(range(n))
    return sorted({0, 1, 2, 3, 4, 5, 6, 7, n // 2, n - 2, n - 1})


@pytest.mark.parametrize("cls", ALL_CLASSES, ids=lambda c: c.__name__)
@settings(max_examples=120, deadline=None)
@given(data=st.data())
def test_round_trip(cls, data) -> None:
    pdu = data.draw(STRATEGIES[cls])
    encoded = pdu.encode()
    assert isinstance(encoded, bytes)
    assert 2 <= len(encoded) <= MAX_PDU_SIZE
    assert encoded[0] == pdu.function_code
    # the class's own decode and decode_pdu in the class's role agree and give the object back
    assert cls.decode(encoded) == pdu
    again = decode_pdu(encoded, cls.role)
    assert again == pdu
    assert type(again) is cls
    assert again.encode() == encoded
    # memoryview and bytearray inputs work too
    assert decode_pdu(bytearray(encoded), cls.role) == pdu
    # the length can be known from the first bytes
    assert pdu_length(encoded, cls.role) == len(encoded)
    # every truncation is reported as such, by both entry points; pdu_length never lies about a prefix
    for n in _prefix_lengths(len(encoded)):
        prefix = encoded[:n]
        assert pdu_length(prefix, cls.role) in (None, len(encoded))
        with raises(TruncatedError, "truncated" if n else "function code"):
            decode_pdu(prefix, cls.role)
        if n:
            with raises(TruncatedError, "truncated"):
                cls.decode(prefix)
    # one more byte is a trailing byte, and the message says where it starts
    extra = data.draw(st.integers(0, 255))
    with raises(TrailingBytesError, "trailing", f"byte {len(encoded)}"):
        decode_pdu(encoded + bytes([extra]), cls.role)
    with raises(TrailingBytesError, "trailing"):
        cls.decode(encoded + bytes([extra]) * 3)


@pytest.mark.parametrize("cls", ALL_CLASSES, ids=lambda c: c.__name__)
@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_fields_cover_every_byte(cls, data) -> None:
    pdu = data.draw(STRATEGIES[cls])
    encoded = pdu.encode()
    fields = pdu.fields()
    assert all(isinstance(f, Field) for f in fields)
    assert fields[0].offset == 0
    assert fields[0].name == "function code"
    assert b"".join(f.raw for f in fields) == encoded
    position = 0
    for f in fields:
        assert f.offset == position
        assert f.raw == encoded[f.offset:f.offset + len(f.raw)]
        assert f.name and isinstance(f.meaning, str)
        position += len(f.raw)


@pytest.mark.parametrize("cls", ALL_CLASSES, ids=lambda c: c.__name__)
def test_role_and_function_code_are_class_attributes(cls) -> None:
    assert cls.role in ("request", "response")
    if cls is not ExceptionResponse:
        assert cls.function_code in set(FunctionCode)
        assert (request_class if cls.role == "request" else response_class)(cls.function_code) is cls


@SETTINGS
@given(st.integers(1, MAX_READ_BITS).flatmap(bit_lists), st.sampled_from(BITS_RESPONSES))
def test_bits_response_decoded_from_bytes_holds_the_padding(bits, cls) -> None:
    pdu = cls(bits=bits)
    encoded = pdu.encode()
    byte_count = (len(bits) + 7) // 8
    assert encoded[1] == byte_count
    assert len(encoded) == 2 + byte_count
    decoded = decode_pdu(encoded, "response")
    assert len(decoded.bits) == 8 * byte_count
    assert decoded.bits[:len(bits)] == tuple(bits)
    assert not any(decoded.bits[len(bits):])
    assert decoded.encode() == encoded


def test_equality_hash_and_conversion_to_tuples() -> None:
    assert ReadCoilsRequest(address=0, count=1) == ReadCoilsRequest(0, 1)
    assert ReadCoilsRequest(0, 1) != ReadDiscreteInputsRequest(0, 1)
    assert WriteSingleCoilRequest(1, True) != WriteSingleCoilResponse(1, True)
    assert len({ReadCoilsRequest(0, 1), ReadCoilsRequest(0, 1), ReadCoilsRequest(0, 2)}) == 2
    write = WriteMultipleRegistersRequest(address=1, values=[10, 258])
    assert write.values == (10, 258)
    assert write == WriteMultipleRegistersRequest(1, (10, 258))
    assert ReadHoldingRegistersResponse(registers=[1, 2]).registers == (1, 2)
    assert ReadCoilsResponse(bits=[1, 0, True]).bits == (True, False, True)
    assert WriteMultipleCoilsRequest(0, [1, 0]).values == (True, False)
    assert WriteSingleCoilRequest(0, 1).value is True
    with pytest.raises(AttributeError):
        write.address = 5  # frozen


# --- documented byte layouts (the specification's examples) -------------------------------------------
LAYOUTS = [
    ("01 00 13 00 13", ReadCoilsRequest(address=19, count=19)),
    ("02 00 C4 00 16", ReadDiscreteInputsRequest(address=196, count=22)),
    ("03 00 6B 00 03", ReadHoldingRegistersRequest(address=107, count=3)),
    ("04 00 08 00 01", ReadInputRegistersRequest(address=8, count=1)),
    ("03 06 02 2B 00 00 00 64", ReadHoldingRegistersResponse(registers=(0x022B, 0x0000, 0x0064))),
    ("04 02 00 0A", ReadInputRegistersResponse(registers=(10,))),
    ("05 00 AC FF 00", WriteSingleCoilRequest(address=172, value=True)),
    ("05 00 AC FF 00", WriteSingleCoilResponse(address=172, value=True)),
    ("05 00 AC 00 00", WriteSingleCoilRequest(address=172, value=False)),
    ("06 00 01 00 03", WriteSingleRegisterRequest(address=1, value=3)),
    ("06 00 01 00 03", WriteSingleRegisterResponse(address=1, value=3)),
    ("0F 00 13 00 0A 02 CD 01", WriteMultipleCoilsRequest(
        address=19, values=(True, False, True, True, False, False, True, True, True, False))),
    ("0F 00 13 00 0A", WriteMultipleCoilsResponse(address=19, count=10)),
    ("10 00 01 00 02 04 00 0A 01 02", WriteMultipleRegistersRequest(address=1, values=(0x000A, 0x0102))),
    ("10 00 01 00 02", WriteMultipleRegistersResponse(address=1, count=2)),
    ("83 02", ExceptionResponse(function=3, code=2)),
    ("81 02", ExceptionResponse(function=1, code=2)),
    ("90 04", ExceptionResponse(function=16, code=4)),
]


@pytest.mark.parametrize(("wire", "pdu"), LAYOUTS, ids=[w for w, _ in LAYOUTS])
def test_documented_layouts(wire: str, pdu: Pdu) -> None:
    assert pdu.encode() == h(wire)
    assert decode_pdu(h(wire), pdu.role) == pdu
    assert type(pdu).decode(h(wire)) == pdu


def test_read_coils_response_of_the_spec() -> None:
    # 01 03 CD 6B 05: coils 20-27 = CD, 28-35 = 6B, 36-38 = 05 (first coil in the LSB)
    decoded = decode_pdu(h("01 03 CD 6B 05"), "response")
    assert isinstance(decoded, ReadCoilsResponse)
    assert decoded.byte_count == 3
    assert len(decoded.bits) == 24  # padding included: the response alone does not say 19
    assert decoded.bits[:8] == (True, False, True, True, False, False, True, True)
    assert decoded.bits[8:16] == (True, True, False, True, False, True, True, False)
    assert decoded.bits[16:19] == (True, False, True)
    bits19 = decoded.bits[:19]
    assert ReadCoilsResponse(bits=bits19).encode() == h("01 03 CD 6B 05")
    discrete = decode_pdu(h("02 03 AC DB 35"), "response")
    assert isinstance(discrete, ReadDiscreteInputsResponse)
    assert discrete.bits[:8] == (False, False, True, True, False, True, False, True)


def test_register_values_are_big_endian() -> None:
    assert ReadHoldingRegistersResponse(registers=(0x1234,)).encode() == h("03 02 12 34")
    assert WriteSingleRegisterRequest(address=0x0102, value=0xABCD).encode() == h("06 01 02 AB CD")
    assert WriteMultipleRegistersRequest(address=0, values=(0xFFFF,)).encode() == h("10 00 00 00 01 02 FF FF")


def test_multiple_coils_packing() -> None:
    assert WriteMultipleCoilsRequest(0, [True]).encode() == h("0F 00 00 00 01 01 01")
    assert WriteMultipleCoilsRequest(0, [False] * 8 + [True]).encode() == h("0F 00 00 00 09 02 00 01")
    assert WriteMultipleCoilsRequest(0, [True] * 16).encode() == h("0F 00 00 00 10 02 FF FF")


# --- quantity limits --------------------------------------------------------------------------------
@pytest.mark.parametrize(("cls", "limit"), READ_REQUESTS, ids=lambda x: getattr(x, "__name__", str(x)))
def test_read_request_quantity_limits(cls, limit: int) -> None:
    assert cls(address=0, count=1).count == 1
    assert cls(address=0, count=limit).count == limit
    for bad in (0, limit + 1):
        with raises(QuantityError, str(bad), f"1 to {limit}"):
            cls(address=0, count=bad)
        # the same quantity arriving on the wire: the message names the quantity's bytes 3-4
        wire = bytes([cls.function_code]) + (0).to_bytes(2, "big") + bad.to_bytes(2, "big")
        with raises(QuantityError, str(bad), f"1 to {limit}", "bytes 3-4"):
            cls.decode(wire)
        with raises(QuantityError, str(bad), f"1 to {limit}", "bytes 3-4"):
            decode_pdu(wire, "request")
        # inside a frame the offsets count from the frame's first byte
        with raises(QuantityError, "bytes 4-5"):
            decode_pdu(wire, "request", 1)
    with raises(QuantityError, "65535"):
        decode_pdu(bytes([cls.function_code]) + h("00 00 FF FF"), "request")


@pytest.mark.parametrize("cls", WRITE_REQUESTS, ids=lambda c: c.__name__)
def test_write_request_quantity_limits_in_the_constructor(cls) -> None:
    limit = MAX_WRITE_COILS if cls is WriteMultipleCoilsRequest else MAX_WRITE_REGISTERS
    value = True if cls is WriteMultipleCoilsRequest else 7
    assert len(cls(address=0, values=[value] * limit).values) == limit
    with raises(QuantityError, "0", f"1 to {limit}"):
        cls(address=0, values=[])
    with raises(QuantityError, str(limit + 1), f"1 to {limit}"):
        cls(address=0, values=[value] * (limit + 1))


def test_write_multiple_coils_quantity_limits_on_the_wire() -> None:
    assert MAX_WRITE_COILS == 1968
    # quantity 0 (with a byte count 0 and no data)
    with raises(QuantityError, "0", "1 to 1968", "bytes 3-4"):
        decode_pdu(h("0F 00 00 00 00 00"), "request")
    # quantity 1969: byte count 247 and 247 data bytes
    wire = h("0F 00 00") + (1969).to_bytes(2, "big") + bytes([247]) + b"\x00" * 247
    with raises(QuantityError, "1969", "1 to 1968", "bytes 3-4"):
        decode_pdu(wire, "request")
    with raises(QuantityError, "1969"):
        WriteMultipleCoilsRequest.decode(wire)
    ok = h("0F 00 00") + (1968).to_bytes(2, "big") + bytes([246]) + b"\x00" * 246
    assert len(decode_pdu(ok, "request").values) == 1968


def test_write_multiple_registers_quantity_limits_on_the_wire() -> None:
    assert MAX_WRITE_REGISTERS == 123
    with raises(QuantityError, "0", "1 to 123", "bytes 3-4"):
        decode_pdu(h("10 00 00 00 00 00"), "request")
    wire = h("10 00 00 00 7C F8") + b"\x00" * 248
    with raises(QuantityError, "124", "1 to 123", "bytes 3-4"):
        decode_pdu(wire, "request")
    with raises(QuantityError, "124"):
        WriteMultipleRegistersRequest.decode(wire)
    ok = h("10 00 00 00 7B F6") + b"\x00" * 246
    assert len(decode_pdu(ok, "request").values) == 123


@pytest.mark.parametrize(("cls", "limit"), WRITE_RESPONSES, ids=lambda x: getattr(x, "__name__", str(x)))
def test_write_response_quantity_limits(cls, limit: int) -> None:
    assert cls(address=0, count=limit).count == limit
    for bad in (0, limit + 1):
        with raises(QuantityError, str(bad), f"1 to {limit}"):
            cls(address=0, count=bad)
        wire = bytes([cls.function_code]) + h("00 00") + bad.to_bytes(2, "big")
        with raises(QuantityError, str(bad), f"1 to {limit}", "bytes 3-4"):
            decode_pdu(wire, "response")


@pytest.mark.parametrize("cls", BITS_RESPONSES, ids=lambda c: c.__name__)
def test_bits_response_limits(cls) -> None:
    assert len(cls(bits=[True] * MAX_READ_BITS).bits) == MAX_READ_BITS
    with raises(QuantityError, "0", "2000"):
        cls(bits=[])
    with raises(QuantityError, "2001", "2000"):
        cls(bits=[False] * 2001)
    fc = bytes([cls.function_code])
    with raises(ByteCountError, "byte count 0", "byte 1", "1 to 250"):
        decode_pdu(fc + h("00"), "response")
    with raises(ByteCountError, "byte count 251", "byte 1", "1 to 250"):
        decode_pdu(fc + bytes([251]) + b"\x00" * 251, "response")
    assert len(decode_pdu(fc + bytes([250]) + b"\xff" * 250, "response").bits) == 2000


@pytest.mark.parametrize("cls", REGISTER_RESPONSES, ids=lambda c: c.__name__)
def test_register_response_limits(cls) -> None:
    assert len(cls(registers=[1] * MAX_READ_REGISTERS).registers) == 125
    with raises(QuantityError, "0", "125"):
        cls(registers=[])
    with raises(QuantityError, "126", "125"):
        cls(registers=[0] * 126)
    fc = bytes([cls.function_code])
    with raises(ByteCountError, "byte count 0", "byte 1", "even"):
        decode_pdu(fc + h("00"), "response")
    with raises(ByteCountError, "byte count 3", "byte 1", "even"):
        decode_pdu(fc + h("03 00 01 02"), "response")
    with raises(ByteCountError, "byte count 252", "byte 1", "250"):
        decode_pdu(fc + bytes([252]) + b"\x00" * 252, "response")
    assert len(decode_pdu(fc + bytes([250]) + b"\x00" * 250, "response").registers) == 125


# --- address range ----------------------------------------------------------------------------------
SPAN_CLASSES = [
    *(c for c, _ in READ_REQUESTS),
    *(c for c, _ in WRITE_RESPONSES),
]


@pytest.mark.parametrize("cls", SPAN_CLASSES, ids=lambda c: c.__name__)
def test_address_plus_quantity_at_most_65536(cls) -> None:
    assert cls(address=65535, count=1).address == 65535
    assert cls(address=65534, count=2).count == 2
    with raises(AddressRangeError, "65535", "2", "65537", "65536"):
        cls(address=65535, count=2)
    limit = dict(READ_REQUESTS + WRITE_RESPONSES)[cls]
    with raises(AddressRangeError, str(65537 - limit), "65536"):
        cls(address=65537 - limit, count=limit)
    wire = bytes([cls.function_code]) + h("FF FF 00 02")
    with raises(AddressRangeError, "65537", "bytes 1-4"):
        decode_pdu(wire, cls.role)
    with raises(AddressRangeError, "65537"):
        cls.decode(wire)


@pytest.mark.parametrize("cls", WRITE_REQUESTS, ids=lambda c: c.__name__)
def test_write_request_address_range(cls) -> None:
    value = True if cls is WriteMultipleCoilsRequest else 1
    assert cls(address=65534, values=[value, value]).address == 65534
    with raises(AddressRangeError, "65535", "65537", "65536"):
        cls(address=65535, values=[value, value])
    if cls is WriteMultipleCoilsRequest:
        wire = h("0F FF FF 00 02 01 03")
    else:
        wire = h("10 FF FF 00 02 04 00 01 00 02")
    with raises(AddressRangeError, "65537", "bytes 1-4"):
        decode_pdu(wire, "request")


@pytest.mark.parametrize("cls", ALL_CLASSES, ids=lambda c: c.__name__)
def test_address_is_a_16_bit_field(cls) -> None:
    names = [f.name for f in dataclasses.fields(cls)]
    if "address" not in names:
        pytest.skip("no address field")
    example = {
        "count": 1, "value": 1 if "Register" in cls.__name__ else True,
        "values": [1] if "Register" in cls.__name__ else [True],
    }
    kwargs = {name: example[name] for name in names if name != "address"}
    for bad in (-1, 65536):
        with raises(PduError, str(bad), "65535"):
            cls(address=bad, **kwargs)
    with raises(PduError, "address"):
        cls(address="0", **kwargs)
    with raises(PduError, "address"):
        cls(address=1.0, **kwargs)


# --- byte counts ------------------------------------------------------------------------------------
def test_write_multiple_coils_byte_count_must_be_ceil_quantity_over_8() -> None:
    # 10 coils need 2 bytes
    with raises(ByteCountError, "byte 5", "byte count 1", "expected 2", "10 coils"):
        decode_pdu(h("0F 00 13 00 0A 01 CD"), "request")
    with raises(ByteCountError, "byte 5", "byte count 3", "expected 2"):
        decode_pdu(h("0F 00 13 00 0A 03 CD 01 00"), "request")
    with raises(ByteCountError, "byte 5", "expected 1"):
        decode_pdu(h("0F 00 00 00 08 02 FF 00"), "request")
    # right byte count, but the data that follows is shorter or longer
    with raises(TruncatedError, "byte 5", "2", "1"):
        decode_pdu(h("0F 00 13 00 0A 02 CD"), "request")
    with raises(TrailingBytesError, "byte 8"):
        decode_pdu(h("0F 00 13 00 0A 02 CD 01 00"), "request")
    # inside a frame, shifted by one
    with raises(ByteCountError, "byte 6"):
        decode_pdu(h("0F 00 13 00 0A 01 CD"), "request", 1)


def test_write_multiple_coils_padding_bits_must_be_zero() -> None:
    # 10 coils: the 6 high bits of the second byte are unused and must be 0, or re-encoding would differ
    with raises(ValueRangeError, "byte 7", "0x05", "padding"):
        decode_pdu(h("0F 00 13 00 0A 02 CD 05"), "request")
    with raises(ValueRangeError, "byte 6", "0x80", "padding"):
        decode_pdu(h("0F 00 13 00 07 01 80"), "request")
    assert decode_pdu(h("0F 00 13 00 0A 02 CD 03"), "request").values[8:] == (True, True)


def test_write_multiple_registers_byte_count_must_be_twice_the_quantity() -> None:
    with raises(ByteCountError, "byte 5", "byte count 3", "expected 4"):
        decode_pdu(h("10 00 01 00 02 03 00 0A 01"), "request")
    with raises(ByteCountError, "byte 5", "byte count 6", "expected 4"):
        decode_pdu(h("10 00 01 00 02 06 00 0A 01 02 00 00"), "request")
    with raises(TruncatedError, "byte 5", "4", "3"):
        decode_pdu(h("10 00 01 00 02 04 00 0A 01"), "request")
    with raises(TrailingBytesError, "byte 10"):
        decode_pdu(h("10 00 01 00 02 04 00 0A 01 02 FF"), "request")


@pytest.mark.parametrize("cls", BITS_RESPONSES + REGISTER_RESPONSES, ids=lambda c: c.__name__)
def test_read_response_byte_count_against_the_data(cls) -> None:
    fc = bytes([cls.function_code])
    # byte count says 4, only 2 follow
    with raises(TruncatedError, "byte 1", "4", "2"):
        decode_pdu(fc + h("04 00 01"), "response")
    with raises(TruncatedError):
        cls.decode(fc + h("04 00 01"))
    # byte count says 2, 4 follow
    with raises(TrailingBytesError, "byte 4", "2"):
        decode_pdu(fc + h("02 00 01 00 02"), "response")
    with raises(TrailingBytesError):
        cls.decode(fc + h("02 00 01 00 02"))


# --- values ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("cls", [WriteSingleCoilRequest, WriteSingleCoilResponse], ids=lambda c: c.__name__)
def test_coil_value_must_be_FF00_or_0000(cls) -> None:
    for raw in ("12 34", "00 FF", "FF FF", "00 01", "FF 01"):
        wire = h("05 00 AC") + h(raw)
        with raises(ValueRangeError, "bytes 3-4", "0x" + raw.replace(" ", ""), "0xFF00", "0x0000"):
            decode_pdu(wire, cls.role)
        with raises(ValueRangeError, "0xFF00"):
            cls.decode(wire)
    assert decode_pdu(h("05 00 AC FF 00"), cls.role).value is True
    assert decode_pdu(h("05 00 AC 00 00"), cls.role).value is False
    for bad in (2, -1, 0xFF00, "ON", None, 0.5):
        with raises(ValueRangeError, "coil value"):
            cls(address=0, value=bad)


@pytest.mark.parametrize(
    "make",
    [
        lambda v: WriteSingleRegisterRequest(address=0, value=v),
        lambda v: WriteSingleRegisterResponse(address=0, value=v),
        lambda v: WriteMultipleRegistersRequest(address=0, values=[1, v]),
        lambda v: ReadHoldingRegistersResponse(registers=[v]),
        lambda v: ReadInputRegistersResponse(registers=[0, 0, v]),
    ],
    ids=["FC6 request", "FC6 response", "FC16 request", "FC3 response", "FC4 response"],
)
def test_register_values_are_0_to_65535(make) -> None:
    assert make(0) is not None
    assert make(65535) is not None
    for bad in (-1, 65536, 1 << 20):
        with raises(ValueRangeError, str(bad), "0..65535"):
            make(bad)
    for bad in (1.0, "1", True, None):
        with raises(ValueRangeError):
            make(bad)


def test_register_index_is_named() -> None:
    with raises(ValueRangeError, "#1", "-1"):
        WriteMultipleRegistersRequest(address=0, values=[1, -1])
    with raises(ValueRangeError, "#2", "70000"):
        ReadHoldingRegistersResponse(registers=[1, 2, 70000])


@pytest.mark.parametrize(
    "make",
    [lambda v: ReadCoilsResponse(bits=[True, v]), lambda v: ReadDiscreteInputsResponse(bits=[v]),
     lambda v: WriteMultipleCoilsRequest(address=0, values=[False, False, v])],
    ids=["FC1 response", "FC2 response", "FC15 request"],
)
def test_bits_must_be_booleans(make) -> None:
    assert make(True) is not None
    assert make(0) is not None
    for bad in (2, -1, "1", None, 0.5):
        with raises(ValueRangeError):
            make(bad)
    with raises(ValueRangeError):
        ReadCoilsResponse(bits=5)


# --- exception responses -----------------------------------------------------------------------------
def test_exception_response_fields() -> None:
    exc = ExceptionResponse(function=3, code=2)
    assert exc.function == 3
    assert exc.code == 2
    assert exc.function_code == 0x83
    assert exc.role == "response"
    assert exc.encode() == h("83 02")
    assert "illegal data address" in exc.meaning


@pytest.mark.parametrize("function", [1, 2, 3, 4, 5, 6, 15, 16, 7, 0x2B, 0x7F])
@pytest.mark.parametrize("code", [1, 2, 3, 4, 5, 6, 8, 0x0A, 0x0B, 0x42])
def test_exception_response_for_any_function(function: int, code: int) -> None:
    wire = bytes([function | 0x80, code])
    decoded = decode_pdu(wire, "response")
    assert decoded == ExceptionResponse(function=function, code=code)
    assert decoded.encode() == wire
    assert pdu_length(wire, "response") == 2


def test_exception_response_rules() -> None:
    for bad in (0, 128, -1):
        with raises(ValueRangeError, str(bad), "1 to 127"):
            ExceptionResponse(function=bad, code=1)
    for bad in (0, 256, -1):
        with raises(ValueRangeError, str(bad)):
            ExceptionResponse(function=3, code=bad)
    with raises(ValueRangeError, "byte 1", "0x00"):
        decode_pdu(h("83 00"), "response")
    with raises(TruncatedError, "truncated"):
        decode_pdu(h("83"), "response")
    with raises(TrailingBytesError, "byte 2"):
        decode_pdu(h("83 02 00"), "response")
    with raises(UnknownFunctionError, "0x03", "byte 0"):
        ExceptionResponse.decode(h("03 02"))


def test_function_code_0x80_is_not_an_exception_for_function_0() -> None:
    # 0x80 would be "exception response to function 0", and there is no function 0
    with raises(PduError, "byte 0", "0x80"):
        decode_pdu(h("80 01"), "response")


def test_exception_codes_and_meanings() -> None:
    assert ExceptionCode.ILLEGAL_FUNCTION == 1
    assert ExceptionCode.ILLEGAL_DATA_ADDRESS == 2
    assert ExceptionCode.ILLEGAL_DATA_VALUE == 3
    assert ExceptionCode.SERVER_DEVICE_FAILURE == 4
    assert ExceptionCode.ACKNOWLEDGE == 5
    assert ExceptionCode.SERVER_DEVICE_BUSY == 6
    assert ExceptionCode.NEGATIVE_ACKNOWLEDGE == 7
    assert ExceptionCode.MEMORY_PARITY_ERROR == 8
    assert ExceptionCode.GATEWAY_PATH_UNAVAILABLE == 0x0A
    assert ExceptionCode.GATEWAY_TARGET_DEVICE_FAILED_TO_RESPOND == 0x0B
    for code in ExceptionCode:
        assert isinstance(code.meaning, str) and len(code.meaning) > 10
    assert "function" in ExceptionCode.ILLEGAL_FUNCTION.meaning
    assert "address" in ExceptionCode.ILLEGAL_DATA_ADDRESS.meaning
    assert "value" in ExceptionCode.ILLEGAL_DATA_VALUE.meaning
    parity = ExceptionCode.MEMORY_PARITY_ERROR.meaning                   # spec section 7: FC 20/21 only
    assert "file record" in parity and "20" in parity and "21" in parity
    assert ExceptionResponse(function=3, code=0x42).meaning  # undefined codes still get a sentence


def test_function_codes_and_titles() -> None:
    assert [int(c) for c in FunctionCode] == [
        1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 15, 16, 17, 20, 21, 22, 23, 24, 43]
    assert FunctionCode.READ_HOLDING_REGISTERS.title == "Read Holding Registers"
    assert FunctionCode.WRITE_MULTIPLE_COILS.title == "Write Multiple Coils"
    assert FunctionCode(2).title == "Read Discrete Inputs"
    assert (MAX_READ_BITS, MAX_READ_REGISTERS, MAX_WRITE_COILS, MAX_WRITE_REGISTERS, MAX_PDU_SIZE) == (
        2000, 125, 1968, 123, 253)


# --- unknown function codes and roles ------------------------------------------------------------------
@pytest.mark.parametrize("function", [0x00, 0x09, 0x0A, 0x0D, 0x0E, 0x13, 0x19, 0x2C, 0x41, 0x7F])
@pytest.mark.parametrize("role", ["request", "response"])
def test_unknown_function_codes(function: int, role: str) -> None:
    wire = bytes([function]) + h("00 00 00 01")
    implemented = "1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 15, 16, 17, 20, 21, 22, 23, 24, 43"
    with raises(UnknownFunctionError, f"0x{function:02X}", "byte 0", implemented) as info:
        decode_pdu(wire, role)
    assert info.value.function == function
    with raises(UnknownFunctionError, "byte 3"):
        decode_pdu(wire, role, 3)
    with raises(UnknownFunctionError, f"0x{function:02X}"):
        pdu_length(wire, role)
    with raises(UnknownFunctionError):
        (request_class if role == "request" else response_class)(function)


@pytest.mark.parametrize("function", [0x80, 0x81, 0x83, 0x90, 0xAB, 0xFF])
def test_exception_codes_are_never_requests(function: int) -> None:
    with raises(UnknownFunctionError, f"0x{function:02X}", "exception") as info:
        decode_pdu(bytes([function, 0x02]), "request")
    assert info.value.function == function
    with raises(UnknownFunctionError):
        pdu_length(bytes([function, 0x02]), "request")


@pytest.mark.parametrize("cls", ALL_CLASSES, ids=lambda c: c.__name__)
def test_class_decode_checks_the_function_code(cls) -> None:
    # A class's own decode must not accept another function's bytes as its own (a silent wrong value)
    samples = {
        ReadCoilsRequest: "01 00 00 00 01", ReadDiscreteInputsRequest: "02 00 00 00 01",
        ReadHoldingRegistersRequest: "03 00 00 00 01", ReadInputRegistersRequest: "04 00 00 00 01",
        ReadCoilsResponse: "01 01 01", ReadDiscreteInputsResponse: "02 01 01",
        ReadHoldingRegistersResponse: "03 02 00 01", ReadInputRegistersResponse: "04 02 00 01",
        WriteSingleCoilRequest: "05 00 01 FF 00", WriteSingleCoilResponse: "05 00 01 FF 00",
        WriteSingleRegisterRequest: "06 00 01 00 05", WriteSingleRegisterResponse: "06 00 01 00 05",
        WriteMultipleCoilsRequest: "0F 00 00 00 01 01 01", WriteMultipleCoilsResponse: "0F 00 00 00 01",
        WriteMultipleRegistersRequest: "10 00 00 00 01 02 00 01",
        WriteMultipleRegistersResponse: "10 00 00 00 01",
        ExceptionResponse: "83 02",
    }
    wire = h(samples[cls])
    assert cls.decode(wire).encode() == wire
    for other in (0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10, 0x07, 0x00):
        if other == wire[0] or (cls is ExceptionResponse):
            continue
        with raises(PduError, "byte 0"):
            cls.decode(bytes([other]) + wire[1:])


def test_decode_pdu_role_selects_the_class() -> None:
    echo = h("05 00 AC FF 00")
    assert type(decode_pdu(echo, "request")) is WriteSingleCoilRequest
    assert type(decode_pdu(echo, "response")) is WriteSingleCoilResponse
    assert type(decode_pdu(h("06 00 01 00 03"), "request")) is WriteSingleRegisterRequest
    assert type(decode_pdu(h("06 00 01 00 03"), "response")) is WriteSingleRegisterResponse
    assert type(decode_pdu(h("0F 00 13 00 0A"), "response")) is WriteMultipleCoilsResponse
    assert type(decode_pdu(h("10 00 01 00 02"), "response")) is WriteMultipleRegistersResponse
    assert type(decode_pdu(h("03 00 6B 00 03"), "request")) is ReadHoldingRegistersRequest
    assert type(decode_pdu(h("03 02 00 0A"), "response")) is ReadHoldingRegistersResponse
    # a request read as a response: byte count 0
    with raises(ByteCountError, "byte count 0"):
        decode_pdu(h("03 00 6B 00 03"), "response")
    # a response read as a request: too short
    with raises(TruncatedError):
        decode_pdu(h("03 02 00 0A"), "request")
    # an FC15 request read as a response: five bytes expected
    with raises(TrailingBytesError):
        decode_pdu(h("0F 00 13 00 0A 02 CD 01"), "response")
    for fc in (1, 2, 3, 4, 5, 6, 15, 16):
        assert request_class(fc).function_code == fc and request_class(fc).role == "request"
        assert response_class(fc).function_code == fc and response_class(fc).role == "response"


@pytest.mark.parametrize("role", ["Request", "req", "", None, "master"])
def test_bad_role_names(role) -> None:
    with pytest.raises(ConfigError, match="role"):
        decode_pdu(h("03 00 00 00 01"), role)
    with pytest.raises(ConfigError, match="role"):
        pdu_length(h("03 00 00 00 01"), role)


def test_empty_pdu() -> None:
    for role in ("request", "response"):
        with raises(TruncatedError, "byte 0", "function code"):
            decode_pdu(b"", role)
        assert pdu_length(b"", role) is None


def test_decode_pdu_rejects_text_with_a_modbus_error() -> None:
    # a learner passing hex text instead of bytes gets a teaching error, not a TypeError
    with pytest.raises(ModbusError):
        decode_pdu("03 00 00 00 01", "request")


# --- pdu_length ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("fc", [1, 2, 3, 4, 5, 6])
def test_pdu_length_fixed_requests(fc: int) -> None:
    assert pdu_length(bytes([fc]), "request") == 5
    assert pdu_length(bytes([fc, 0, 0]), "request") == 5


@pytest.mark.parametrize("fc", [15, 16])
def test_pdu_length_write_multiple_requests(fc: int) -> None:
    for n in range(1, 6):
        assert pdu_length(bytes([fc]) + b"\x00" * (n - 1), "request") is None
    assert pdu_length(bytes([fc, 0, 0, 0, 1, 2]), "request") == 8
    assert pdu_length(bytes([fc, 0, 0, 0, 1, 246]), "request") == 252
    assert pdu_length(bytes([fc, 0, 0, 0, 1, 246]) + b"\x00" * 3, "request") == 252


@pytest.mark.parametrize("fc", [1, 2, 3, 4])
def test_pdu_length_read_responses(fc: int) -> None:
    assert pdu_length(bytes([fc]), "response") is None
    assert pdu_length(bytes([fc, 2]), "response") == 4
    assert pdu_length(bytes([fc, 250]), "response") == 252
    assert pdu_length(bytes([fc, 0]), "response") == 2


@pytest.mark.parametrize("fc", [5, 6, 15, 16])
def test_pdu_length_write_responses(fc: int) -> None:
    assert pdu_length(bytes([fc]), "response") == 5


@pytest.mark.parametrize("fc", range(0x81, 0x100, 7))
def test_pdu_length_exception_responses(fc: int) -> None:
    assert pdu_length(bytes([fc]), "response") == 2


def test_messages_never_use_python_jargon() -> None:
    # errors teach: no IndexError/struct words leak into the messages of a few typical failures
    cases = [
        (h("03 00"), "request"), (h("03 05 00"), "response"), (h("0F 00 00 00 01"), "request"),
        (h("10 00 00 00 02 04 00"), "request"), (h("05 00 00 12 34"), "request"),
    ]
    for wire, role in cases:
        with pytest.raises(PduError) as info:
            decode_pdu(wire, role)
        message = str(info.value)
        assert not re.search(r"unpack|struct|index out of range|Traceback", message), message
        assert re.search(r"byte", message), message


@pytest.mark.parametrize("values", [{1: 2}, {1, 2}, "12", 5])
def test_values_must_be_an_ordered_sequence(values) -> None:
    # a dict or a set iterates, but has no order of values: it must not become a frame silently
    with pytest.raises(ValueRangeError, match="sequence"):
        WriteMultipleRegistersRequest(address=0, values=values)
    with pytest.raises(ValueRangeError, match="sequence"):
        WriteMultipleCoilsRequest(address=0, values=values)


@pytest.mark.parametrize("data", [5, None, 1.5, "03 00"])
def test_pdu_length_and_decode_pdu_refuse_what_is_not_bytes(data) -> None:
    # bytes(5) would be five zero bytes: a number is refused, not read as a PDU
    with pytest.raises(ModbusError):
        pdu_length(data, "request")
    with pytest.raises(ModbusError):
        decode_pdu(data, "request")
    assert pdu_length(b"", "request") is None
