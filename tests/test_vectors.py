"""Every frame and checksum of VECTORS.md as a fixed expectation, through the public API.

Each frame is checked both ways: the bytes decode to the documented fields, and the fields encode to
exactly the documented bytes.
"""

from __future__ import annotations

import importlib

import pytest

import modbus_edu as mb

_HOMES = ("modbus_edu.crc", "modbus_edu.pdu", "modbus_edu.framing", "modbus_edu.errors")


def api(name: str):
    """``mb.<name>``; while the package does not re-export it yet, the submodule that defines it."""
    if hasattr(mb, name):
        return getattr(mb, name)
    for module_name in _HOMES:
        module = importlib.import_module(module_name)
        if hasattr(module, name):
            return getattr(module, name)
    raise AttributeError(f"modbus_edu has no public name {name!r}")


def hexbytes(text: str) -> bytes:
    return bytes.fromhex(text.replace(" ", ""))


# --- checksums -------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("data", "value", "wire"),
    [(b"123456789", 0x4B37, "37 4B"), (hexbytes("01 03 00 00 00 01"), 0x0A84, "84 0A")],
)
def test_crc_vectors(data: bytes, value: int, wire: str) -> None:
    assert api("crc16")(data) == value
    assert value.to_bytes(2, "little") == hexbytes(wire)


@pytest.mark.parametrize(
    ("data", "value"),
    [("05 06 10 01 02 00", 0xE2), ("05 03 10 00 00 02", 0xE6), ("05 03 04 FF 06 00 64", 0x8B)],
)
def test_lrc_vectors(data: str, value: int) -> None:
    assert api("lrc")(hexbytes(data)) == value


# --- RTU -------------------------------------------------------------------------------------------
def _rtu_cases():
    p = api
    return [
        ("01 03 00 00 00 01 84 0A", "request", 1, p("ReadHoldingRegistersRequest")(address=0, count=1)),
        ("01 03 00 00 00 0A C5 CD", "request", 1, p("ReadHoldingRegistersRequest")(address=0, count=10)),
        ("01 03 00 00 00 03 05 CB", "request", 1, p("ReadHoldingRegistersRequest")(address=0, count=3)),
        ("01 03 04 00 03 55 71 F5 47", "response", 1,
         p("ReadHoldingRegistersResponse")(registers=(0x0003, 0x5571))),
        ("01 83 02 C0 F1", "response", 1, p("ExceptionResponse")(function=3, code=2)),
        ("01 10 00 01 00 02 04 00 0A 01 02 92 30", "request", 1,
         p("WriteMultipleRegistersRequest")(address=1, values=(0x000A, 0x0102))),
        ("11 05 00 AC FF 00 4E 8B", "request", 17, p("WriteSingleCoilRequest")(address=172, value=True)),
        ("11 05 00 AC FF 00 4E 8B", "response", 17, p("WriteSingleCoilResponse")(address=172, value=True)),
        ("11 0F 00 13 00 0A 02 CD 01 BF 0B", "request", 17,
         p("WriteMultipleCoilsRequest")(
             address=19, values=(True, False, True, True, False, False, True, True, True, False))),
        ("11 01 00 13 00 25 0E 84", "request", 17, p("ReadCoilsRequest")(address=19, count=37)),
        ("11 03 00 6B 00 03 76 87", "request", 17, p("ReadHoldingRegistersRequest")(address=107, count=3)),
    ]


@pytest.mark.parametrize(("frame", "role", "unit", "pdu"), _rtu_cases())
def test_rtu_vectors(frame: str, role: str, unit: int, pdu) -> None:
    RtuFrame = api("RtuFrame")
    data = hexbytes(frame)
    decoded = RtuFrame.decode(data, role=role)
    assert decoded.unit == unit
    assert decoded.pdu == pdu
    assert type(decoded.pdu) is type(pdu)
    assert decoded.encode() == data
    assert RtuFrame(unit=unit, pdu=pdu).encode() == data
    assert pdu.encode() == data[1:-2]


def test_rtu_fields_of_the_vectors() -> None:
    RtuFrame = api("RtuFrame")
    response = RtuFrame.decode(hexbytes("01 03 04 00 03 55 71 F5 47"), role="response").pdu
    assert response.registers == (3, 0x5571)
    exception = RtuFrame.decode(hexbytes("01 83 02 C0 F1"), role="response").pdu
    assert exception.function == 3
    assert exception.code == 2
    assert exception.function_code == 0x83
    write = RtuFrame.decode(hexbytes("01 10 00 01 00 02 04 00 0A 01 02 92 30"), role="request").pdu
    assert (write.address, write.values) == (1, (10, 258))
    coils = RtuFrame.decode(hexbytes("11 0F 00 13 00 0A 02 CD 01 BF 0B"), role="request").pdu
    assert coils.address == 19
    assert len(coils.values) == 10
    assert coils.values == (True, False, True, True, False, False, True, True, True, False)
    coil = RtuFrame.decode(hexbytes("11 05 00 AC FF 00 4E 8B"), role="request").pdu
    assert coil.value is True
    read = RtuFrame.decode(hexbytes("11 01 00 13 00 25 0E 84"), role="request").pdu
    assert (read.address, read.count) == (19, 37)


def test_rtu_vector_with_a_bad_crc() -> None:
    RtuFrame = api("RtuFrame")
    CrcError = api("CrcError")
    with pytest.raises(CrcError) as info:
        RtuFrame.decode(hexbytes("01 03 00 00 00 01 85 0A"), role="request")
    assert info.value.received == 0x0A85
    assert info.value.computed == 0x0A84
    message = str(info.value)
    assert "0A85" in message.upper() and "0A84" in message.upper()


def test_rtu_vector_decoded_in_the_wrong_role() -> None:
    # "01 03 00 00 00 01" as a response would be byte count 0 followed by stray bytes
    with pytest.raises(api("ModbusError")):
        api("RtuFrame").decode(hexbytes("01 03 00 00 00 01 84 0A"), role="response")


# --- ASCII -----------------------------------------------------------------------------------------
def _ascii_cases():
    p = api
    return [
        (":050610010200E2", "request", 5, p("WriteSingleRegisterRequest")(address=0x1001, value=0x0200)),
        (":050610010200E2", "response", 5, p("WriteSingleRegisterResponse")(address=0x1001, value=0x0200)),
        (":050310000002E6", "request", 5, p("ReadHoldingRegistersRequest")(address=0x1000, count=2)),
        (":050304FF0600648B", "response", 5, p("ReadHoldingRegistersResponse")(registers=(0xFF06, 0x0064))),
    ]


@pytest.mark.parametrize(("frame", "role", "unit", "pdu"), _ascii_cases())
def test_ascii_vectors(frame: str, role: str, unit: int, pdu) -> None:
    AsciiFrame = api("AsciiFrame")
    data = frame.encode("ascii") + b"\r\n"
    decoded = AsciiFrame.decode(data, role=role)
    assert decoded.unit == unit
    assert decoded.pdu == pdu
    assert type(decoded.pdu) is type(pdu)
    assert decoded.encode() == data
    assert AsciiFrame(unit=unit, pdu=pdu).encode() == data


def test_ascii_fields_of_the_004_exchange() -> None:
    AsciiFrame = api("AsciiFrame")
    write = AsciiFrame.decode(b":050610010200E2\r\n", role="request").pdu
    assert (write.address, write.value) == (4097, 512)
    response = AsciiFrame.decode(b":050304FF0600648B\r\n", role="response").pdu
    assert response.registers == (0xFF06, 100)


def test_ascii_vector_with_a_bad_lrc() -> None:
    with pytest.raises(api("LrcError")) as info:
        api("AsciiFrame").decode(b":050610010200E3\r\n", role="request")
    assert info.value.received == 0xE3
    assert info.value.computed == 0xE2


# --- TCP -------------------------------------------------------------------------------------------
def test_tcp_request_vector() -> None:
    TcpFrame = api("TcpFrame")
    data = hexbytes("01 18 00 00 00 06 01 03 00 00 00 01")
    pdu = api("ReadHoldingRegistersRequest")(address=0, count=1)
    assert TcpFrame(transaction_id=0x0118, unit=1, pdu=pdu).encode() == data
    decoded = TcpFrame.decode(data, role="request")
    assert decoded.transaction_id == 280
    assert decoded.protocol_id == 0
    assert decoded.unit == 1
    assert decoded.pdu == pdu
    assert decoded.encode() == data


def test_tcp_response_vector() -> None:
    TcpFrame = api("TcpFrame")
    data = hexbytes("01 18 00 00 00 05 01 03 02 04 D2")
    pdu = api("ReadHoldingRegistersResponse")(registers=(1234,))
    assert TcpFrame(transaction_id=0x0118, unit=1, pdu=pdu).encode() == data
    decoded = TcpFrame.decode(data, role="response")
    assert decoded.transaction_id == 0x0118
    assert decoded.unit == 1
    assert decoded.pdu.registers == (1234,)
    assert decoded.encode() == data


def test_tcp_transaction_id_is_big_endian() -> None:
    # 000 draws it as 18 01 (low byte first); the specification sends 01 18
    TcpFrame = api("TcpFrame")
    frame = TcpFrame(transaction_id=280, unit=1, pdu=api("ReadHoldingRegistersRequest")(address=0, count=1))
    assert frame.encode()[:2] == b"\x01\x18"
    swapped = TcpFrame.decode(hexbytes("18 01 00 00 00 06 01 03 00 00 00 01"), role="request")
    assert swapped.transaction_id == 0x1801
