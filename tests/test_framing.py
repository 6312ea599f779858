"""RTU, ASCII and TCP frames: the known-good vectors, every decoding rule broken once, helpers, fuzzing,
and a cross-check of the framing bytes against pymodbus's framers."""

from __future__ import annotations

import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modbus_edu import pdu as P
from modbus_edu.crc import crc16, lrc
from modbus_edu.errors import (
    AsciiFormatError,
    ByteCountError,
    ConfigError,
    CrcError,
    FrameError,
    FrameLengthError,
    LrcError,
    MbapError,
    ModbusError,
    TruncatedError,
    UnitError,
    UnknownFunctionError,
    ValueRangeError,
)
from modbus_edu.explain import explain
from modbus_edu.framing import (
    MODES,
    AsciiFrame,
    RtuFrame,
    TcpFrame,
    decode_frame,
    detect_mode,
    detect_mode_why,
    encode_frame,
    frame_class,
    make_frame,
    parse_hex,
)

FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def rtu(body_hex: str) -> bytes:
    """An RTU frame with a correct CRC around ``body_hex`` (unit + PDU)."""
    body = h(body_hex)
    return body + crc16(body).to_bytes(2, "little")


def ascii_frame(body_hex: str) -> bytes:
    """An ASCII frame with a correct LRC around ``body_hex`` (unit + PDU)."""
    body = h(body_hex)
    return b":" + (body + bytes([lrc(body)])).hex().upper().encode() + b"\r\n"


def tcp(tid: int, unit: int, pdu_hex: str) -> bytes:
    pdu = h(pdu_hex)
    return tid.to_bytes(2, "big") + b"\0\0" + (1 + len(pdu)).to_bytes(2, "big") + bytes([unit]) + pdu


# --- VECTORS.md -----------------------------------------------------------------------------------------
RTU_VECTORS = [
    ("01 03 00 00 00 01 84 0A", "request", 1, P.ReadHoldingRegistersRequest(address=0, count=1)),
    ("01 03 00 00 00 0A C5 CD", "request", 1, P.ReadHoldingRegistersRequest(address=0, count=10)),
    ("01 03 00 00 00 03 05 CB", "request", 1, P.ReadHoldingRegistersRequest(address=0, count=3)),
    ("01 03 04 00 03 55 71 F5 47", "response", 1, P.ReadHoldingRegistersResponse(registers=(3, 0x5571))),
    ("01 83 02 C0 F1", "response", 1, P.ExceptionResponse(function=3, code=2)),
    ("01 10 00 01 00 02 04 00 0A 01 02 92 30", "request", 1,
     P.WriteMultipleRegistersRequest(address=1, values=(0x000A, 0x0102))),
    ("11 05 00 AC FF 00 4E 8B", "request", 17, P.WriteSingleCoilRequest(address=172, value=True)),
    ("11 05 00 AC FF 00 4E 8B", "response", 17, P.WriteSingleCoilResponse(address=172, value=True)),
    ("11 0F 00 13 00 0A 02 CD 01 BF 0B", "request", 17,
     P.WriteMultipleCoilsRequest(address=19, values=[True, False, True, True, False, False, True, True,
                                                     True, False])),
    ("11 01 00 13 00 25 0E 84", "request", 17, P.ReadCoilsRequest(address=19, count=37)),
    ("11 03 00 6B 00 03 76 87", "request", 17, P.ReadHoldingRegistersRequest(address=107, count=3)),
]

ASCII_VECTORS = [
    (":050610010200E2", "request", 5, P.WriteSingleRegisterRequest(address=0x1001, value=0x0200)),
    (":050610010200E2", "response", 5, P.WriteSingleRegisterResponse(address=0x1001, value=0x0200)),
    (":050310000002E6", "request", 5, P.ReadHoldingRegistersRequest(address=0x1000, count=2)),
    (":050304FF0600648B", "response", 5, P.ReadHoldingRegistersResponse(registers=(0xFF06, 0x0064))),
]

TCP_VECTORS = [
    ("01 18 00 00 00 06 01 03 00 00 00 01", "request", 0x0118, 1,
     P.ReadHoldingRegistersRequest(address=0, count=1)),
    ("01 18 00 00 00 05 01 03 02 04 D2", "response", 0x0118, 1,
     P.ReadHoldingRegistersResponse(registers=(1234,))),
]


@pytest.mark.parametrize(("wire", "role", "unit", "pdu"), RTU_VECTORS)
def test_rtu_vectors(wire: str, role: str, unit: int, pdu: P.Pdu) -> None:
    data = h(wire)
    frame = RtuFrame.decode(data, role=role)
    assert frame == RtuFrame(unit=unit, pdu=pdu)
    assert frame.encode() == data
    assert RtuFrame(unit=unit, pdu=pdu).encode() == data
    assert detect_mode(data) == "rtu"
    assert decode_frame(data, "rtu", role) == frame


@pytest.mark.parametrize(("text", "role", "unit", "pdu"), ASCII_VECTORS)
def test_ascii_vectors(text: str, role: str, unit: int, pdu: P.Pdu) -> None:
    data = text.encode() + b"\r\n"
    frame = AsciiFrame.decode(data, role=role)
    assert frame == AsciiFrame(unit=unit, pdu=pdu)
    assert frame.encode() == data
    assert AsciiFrame(unit=unit, pdu=pdu).encode() == data
    assert detect_mode(data) == "ascii"
    assert parse_hex(text) == data  # CR LF appended
    assert AsciiFrame.decode(text + "\r\n", role=role) == frame  # text is accepted too
    assert AsciiFrame.decode(data.lower(), role=role) == frame  # lowercase hex


@pytest.mark.parametrize(("wire", "role", "tid", "unit", "pdu"), TCP_VECTORS)
def test_tcp_vectors(wire: str, role: str, tid: int, unit: int, pdu: P.Pdu) -> None:
    data = h(wire)
    frame = TcpFrame.decode(data, role=role)
    assert frame == TcpFrame(transaction_id=tid, unit=unit, pdu=pdu)
    assert frame.protocol_id == 0
    assert frame.encode() == data
    assert TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode() == data
    assert detect_mode(data) == "tcp"


def test_tcp_byte_order_of_source_000_is_a_different_transaction() -> None:
    """000 draws the transaction id low byte first (18 01); big-endian that is 0x1801, not 280."""
    swapped = TcpFrame.decode(h("18 01 00 00 00 06 01 03 00 00 00 01"))
    assert swapped.transaction_id == 0x1801 != 280


def test_tcp_unit_range_is_a_whole_byte() -> None:
    frame = TcpFrame(transaction_id=0xFFFF, unit=255, pdu=P.ReadCoilsRequest(0, 1))
    assert TcpFrame.decode(frame.encode()) == frame
    assert TcpFrame.decode(tcp(7, 0, "01 00 00 00 01")).unit == 0


def test_broadcast_unit_zero_is_valid_on_serial_lines() -> None:
    pdu = P.WriteSingleRegisterRequest(address=1, value=3)
    for cls in (RtuFrame, AsciiFrame):
        frame = cls(unit=0, pdu=pdu)
        assert cls.decode(frame.encode()) == frame


# --- RTU rules --------------------------------------------------------------------------------------------
def test_rtu_crc_mismatch_message() -> None:
    with pytest.raises(CrcError) as info:
        RtuFrame.decode(h("01 03 00 00 00 01 85 0A"))
    message = str(info.value)
    assert "CRC mismatch: frame carries 0x0A85, computed 0x0A84 over bytes 0-5" in message
    assert "bytes 6-7" in message and "expected 84 0A" in message
    assert info.value.received == 0x0A85 and info.value.computed == 0x0A84


def test_rtu_crc_sent_high_byte_first_is_a_mismatch() -> None:
    """The classic mistake: CRC appended high byte first."""
    with pytest.raises(CrcError, match="carries 0x840A, computed 0x0A84"):
        RtuFrame.decode(h("01 03 00 00 00 01 0A 84"))


@pytest.mark.parametrize("size", [0, 1, 3])
def test_rtu_too_short(size: int) -> None:
    with pytest.raises(FrameLengthError, match=rf"too short: {size} byte.*at least 4"):
        RtuFrame.decode(h("01 03 00")[:size])


def test_rtu_too_long() -> None:
    body = h("01 10 00 00 00 7B F6") + bytes(246) + b"\0\0"
    frame = body + crc16(body).to_bytes(2, "little")
    assert len(frame) == 257
    with pytest.raises(FrameLengthError, match="257 bytes; expected at most 256"):
        RtuFrame.decode(frame)


def test_rtu_longest_frame_is_256_bytes() -> None:
    frame = RtuFrame(unit=1, pdu=P.ReadHoldingRegistersResponse(registers=range(125)))
    assert len(frame.encode()) == 255
    bits = RtuFrame(unit=1, pdu=P.ReadCoilsResponse(bits=[True] * 2000))
    assert len(bits.encode()) == 255
    assert RtuFrame.decode(bits.encode(), "response") == bits


@pytest.mark.parametrize("unit", [248, 255])
def test_rtu_reserved_unit_is_decoded_and_building_one_warns(unit: int) -> None:
    import warnings

    from modbus_edu.errors import ReservedUnitWarning

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # decoding what is on the wire never warns
        frame = RtuFrame.decode(rtu(f"{unit:02X} 03 00 00 00 01"))
    assert frame.unit == unit
    with pytest.warns(ReservedUnitWarning, match="reserved range 248..255"):
        built = RtuFrame(unit, P.ReadHoldingRegistersRequest(address=0, count=1))
    assert built.encode() == rtu(f"{unit:02X} 03 00 00 00 01")
    with pytest.raises(UnitError, match="does not fit its one byte"):
        RtuFrame(256, P.ReadHoldingRegistersRequest(address=0, count=1))


def test_rtu_pdu_errors_propagate_with_frame_offsets() -> None:
    with pytest.raises(ValueRangeError, match="at bytes 4-5") as info:  # coil value 0x1234
        RtuFrame.decode(rtu("11 05 00 AC 12 34"))
    assert "0xFF00" in str(info.value)
    with pytest.raises(UnknownFunctionError, match="at byte 1"):
        RtuFrame.decode(rtu("01 09"))
    with pytest.raises(ByteCountError, match="at byte 2"):
        RtuFrame.decode(rtu("01 03 03 00 01 02"), "response")
    with pytest.raises(TruncatedError):
        RtuFrame.decode(rtu("01 03 00 00 00"))


def test_rtu_checks_crc_before_unit_and_pdu() -> None:
    """A receiver trusts nothing in a frame whose CRC is wrong."""
    with pytest.raises(CrcError):
        RtuFrame.decode(h("FF 07 00 00"))


# --- ASCII rules ------------------------------------------------------------------------------------------
def test_ascii_missing_start() -> None:
    with pytest.raises(AsciiFormatError) as info:
        AsciiFrame.decode(b"050610010200E2\r\n")
    assert "':'" in str(info.value) and "char 0" in str(info.value) and "'0'" in str(info.value)


@pytest.mark.parametrize("end", [b"", b"\r", b"\n", b"\n\r"])
def test_ascii_missing_cr_lf(end: bytes) -> None:
    with pytest.raises(AsciiFormatError, match="CR LF") as info:
        AsciiFrame.decode(b":050610010200E2" + end)
    assert "chars" in str(info.value)


def test_ascii_bad_hex_digit() -> None:
    with pytest.raises(AsciiFormatError) as info:
        AsciiFrame.decode(b":0506G0010200E2\r\n")
    assert "'G'" in str(info.value) and "char 5" in str(info.value) and "0-9" in str(info.value)


def test_ascii_second_start_character_is_not_hex() -> None:
    with pytest.raises(AsciiFormatError, match="char 3"):
        AsciiFrame.decode(b":05:0610010200E2\r\n")


def test_ascii_odd_number_of_digits() -> None:
    with pytest.raises(AsciiFormatError, match=r"odd number of hex digits \(13"):
        AsciiFrame.decode(b":050610010200E\r\n")


def test_ascii_too_short() -> None:
    with pytest.raises(FrameLengthError, match="2 bytes.*at least 3"):
        AsciiFrame.decode(b":05FB\r\n")
    with pytest.raises(FrameLengthError, match="empty"):
        AsciiFrame.decode(b"")


def test_ascii_too_long() -> None:
    frame = b":" + b"00" * 256 + b"\r\n"
    assert len(frame) == 515
    with pytest.raises(FrameLengthError, match="515 chars; expected at most 513"):
        AsciiFrame.decode(frame)


def test_ascii_longest_frames_fit_in_513_chars() -> None:
    frame = AsciiFrame(unit=1, pdu=P.ReadCoilsResponse(bits=[False] * 2000))
    assert len(frame.encode()) == 1 + 2 * (1 + 252 + 1) + 2  # ':', unit + 252-byte PDU + LRC, CR LF
    regs = AsciiFrame(unit=1, pdu=P.WriteMultipleRegistersRequest(address=0, values=range(123)))
    assert len(regs.encode()) <= 513
    assert AsciiFrame.decode(regs.encode()) == regs


def test_ascii_lrc_mismatch() -> None:
    with pytest.raises(LrcError) as info:
        AsciiFrame.decode(b":050304FF0600648C\r\n", "response")
    message = str(info.value)
    assert "LRC mismatch: frame carries 0x8C" in message and "computed 0x8B" in message
    assert "chars 15-16" in message
    assert info.value.received == 0x8C and info.value.computed == 0x8B


def test_ascii_reserved_unit_is_decoded() -> None:
    assert AsciiFrame.decode(ascii_frame("F8 03 00 00 00 01")).unit == 0xF8


def test_ascii_non_ascii_text() -> None:
    with pytest.raises(AsciiFormatError, match="char 3"):
        AsciiFrame.decode(":05é610010200E2\r\n")


def test_ascii_pdu_error_names_decoded_bytes() -> None:
    with pytest.raises(ValueRangeError, match="at bytes 4-5.*chars 2k\\+1"):
        AsciiFrame.decode(ascii_frame("11 05 00 AC 12 34"))


# --- TCP rules --------------------------------------------------------------------------------------------
def test_tcp_too_short() -> None:
    with pytest.raises(FrameLengthError, match="7 bytes; expected at least 8"):
        TcpFrame.decode(h("00 01 00 00 00 01 01"))


def test_tcp_too_long() -> None:
    frame = tcp(1, 1, "10 00 00 00 7B F6" + "00" * 246 + "00 00")
    assert len(frame) == 261
    with pytest.raises(FrameLengthError, match="261 bytes; expected at most 260"):
        TcpFrame.decode(frame)


def test_tcp_protocol_id() -> None:
    with pytest.raises(MbapError) as info:
        TcpFrame.decode(h("01 18 00 01 00 06 01 03 00 00 00 01"))
    message = str(info.value)
    assert "protocol identifier" in message and "bytes 2-3" in message and "expected 0" in message


@pytest.mark.parametrize("length", [0, 1, 255, 0x0600])
def test_tcp_length_out_of_range(length: int) -> None:
    data = h("01 18 00 00") + length.to_bytes(2, "big") + h("01 03 00 00 00 01")
    with pytest.raises(MbapError, match=rf"length at bytes 4-5 is {length} .*expected 2\.\.254"):
        TcpFrame.decode(data)


@pytest.mark.parametrize(("length", "follow"), [(7, 6), (5, 6)])
def test_tcp_length_mismatch(length: int, follow: int) -> None:
    data = h("01 18 00 00") + length.to_bytes(2, "big") + h("01 03 00 00 00 01")
    with pytest.raises(MbapError) as info:
        TcpFrame.decode(data)
    message = str(info.value)
    assert f"length at bytes 4-5 is {length}" in message and f"{follow} bytes follow" in message
    assert f"expected {follow}" in message


def test_tcp_pdu_errors_count_from_frame_start() -> None:
    with pytest.raises(ByteCountError, match="at byte 8"):
        TcpFrame.decode(tcp(1, 1, "03 03 04 D2 00"), "response")


# --- constructors and helpers ------------------------------------------------------------------------------
def test_constructor_checks() -> None:
    pdu = P.ReadCoilsRequest(address=0, count=1)
    for cls in (RtuFrame, AsciiFrame):
        for unit in (-1, 256, 300, 10**5000, "1", True, None):
            with pytest.raises(UnitError):
                cls(unit=unit, pdu=pdu)
        with pytest.raises(FrameError, match="PDU object"):
            cls(unit=1, pdu=b"\x01\x00\x00\x00\x01")
    with pytest.raises(UnitError, match="0..255"):
        TcpFrame(transaction_id=1, unit=256, pdu=pdu)
    with pytest.raises(MbapError, match="0..65535"):
        TcpFrame(transaction_id=65536, unit=1, pdu=pdu)
    with pytest.raises(MbapError, match="protocol identifier of Modbus is 0"):
        TcpFrame(transaction_id=1, unit=1, pdu=pdu, protocol_id=1)


def test_frames_are_frozen_and_compare_by_value() -> None:
    a = RtuFrame(unit=1, pdu=P.ReadCoilsRequest(0, 8))
    assert a == RtuFrame(1, P.ReadCoilsRequest(0, 8))
    with pytest.raises(AttributeError):
        a.unit = 2  # type: ignore[misc]


def test_bad_arguments_are_modbus_errors() -> None:
    with pytest.raises(ConfigError, match="role"):
        RtuFrame.decode(h("01 03 00 00 00 01 84 0A"), role="master")
    with pytest.raises(ConfigError, match="mode"):
        decode_frame(b"", "udp")
    with pytest.raises(FrameError, match="parse_hex"):
        RtuFrame.decode("01 03 00 00 00 01 84 0A")  # type: ignore[arg-type]
    with pytest.raises(FrameError, match="number"):
        TcpFrame.decode(12345)  # type: ignore[arg-type]
    with pytest.raises(FrameError, match="0..255"):
        TcpFrame.decode([1, 300])  # type: ignore[arg-type]
    assert RtuFrame.decode([1, 3, 0, 0, 0, 1, 0x84, 0x0A]).unit == 1  # type: ignore[arg-type]


def test_helpers() -> None:
    pdu = P.ReadHoldingRegistersRequest(address=0, count=1)
    assert MODES == ("rtu", "ascii", "tcp")
    assert frame_class("rtu") is RtuFrame and frame_class("ASCII") is AsciiFrame
    assert frame_class("tcp") is TcpFrame
    assert make_frame("tcp", 1, pdu, transaction_id=280) == TcpFrame(280, 1, pdu)
    assert encode_frame("rtu", 1, pdu) == h("01 03 00 00 00 01 84 0A")
    assert encode_frame("ascii", 5, P.WriteSingleRegisterRequest(0x1001, 0x200)) == b":050610010200E2\r\n"
    assert decode_frame(bytearray(h("01 03 00 00 00 01 84 0A")), "rtu") == RtuFrame(1, pdu)
    assert decode_frame(memoryview(b":050310000002E6\r\n"), "ascii").unit == 5


def test_detect_mode() -> None:
    assert detect_mode(b":050310000002E6\r\n") == "ascii"
    assert detect_mode(":0503") == "ascii"
    assert detect_mode("01 18 00 00 00 06 01 03 00 00 00 01") == "tcp"
    assert detect_mode("01 03 00 00 00 01 84 0A") == detect_mode("not hex") == "rtu"
    assert detect_mode(h("00 01 00 00 00 06 01 03 00 00 00 01")) == "tcp"
    assert detect_mode(h("00 01 00 00 00 07 01 03 00 00 00 01")) == "rtu"  # length does not match
    assert detect_mode(h("00 01 00 01 00 06 01 03 00 00 00 01")) == "rtu"  # protocol is not 0
    assert detect_mode(b"") == "rtu"
    # an RTU frame for unit 58 (0x3A = ':') with a correct CRC is not an ASCII frame
    assert detect_mode(rtu("3A 03 00 00 00 01")) == "rtu"


def test_detect_mode_prefers_tcp_for_protocol_0_and_a_length_written_low_byte_first() -> None:
    # a TCP response whose length 00 05 was written 05 00: an MBAP header with a slip, not RTU
    swapped = h("01 18 00 00 05 00 01 03 02 04 D2")
    assert detect_mode(swapped) == "tcp"
    mode, why = detect_mode_why(swapped)
    assert mode == "tcp" and why == ("protocol 0 in bytes 2-3, and the length, read low byte first, counts "
                                     "the 5 bytes that follow")
    assert explain(swapped).mode == "tcp" and explain(swapped).detected == why
    assert isinstance(explain(swapped).error, MbapError)  # the length is named, not a CRC
    assert detect_mode_why(h("01 18 00 00 00 05 01 03 02 04 D2")) == (
        "tcp", "protocol 0 in bytes 2-3, and the length counts the 5 bytes that follow")
    # an RTU request for address 0 has 00 00 in bytes 2-3 too: its CRC, or its length's misfit, keeps it RTU
    assert detect_mode_why(h("01 03 00 00 00 01 84 0A")) == ("rtu", "its last two bytes are its RTU CRC")
    assert detect_mode_why(h("01 03 00 00 00 01 84 0B")) == ("rtu", "no ':' in front, no MBAP header")
    assert detect_mode_why(":0503") == ("ascii", "it starts with ':'")
    assert explain(swapped, "tcp").detected == ""  # a mode given is not detected


def test_parse_hex_forms() -> None:
    want = h("01 03 00 0A")
    for text in ("01 03 00 0A", "0103000a", "0x01,0x03,0x00,0x0A", "01-03-00-0a", "0X01, 0x3, 0x0, 0xa",
                 " 01\t03\n00 0A ", "0103 000A", "01;03;00;0A", b"01 03 00 0a"):
        assert parse_hex(text) == want, text
    assert parse_hex("") == b""
    assert parse_hex(":050610010200E2") == b":050610010200E2\r\n"
    assert parse_hex(":050610010200E2\r\n") == b":050610010200E2\r\n"
    assert parse_hex(" :050610010200E2\\r\\n ") == b":050610010200E2\r\n"


@pytest.mark.parametrize(
    ("text", "position", "char"),
    [("01 0G", 4, "G"), ("0x01,0xZZ", 7, "Z"), ("01 03 +4", 6, "+"), ("01:03", 2, ":")],
)
def test_parse_hex_bad_character_names_its_position(text: str, position: int, char: str) -> None:
    with pytest.raises(AsciiFormatError) as info:
        parse_hex(text)
    assert f"position {position}" in str(info.value) and repr(char) in str(info.value)


def test_parse_hex_odd_digits_and_empty_prefix() -> None:
    with pytest.raises(AsciiFormatError, match="odd number of hex digits.*position 3"):
        parse_hex("01 030")
    with pytest.raises(AsciiFormatError, match="'0x' at position 3"):
        parse_hex("01 0x 03")
    with pytest.raises(AsciiFormatError, match="non-ASCII"):
        parse_hex(":05é6")
    with pytest.raises(FrameError):
        parse_hex(None)  # type: ignore[arg-type]


# --- generated PDUs: round trips and pymodbus cross-check ---------------------------------------------------
addresses = st.integers(0, 0xFFFF)
registers = st.integers(0, 0xFFFF)


def _read_request(cls, limit):
    return st.integers(0, 0xFFFF).flatmap(
        lambda a: st.integers(1, min(limit, 0x10000 - a)).map(lambda c: cls(address=a, count=c)))


def _write_many(cls, item, limit):
    return st.integers(0, 0xFFFF).flatmap(
        lambda a: st.lists(item, min_size=1, max_size=min(limit, 0x10000 - a)).map(
            lambda v: cls(address=a, values=v)))


REQUESTS = st.one_of(
    _read_request(P.ReadCoilsRequest, 2000),
    _read_request(P.ReadDiscreteInputsRequest, 2000),
    _read_request(P.ReadHoldingRegistersRequest, 125),
    _read_request(P.ReadInputRegistersRequest, 125),
    st.builds(P.WriteSingleCoilRequest, address=addresses, value=st.booleans()),
    st.builds(P.WriteSingleRegisterRequest, address=addresses, value=registers),
    _write_many(P.WriteMultipleCoilsRequest, st.booleans(), 1968),
    _write_many(P.WriteMultipleRegistersRequest, registers, 123),
)
RESPONSES = st.one_of(
    st.lists(st.booleans(), min_size=1, max_size=250).map(
        lambda b: P.ReadCoilsResponse(bits=b + [False] * (-len(b) % 8))),
    st.lists(st.booleans(), min_size=8, max_size=8).map(lambda b: P.ReadDiscreteInputsResponse(bits=b)),
    st.lists(registers, min_size=1, max_size=125).map(lambda r: P.ReadHoldingRegistersResponse(registers=r)),
    st.lists(registers, min_size=1, max_size=125).map(lambda r: P.ReadInputRegistersResponse(registers=r)),
    st.builds(P.WriteSingleCoilResponse, address=addresses, value=st.booleans()),
    st.builds(P.WriteSingleRegisterResponse, address=addresses, value=registers),
    _read_request(P.WriteMultipleCoilsResponse, 1968),
    _read_request(P.WriteMultipleRegistersResponse, 123),
    st.builds(P.ExceptionResponse, function=st.sampled_from([1, 2, 3, 4, 5, 6, 15, 16]),
              code=st.sampled_from([1, 2, 3, 4, 5, 6, 8, 10, 11])),
)
PDUS = st.one_of(REQUESTS.map(lambda p: ("request", p)), RESPONSES.map(lambda p: ("response", p)))
SERIAL_UNITS = st.integers(0, 247)


@FUZZ
@given(PDUS, SERIAL_UNITS, st.integers(0, 0xFFFF), st.integers(0, 255))
def test_round_trip_all_modes(item, unit: int, tid: int, tcp_unit: int) -> None:
    role, pdu = item
    for frame in (RtuFrame(unit, pdu), AsciiFrame(unit, pdu), TcpFrame(tid, tcp_unit, pdu)):
        data = frame.encode()
        assert type(frame).decode(data, role) == frame
        assert detect_mode(data) == frame.mode or frame.mode == "tcp"


def _pymodbus_framers():
    from pymodbus.framer import FramerAscii, FramerRTU, FramerSocket
    from pymodbus.pdu import DecodePDU

    decoder = DecodePDU(is_server=True)
    return FramerRTU(decoder), FramerAscii(decoder), FramerSocket(decoder)


@FUZZ
@given(PDUS, SERIAL_UNITS, st.integers(0, 0xFFFF))
def test_frame_bytes_equal_pymodbus_framers(item, unit: int, tid: int) -> None:
    """Same PDU bytes, same unit, same transaction id: our ADU bytes equal pymodbus's, and pymodbus's
    decoders find our unit, transaction id and PDU in them."""
    from pymodbus.framer import FramerRTU
    from pymodbus.pdu import DecodePDU

    role, pdu = item
    body = pdu.encode()
    f_rtu, f_ascii, f_socket = _pymodbus_framers()
    ours = {
        f_rtu: RtuFrame(unit, pdu).encode(),
        f_ascii: AsciiFrame(unit, pdu).encode(),
        f_socket: TcpFrame(tid, unit, pdu).encode(),
    }
    assert f_rtu.encode(body, unit, 0) == ours[f_rtu]
    assert f_ascii.encode(body, unit, 0) == ours[f_ascii]
    assert f_socket.encode(body, unit, tid) == ours[f_socket]
    used, dev_id, got_tid, got_pdu = f_socket.decode(ours[f_socket])
    assert (used, dev_id, got_tid, got_pdu) == (len(ours[f_socket]), unit, tid, body)
    used, dev_id, _tid, got_pdu = f_ascii.decode(ours[f_ascii])
    assert (used, dev_id, got_pdu) == (len(ours[f_ascii]), unit, body)
    rtu_reader = FramerRTU(DecodePDU(is_server=role == "request"))  # RTU needs the PDU lengths by role
    used, dev_id, _tid, got_pdu = rtu_reader.decode(ours[f_rtu])
    assert (used, dev_id, got_pdu) == (len(ours[f_rtu]), unit, body)


def test_pymodbus_crc_is_byte_swapped() -> None:
    """pymodbus's compute_CRC returns the CRC already swapped into wire order (VECTORS.md's remark)."""
    from pymodbus.framer import FramerRTU

    assert FramerRTU.compute_CRC(b"123456789") == 0x374B
    assert crc16(b"123456789") == 0x4B37


def test_pymodbus_frames_decode_here() -> None:
    from pymodbus.pdu.register_message import ReadHoldingRegistersResponse

    f_rtu, f_ascii, f_socket = _pymodbus_framers()
    message = ReadHoldingRegistersResponse(registers=[3, 0x5571], dev_id=1, transaction_id=280)
    assert f_rtu.buildFrame(message) == h("01 03 04 00 03 55 71 F5 47")
    expected = P.ReadHoldingRegistersResponse(registers=(3, 0x5571))
    assert RtuFrame.decode(f_rtu.buildFrame(message), "response") == RtuFrame(1, expected)
    assert AsciiFrame.decode(f_ascii.buildFrame(message), "response") == AsciiFrame(1, expected)
    assert TcpFrame.decode(f_socket.buildFrame(message), "response") == TcpFrame(280, 1, expected)


# --- fuzzing: nothing but ModbusError ----------------------------------------------------------------------
def _decode_everything(data: bytes) -> None:
    for mode in MODES:
        for role in ("request", "response"):
            try:
                frame = decode_frame(data, mode, role)
            except ModbusError:
                continue
            assert frame.encode() == data or mode == "ascii"  # ASCII also accepts lowercase hex
    detect_mode(data)


@FUZZ
@given(st.binary(max_size=300))
def test_random_bytes_raise_only_modbus_errors(data: bytes) -> None:
    _decode_everything(data)


@FUZZ
@given(st.text(alphabet="0123456789ABCDEFabcdef:\r\n xG", max_size=80))
def test_random_ascii_like_text_raises_only_modbus_errors(text: str) -> None:
    _decode_everything(text.encode())
    try:
        parse_hex(text)
    except ModbusError:
        pass


@st.composite
def mutated_frames(draw) -> bytes:
    role, pdu = draw(PDUS)
    mode = draw(st.sampled_from(MODES))
    unit = draw(SERIAL_UNITS)
    data = bytearray(make_frame(mode, unit, pdu, transaction_id=draw(st.integers(0, 0xFFFF))).encode())
    kind = draw(st.sampled_from(["flip", "truncate", "extend", "flip+truncate"]))
    if "flip" in kind:
        for _ in range(draw(st.integers(1, 3))):
            index = draw(st.integers(0, len(data) - 1))
            data[index] ^= 1 << draw(st.integers(0, 7))
    if "truncate" in kind:
        data = data[: draw(st.integers(0, len(data) - 1))]
    if kind == "extend":
        data += draw(st.binary(min_size=1, max_size=8))
    return bytes(data)


@FUZZ
@given(mutated_frames())
def test_mutated_frames_raise_only_modbus_errors(data: bytes) -> None:
    _decode_everything(data)


@FUZZ
@given(PDUS, SERIAL_UNITS, st.data())
def test_single_bit_flip_is_always_caught_by_the_crc(item, unit: int, data) -> None:
    """CRC-16 detects every single-bit error: a flipped RTU frame never decodes to another frame."""
    role, pdu = item
    frame = bytearray(RtuFrame(unit, pdu).encode())
    bit = data.draw(st.integers(0, 8 * len(frame) - 1))
    frame[bit // 8] ^= 1 << (bit % 8)
    with pytest.raises(CrcError):
        RtuFrame.decode(bytes(frame), role)


@pytest.mark.parametrize("cut, words", [
    (5, "byte count (byte 2) says 6 data bytes, 5 arrived: a byte was lost"),
    (3, "byte count (byte 2) says 6 data bytes, 5 arrived: a byte was lost"),
])
def test_a_response_shorter_than_its_byte_count_is_diagnosed_as_a_lost_byte(cut, words):
    from modbus_edu.errors import FrameLengthError

    frame = RtuFrame(1, P.ReadHoldingRegistersResponse(registers=[0x0102, 0x0304, 0x0506])).encode()
    with pytest.raises(FrameLengthError, match=re.escape(words)):
        RtuFrame.decode(frame[:cut] + frame[cut + 1:], role="response")


def test_a_fixed_length_frame_missing_a_byte_is_diagnosed_as_a_lost_byte():
    from modbus_edu.errors import FrameLengthError

    frame = RtuFrame(1, P.WriteSingleRegisterResponse(address=1, value=2)).encode()
    with pytest.raises(FrameLengthError, match="an FC6 response is 8 bytes, 7 arrived: a byte was lost"):
        RtuFrame.decode(frame[:3] + frame[4:], role="response")
    with pytest.raises(CrcError):  # the right length with a damaged byte stays a CRC error
        RtuFrame.decode(frame[:3] + bytes([frame[3] ^ 1]) + frame[4:], role="response")
