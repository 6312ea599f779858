"""CRC-16/MODBUS and LRC: known values, the three CRC methods agree, and pymodbus agrees with us."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pymodbus.framer import FramerAscii, FramerRTU

from modbus_edu.crc import (
    CRC_TABLE,
    build_crc_table,
    crc16,
    crc16_bitwise,
    crc16_table_trace,
    crc16_trace,
    crc_bytes,
    lrc,
    lrc_trace,
)

SETTINGS = settings(max_examples=300, deadline=None)


def reference_crc16(data: bytes) -> int:
    """An independent, deliberately naive CRC-16/MODBUS (init 0xFFFF, reflected poly 0xA001)."""
    crc = 0xFFFF
    for byte in data:
        for bit in range(8):
            # feed the message one bit at a time, least significant bit first
            feedback = (crc ^ (byte >> bit)) & 1
            crc >>= 1
            if feedback:
                crc ^= 0xA001
    return crc


def pymodbus_crc16(data: bytes) -> int:
    """pymodbus returns the CRC already byte-swapped (wire order read as big-endian): swap it back."""
    swapped = FramerRTU.compute_CRC(data)
    return ((swapped & 0xFF) << 8) | (swapped >> 8)


# --- fixed values ----------------------------------------------------------------------------------
def test_check_value() -> None:
    assert crc16(b"123456789") == 0x4B37
    assert crc16_bitwise(b"123456789") == 0x4B37
    assert crc_bytes(b"123456789") == bytes([0x37, 0x4B])


def test_pymodbus_returns_the_byte_swapped_value() -> None:
    # what VECTORS.md tells learners: pymodbus's compute_CRC is already in wire order
    assert FramerRTU.compute_CRC(b"123456789") == 0x374B


@pytest.mark.parametrize(
    ("data", "value", "wire"),
    [
        (b"123456789", 0x4B37, "37 4B"),
        (bytes.fromhex("010300000001"), 0x0A84, "84 0A"),
        (bytes.fromhex("01030000000A"), 0xCDC5, "C5 CD"),
        (bytes.fromhex("010300000003"), 0xCB05, "05 CB"),
        (bytes.fromhex("01030400035571"), 0x47F5, "F5 47"),
        (bytes.fromhex("018302"), 0xF1C0, "C0 F1"),
        (bytes.fromhex("01100001000204000A0102"), 0x3092, "92 30"),
        (bytes.fromhex("110500ACFF00"), 0x8B4E, "4E 8B"),
        (bytes.fromhex("110F0013000A02CD01"), 0x0BBF, "BF 0B"),
        (bytes.fromhex("110100130025"), 0x840E, "0E 84"),
        (bytes.fromhex("1103006B0003"), 0x8776, "76 87"),
    ],
)
def test_crc_vectors(data: bytes, value: int, wire: str) -> None:
    assert crc16(data) == value
    assert crc16_bitwise(data) == value
    assert crc_bytes(data) == bytes.fromhex(wire)
    assert list(crc16_trace(data))[-1].after == value
    assert list(crc16_table_trace(data))[-1].after == value


def test_empty_message_leaves_the_initial_value() -> None:
    assert crc16(b"") == 0xFFFF
    assert crc16_bitwise(b"") == 0xFFFF
    assert crc_bytes(b"") == b"\xff\xff"
    assert list(crc16_trace(b"")) == []
    assert list(crc16_table_trace(b"")) == []


def test_appending_the_crc_low_byte_first_gives_residue_zero() -> None:
    # the property a receiver may use: CRC over message + its CRC (low, high) is 0
    for data in (b"123456789", bytes.fromhex("010300000001"), bytes(range(256))):
        assert crc16(data + crc_bytes(data)) == 0


def test_accepts_bytearray_and_memoryview() -> None:
    data = bytes.fromhex("010300000001")
    assert crc16(bytearray(data)) == 0x0A84
    assert crc16(memoryview(data)) == 0x0A84
    assert crc16_bitwise(bytearray(data)) == 0x0A84


# --- the table -------------------------------------------------------------------------------------
def test_table_known_entries() -> None:
    assert len(CRC_TABLE) == 256
    assert isinstance(CRC_TABLE, tuple)
    assert CRC_TABLE[0] == 0x0000
    assert CRC_TABLE[1] == 0xC0C1
    assert CRC_TABLE[2] == 0xC181
    assert CRC_TABLE[3] == 0x0140
    assert CRC_TABLE[0x80] == 0xA001
    assert CRC_TABLE[255] == 0x4040


def test_table_is_built_from_0xA001_and_matches_pymodbus() -> None:
    assert build_crc_table() == CRC_TABLE
    assert build_crc_table(0xA001) == CRC_TABLE
    assert list(CRC_TABLE) == FramerRTU.generate_crc16_table()
    # each entry is eight bitwise steps applied to its index
    for index in range(256):
        register = index
        for _ in range(8):
            register = (register >> 1) ^ 0xA001 if register & 1 else register >> 1
        assert CRC_TABLE[index] == register


def test_table_for_another_polynomial() -> None:
    table = build_crc_table(0x8408)  # reflected CCITT polynomial, a different CRC
    assert table[0] == 0
    assert table[0x80] == 0x8408
    assert table != CRC_TABLE


# --- properties ------------------------------------------------------------------------------------
@SETTINGS
@given(st.binary(max_size=300))
def test_three_methods_agree(data: bytes) -> None:
    value = crc16(data)
    assert value == crc16_bitwise(data)
    assert value == reference_crc16(data)
    if data:
        assert list(crc16_trace(data))[-1].after == value
        assert list(crc16_table_trace(data))[-1].after == value
    assert crc_bytes(data) == value.to_bytes(2, "little")
    assert 0 <= value <= 0xFFFF


@settings(max_examples=100, deadline=None)
@given(st.binary(min_size=250, max_size=1100))
def test_long_inputs_agree(data: bytes) -> None:
    # crc16 may take long inputs two bytes per look-up: odd and even lengths around 256 must agree
    assert crc16(data) == crc16_bitwise(data) == pymodbus_crc16(data)
    assert crc16(bytearray(data)) == crc16(memoryview(data)) == crc16(data)


@pytest.mark.parametrize("length", [255, 256, 257, 258, 511, 512, 513, 4096, 4097])
def test_lengths_around_the_word_table_threshold(length: int) -> None:
    data = bytes((i * 37 + 11) & 0xFF for i in range(length))
    assert crc16(data) == crc16_bitwise(data) == reference_crc16(data)
    # the same bytes at an odd offset inside a larger buffer (memoryview of a slice)
    buffer = b"\x55" + data
    assert crc16(memoryview(buffer)[1:]) == crc16(data)


@SETTINGS
@given(st.binary(max_size=300))
def test_agrees_with_pymodbus(data: bytes) -> None:
    assert crc16(data) == pymodbus_crc16(data)
    # pymodbus's value, read as big-endian bytes, is exactly our wire order
    assert FramerRTU.compute_CRC(data).to_bytes(2, "big") == crc_bytes(data)


@SETTINGS
@given(st.binary(min_size=1, max_size=40))
def test_bitwise_trace_structure(data: bytes) -> None:
    steps = list(crc16_trace(data))
    assert len(steps) == 9 * len(data)
    register = 0xFFFF
    for position, byte in enumerate(data):
        group = steps[9 * position: 9 * position + 9]
        xor_step, shifts = group[0], group[1:]
        # one XOR-in step per byte
        assert xor_step.action == "xor_byte"
        assert xor_step.bit is None
        assert xor_step.byte_index == position
        assert xor_step.byte == byte
        assert xor_step.before == register
        assert xor_step.after == register ^ byte
        register = xor_step.after
        # then eight shifts, chained before -> after
        assert [s.bit for s in shifts] == list(range(8))
        for step in shifts:
            assert step.byte_index == position
            assert step.byte == byte
            assert step.before == register
            assert step.lsb == register & 1
            if step.lsb:
                assert step.action == "shift_xor"
                assert step.after == (register >> 1) ^ 0xA001
            else:
                assert step.action == "shift"
                assert step.after == register >> 1
            register = step.after
    assert register == crc16(data)


@SETTINGS
@given(st.binary(min_size=1, max_size=60))
def test_table_trace_chaining(data: bytes) -> None:
    steps = list(crc16_table_trace(data))
    assert len(steps) == len(data)
    register = 0xFFFF
    for position, (step, byte) in enumerate(zip(steps, data)):
        assert step.byte_index == position
        assert step.byte == byte
        assert step.before == register
        assert step.index == (register ^ byte) & 0xFF
        assert step.table_value == CRC_TABLE[step.index]
        assert step.after == (register >> 8) ^ step.table_value
        register = step.after
    assert register == crc16(data)


def test_trace_steps_describe_themselves() -> None:
    steps = list(crc16_trace(b"\x01"))
    assert "0xFFFF" in steps[0].describe() and "0xFFFE" in steps[0].describe()
    table_step = next(iter(crc16_table_trace(b"\x01")))
    assert "0x" in table_step.describe()


def test_trace_is_lazy() -> None:
    # a trace is an iterator: a learner can step through it with next()
    trace = crc16_trace(b"12")
    first = next(trace)
    assert first.action == "xor_byte"
    assert first.before == 0xFFFF
    assert first.after == 0xFFFF ^ ord("1")


# --- LRC -------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("data", "value"),
    [("050610010200", 0xE2), ("050310000002", 0xE6), ("050304FF060064", 0x8B), ("", 0x00), ("01", 0xFF)],
)
def test_lrc_vectors(data: str, value: int) -> None:
    assert lrc(bytes.fromhex(data)) == value


@SETTINGS
@given(st.binary(max_size=300))
def test_lrc_agrees_with_pymodbus(data: bytes) -> None:
    value = lrc(data)
    assert value == FramerAscii.compute_LRC(data)
    assert (sum(data) + value) & 0xFF == 0


@SETTINGS
@given(st.binary(max_size=60))
def test_lrc_trace(data: bytes) -> None:
    steps = lrc_trace(data)
    assert len(steps) == len(data)
    total = 0
    for position, (step, byte) in enumerate(zip(steps, data)):
        assert step.byte_index == position
        assert step.byte == byte
        assert step.before == total
        assert step.after == (total + byte) & 0xFF
        total = step.after
    if data:
        assert (-steps[-1].after) & 0xFF == lrc(data)


def test_lrc_trace_of_the_004_write() -> None:
    steps = lrc_trace(bytes.fromhex("050610010200"))
    assert [s.after for s in steps] == [0x05, 0x0B, 0x1B, 0x1C, 0x1E, 0x1E]
    assert (-steps[-1].after) & 0xFF == 0xE2


def test_bad_input_raises_a_modbus_error() -> None:
    from modbus_edu.errors import ModbusError

    with pytest.raises(ModbusError, match="0..255"):
        crc16([1, 2, 300])
    with pytest.raises(ModbusError):
        crc16_bitwise([-1])
    with pytest.raises(ModbusError):
        lrc([256])
    assert crc16([0x01, 0x03, 0x00, 0x00, 0x00, 0x01]) == 0x0A84


def test_trace_records_the_register_between_shift_and_xor() -> None:
    for step in crc16_trace(b"\x01\x03\x00\x00\x00\x01"):
        if step.action == "xor_byte":
            assert step.shifted == step.after
        else:
            assert step.shifted == step.before >> 1
            assert step.after == (step.shifted ^ 0xA001 if step.lsb else step.shifted)
