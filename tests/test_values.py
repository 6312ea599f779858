"""Values across registers: types x orders, scaling, text, display formats."""

from __future__ import annotations

import math
import re
import struct

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from modbus_edu.errors import ModbusError, ValueFormatError
from modbus_edu.values import (
    FORMATS,
    ORDERS,
    TYPES,
    decode_value,
    decode_values,
    encode_value,
    format_registers,
    parse_formatted,
    register_count,
    registers_to_text,
    scale,
    text_to_registers,
    unscale,
)

INT_RANGES = {
    "int16": (-(2**15), 2**15 - 1),
    "uint16": (0, 2**16 - 1),
    "int32": (-(2**31), 2**31 - 1),
    "uint32": (0, 2**32 - 1),
}


def test_types_and_orders():
    assert set(TYPES) == {"int16", "uint16", "int32", "uint32", "float32", "float64"}
    assert ORDERS == ("ABCD", "CDAB", "BADC", "DCBA")
    assert [register_count(t) for t in ("int16", "uint16", "int32", "uint32", "float32", "float64")] == [
        1,
        1,
        2,
        2,
        2,
        4,
    ]


# --- the byte diagrams of the module docstring, as fixed vectors -----------------------------------
@pytest.mark.parametrize(
    "order,regs32,regs64",
    [
        ("ABCD", [0x0102, 0x0304], [0x0102, 0x0304, 0x0506, 0x0708]),
        ("CDAB", [0x0304, 0x0102], [0x0708, 0x0506, 0x0304, 0x0102]),
        ("BADC", [0x0201, 0x0403], [0x0201, 0x0403, 0x0605, 0x0807]),
        ("DCBA", [0x0403, 0x0201], [0x0807, 0x0605, 0x0403, 0x0201]),
    ],
)
def test_order_diagram(order, regs32, regs64):
    assert encode_value(0x01020304, "uint32", order) == regs32
    assert decode_value(regs32, "uint32", order) == 0x01020304
    f64 = struct.unpack(">d", bytes(range(1, 9)))[0]
    assert encode_value(f64, "float64", order) == regs64
    assert decode_value(regs64, "float64", order) == f64


@pytest.mark.parametrize(
    "order,regs",
    [
        ("ABCD", [0x42F6, 0xE979]),
        ("CDAB", [0xE979, 0x42F6]),
        ("BADC", [0xF642, 0x79E9]),
        ("DCBA", [0x79E9, 0xF642]),
    ],
)
def test_float32_123_456(order, regs):
    assert encode_value(123.456, "float32", order) == regs
    assert decode_value(regs, "float32", order) == pytest.approx(123.456, rel=1e-7)


def test_16_bit_types_only_see_byte_order():
    assert encode_value(-2, "int16") == [0xFFFE]
    assert encode_value(-2, "int16", "CDAB") == [0xFFFE]
    assert encode_value(0x1234, "uint16", "BADC") == [0x3412]
    assert encode_value(0x1234, "uint16", "DCBA") == [0x3412]
    assert decode_value([0xFFFF], "int16") == -1
    assert decode_value([0xFFFF], "uint16") == 65535
    assert decode_value([1234], "uint16") == 1234  # 000's 04 D2


def test_int32_negative():
    assert encode_value(-2, "int32") == [0xFFFF, 0xFFFE]
    assert encode_value(-2, "int32", "CDAB") == [0xFFFE, 0xFFFF]
    assert decode_value([0xFFFF, 0xFFFE], "int32") == -2
    assert decode_value([0xFFFF, 0xFFFE], "uint32") == 0xFFFFFFFE


def test_case_insensitive_names():
    assert encode_value(1, "UINT32", "cdab") == [1, 0]


@pytest.mark.parametrize("type_", sorted(INT_RANGES))
def test_integer_range_errors(type_):
    lo, hi = INT_RANGES[type_]
    assert decode_value(encode_value(lo, type_), type_) == lo
    assert decode_value(encode_value(hi, type_), type_) == hi
    for bad in (lo - 1, hi + 1):
        with pytest.raises(ValueFormatError, match=rf"does not fit {type_}: its range is {lo}\.\.{hi}"):
            encode_value(bad, type_)
    with pytest.raises(ValueFormatError, match="whole number"):
        encode_value(1.5, type_)
    with pytest.raises(ValueFormatError, match="whole number"):
        encode_value("1", type_)


def test_float_errors_and_specials():
    with pytest.raises(ValueFormatError, match="too large for float32"):
        encode_value(1e39, "float32")
    with pytest.raises(ValueFormatError, match="too large"):
        encode_value(10**400, "float64")
    with pytest.raises(ValueFormatError, match="holds a number"):
        encode_value("1.0", "float32")
    with pytest.raises(ValueFormatError):
        encode_value(None, "float64")
    assert encode_value(math.inf, "float32") == [0x7F80, 0]
    assert math.isnan(decode_value(encode_value(math.nan, "float32"), "float32"))
    assert encode_value(3, "float32") == encode_value(3.0, "float32")


def test_bad_type_order_and_counts():
    with pytest.raises(ValueFormatError, match="unknown value type 'int8'.*int16, uint16"):
        encode_value(1, "int8")
    with pytest.raises(ValueFormatError, match="unknown order 'ABDC'"):
        encode_value(1, "uint16", "ABDC")
    with pytest.raises(ValueFormatError):
        register_count("double")
    with pytest.raises(ValueFormatError, match="int32 takes 2 registers, got 3"):
        decode_value([1, 2, 3], "int32")
    with pytest.raises(ValueFormatError, match="float64 takes 4 registers, got 2"):
        decode_value([1, 2], "float64")
    with pytest.raises(ValueFormatError, match=r"registers\[1\] = 65536 is outside 0\.\.65535"):
        decode_value([1, 65536], "int32")
    with pytest.raises(ValueFormatError, match=r"registers\[0\]"):
        decode_value([-1], "int16")
    with pytest.raises(ValueFormatError, match=r"registers\[0\] is float"):
        decode_value([1.0], "int16")
    with pytest.raises(ValueFormatError, match="list of 16-bit values"):
        decode_value(5, "int16")
    with pytest.raises(ValueFormatError):
        decode_value(b"\x00\x01", "int16")


def test_decode_values():
    regs = encode_value(1, "int32", "CDAB") + encode_value(-1, "int32", "CDAB")
    assert decode_values(regs, "int32", "CDAB") == [1, -1]
    assert decode_values([], "float32") == []
    assert decode_values([1, 2, 3], "uint16") == [1, 2, 3]
    with pytest.raises(ValueFormatError, match=r"5 registers .* 1 register left over from index 4"):
        decode_values([0] * 5, "float32")
    with pytest.raises(ValueFormatError, match="3 registers left over from index 4"):
        decode_values([0] * 7, "float64")


# --- properties: every type x order --------------------------------------------------------------------
def _value_strategy(type_):
    if type_ in INT_RANGES:
        return st.integers(*INT_RANGES[type_])
    if type_ == "float32":
        return st.floats(width=32, allow_nan=False)
    return st.floats(allow_nan=False)


type_order = st.sampled_from(sorted(TYPES)).flatmap(
    lambda t: st.tuples(st.just(t), st.sampled_from(ORDERS), _value_strategy(t))
)


@settings(max_examples=500, deadline=None)
@given(type_order)
def test_encode_decode_round_trip(case):
    type_, order, value = case
    regs = encode_value(value, type_, order)
    assert len(regs) == register_count(type_)
    assert all(0 <= r <= 0xFFFF for r in regs)
    back = decode_value(regs, type_, order)
    assert back == value
    if isinstance(value, float):
        assert math.copysign(1, back) == math.copysign(1, value)
    assert decode_values(regs * 3, type_, order) == [value] * 3


@settings(max_examples=400, deadline=None)
@given(st.sampled_from(sorted(TYPES)), st.sampled_from(ORDERS), st.data())
def test_decode_encode_round_trip(type_, order, data):
    n = register_count(type_)
    regs = data.draw(st.lists(st.integers(0, 0xFFFF), min_size=n, max_size=n))
    value = decode_value(regs, type_, order)
    if isinstance(value, float) and math.isnan(value):
        return  # NaN payloads need not survive a trip through a Python float
    assert encode_value(value, type_, order) == regs


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["int16", "uint16", "int32", "uint32", "float32", "float64"]), st.data())
def test_agrees_with_pymodbus(type_, data):
    from pymodbus.client.mixin import ModbusClientMixin as M

    value = data.draw(_value_strategy(type_))
    dt = getattr(M.DATATYPE, type_.upper())
    assert encode_value(value, type_, "ABCD") == M.convert_to_registers(value, dt, word_order="big")
    assert encode_value(value, type_, "CDAB") == M.convert_to_registers(value, dt, word_order="little")


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.integers(), st.floats(), st.text(max_size=3), st.none()), st.sampled_from(sorted(TYPES)))
def test_encode_never_leaks_python_errors(value, type_):
    try:
        regs = encode_value(value, type_)
    except ValueFormatError:
        return
    assert all(0 <= r <= 0xFFFF for r in regs)


# --- scaling -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "raw,factor,value",
    [
        (4036, 10, 403.6),  # 003: VL1 403.6 V
        (4126, 10, 412.6),
        (66, 100, 0.66),  # power factor 0.66
        (60, 100, 0.6),
        (3049, 10, 304.9),
        (-15, 10, -1.5),
        (7, 1, 7.0),
        (4036, 0.1, 40360.0),
    ],
)
def test_scale(raw, factor, value):
    assert scale(raw, factor) == value
    assert repr(scale(raw, factor)) == repr(value)
    assert unscale(value, factor) == raw


def test_scale_prints_exactly():
    assert str(scale(4036, 10)) == "403.6"
    assert str(scale(1, 1000)) == "0.001"
    assert unscale(0.665, 100) == 67  # half away from zero
    assert unscale(-0.665, 100) == -67
    assert unscale(403.64, 10) == 4036


def test_scale_errors():
    with pytest.raises(ValueFormatError, match="must not be 0"):
        scale(1, 0)
    with pytest.raises(ValueFormatError):
        unscale(1, 0)
    with pytest.raises(ValueFormatError):
        scale("abc", 10)
    with pytest.raises(ValueFormatError, match="finite"):
        unscale(math.inf, 10)
    with pytest.raises(ValueFormatError):
        scale(True, 10)


@settings(max_examples=300, deadline=None)
@given(st.integers(-(2**31), 2**31 - 1), st.sampled_from([1, 10, 100, 1000]))
def test_scale_unscale_round_trip(raw, factor):
    assert unscale(scale(raw, factor), factor) == raw


# --- text --------------------------------------------------------------------------------
def test_text_to_registers():
    assert text_to_registers("AB") == [0x4142]
    assert text_to_registers("ABC") == [0x4142, 0x4300]
    assert text_to_registers("ABC", pad=" ") == [0x4142, 0x4320]
    assert text_to_registers("AB", length=3) == [0x4142, 0, 0]
    assert text_to_registers("ABC", order="BA") == [0x4241, 0x0043]
    assert text_to_registers("") == []
    assert text_to_registers("", length=1, pad=" ") == [0x2020]


def test_text_errors():
    with pytest.raises(ValueFormatError, match=r"character 2 .*'é' \(U\+00E9\), is not ASCII"):
        text_to_registers("caé")
    with pytest.raises(ValueFormatError, match="5 characters need 3 registers"):
        text_to_registers("ABCDE", length=2)
    with pytest.raises(ValueFormatError):
        text_to_registers(b"AB")
    with pytest.raises(ValueFormatError):
        text_to_registers("AB", pad="")
    with pytest.raises(ValueFormatError):
        text_to_registers("AB", order="CD")
    with pytest.raises(ValueFormatError):
        text_to_registers("AB", length=-1)
    for huge in (2**70, 2**40, 65537):  # more registers than a table holds: our error, not Overflow/Memory
        with pytest.raises(ValueFormatError, match="65536"):
            text_to_registers("\x00", length=huge)
    assert len(text_to_registers("A", length=65536)) == 65536
    with pytest.raises(ValueFormatError, match=r"register 1 \(0x41C3\) byte 1 is 0xC3, not ASCII"):
        registers_to_text([0x4142, 0x41C3])
    with pytest.raises(ValueFormatError):
        registers_to_text([0x10000])
    with pytest.raises(ValueFormatError):
        registers_to_text([0x4142], order="XY")


def test_registers_to_text():
    assert registers_to_text([0x4142, 0x4300]) == "ABC"
    assert registers_to_text([0x4142, 0x4300], strip="") == "ABC\x00"
    assert registers_to_text([0x4142, 0x2020]) == "AB  "
    assert registers_to_text([0x4142, 0x2020], strip="\x00 ") == "AB"
    assert registers_to_text([0x4241, 0x0043], order="BA") == "ABC"


@settings(max_examples=300, deadline=None)
@given(
    st.text(st.characters(min_codepoint=0, max_codepoint=127), max_size=40).filter(
        lambda s: not s.endswith("\x00")
    ),
    st.sampled_from(["AB", "BA"]),
)
def test_text_round_trip(text, order):
    regs = text_to_registers(text, order=order)
    assert len(regs) == (len(text) + 1) // 2
    assert registers_to_text(regs, order=order) == text


def test_text_matches_pymodbus_string_layout():
    from pymodbus.client.mixin import ModbusClientMixin as M

    assert text_to_registers("ABC") == M.convert_to_registers("ABC", M.DATATYPE.STRING)


# --- display formats --------------------------------------------------------------------------------
def test_formats_list():
    assert FORMATS[:6] == ("hex", "binary", "unsigned", "signed", "ascii_char", "ascii_value")
    for name in ("int32_ABCD", "uint32_CDAB", "float32_BADC", "float64_ABCD", "float32_DCBA"):
        assert name in FORMATS
    assert len(FORMATS) == 6 + 4 * 4


def test_single_register_formats():
    regs = [0x04D2, 0xFFFF, 0x4142, 0x0041, 0x7F20]
    assert format_registers(regs, "hex") == ["0x04D2", "0xFFFF", "0x4142", "0x0041", "0x7F20"]
    assert format_registers([0x04D2], "binary") == ["0000 0100 1101 0010"]
    assert format_registers(regs, "unsigned") == ["1234", "65535", "16706", "65", "32544"]
    assert format_registers(regs, "signed") == ["1234", "-1", "16706", "65", "32544"]
    assert format_registers(regs, "ascii_char") == ["..", "..", "AB", ".A", ". "]
    assert format_registers(regs, "ascii_value") == ["4 210", "255 255", "65 66", "0 65", "127 32"]
    assert format_registers([], "hex") == []


def test_wide_formats_group_registers():
    regs = encode_value(-2, "int32") + encode_value(70000, "int32")
    assert format_registers(regs, "int32_ABCD") == ["-2", "", "70000", ""]
    assert format_registers(regs + [5], "int32_ABCD") == ["-2", "", "70000", "", "—"]
    assert format_registers(encode_value(0.1, "float32", "BADC"), "float32_BADC") == ["0.1", ""]
    assert format_registers(encode_value(403.6, "float32", "CDAB"), "float32_CDAB") == ["403.6", ""]
    assert format_registers(encode_value(1.0, "float32"), "float32_ABCD") == ["1.0", ""]
    assert format_registers(encode_value(0.1, "float64") + [1, 2, 3], "float64_ABCD") == [
        "0.1",
        "",
        "",
        "",
        "—",
        "—",
        "—",
    ]
    assert format_registers([0xFFFF, 0xFFFF], "uint32_CDAB") == ["4294967295", ""]
    assert format_registers([0x7FC0, 0], "float32_ABCD") == ["nan", ""]
    assert format_registers([0xFF80, 0], "float32_ABCD") == ["-inf", ""]
    assert format_registers([1], "float32_ABCD") == ["—"]
    assert format_registers([1], "uint32_cdab") == ["—"]  # case-insensitive


def test_format_errors():
    with pytest.raises(ValueFormatError, match="unknown display format 'octal'"):
        format_registers([1], "octal")
    with pytest.raises(ValueFormatError, match=r"registers\[1\] = 70000"):
        format_registers([1, 70000], "hex")


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(FORMATS), st.lists(st.integers(0, 0xFFFF), max_size=12))
def test_every_format_gives_one_string_per_register(fmt, regs):
    out = format_registers(regs, fmt)
    assert len(out) == len(regs)
    assert all(isinstance(s, str) for s in out)


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(FORMATS), st.data())
def test_parse_formatted_inverts_format(fmt, data):
    if fmt in FORMATS[:6]:
        n = 1
    else:
        n = register_count(fmt.rpartition("_")[0])
    regs = data.draw(st.lists(st.integers(0, 0xFFFF), min_size=n, max_size=n))
    text = format_registers(regs, fmt)[0]
    pair = (regs[0] >> 8, regs[0] & 0xFF)
    if fmt == "ascii_char" and any(not 0x20 <= b <= 0x7E or b == 0x2E for b in pair):
        return  # non-printables are shown as '.', which cannot come back
    if fmt.startswith("float") and text in ("nan", "-nan"):
        return
    back = parse_formatted(text, fmt)
    if fmt.startswith("float") and fmt.rpartition("_")[0] == "float32":
        assert decode_value(back, "float32", fmt[-4:]) == decode_value(regs, "float32", fmt[-4:])
    elif fmt.startswith("float64"):
        assert decode_value(back, "float64", fmt[-4:]) == decode_value(regs, "float64", fmt[-4:])
    else:
        assert back == regs


def test_parse_formatted_examples_and_errors():
    assert parse_formatted("0x04D2", "hex") == [1234]
    assert parse_formatted("04d2", "hex") == [1234]
    assert parse_formatted("0000 0100 1101 0010", "binary") == [1234]
    assert parse_formatted("-1", "signed") == [0xFFFF]
    assert parse_formatted("AB", "ascii_char") == [0x4142]
    assert parse_formatted("4 210", "ascii_value") == [0x04D2]
    assert parse_formatted("1.5", "float32_CDAB") == encode_value(1.5, "float32", "CDAB")
    assert parse_formatted("-2", "int32_DCBA") == encode_value(-2, "int32", "DCBA")
    for text, fmt in [
        ("zz", "hex"),
        ("0x10000", "hex"),
        ("12", "binary"),
        ("70000", "unsigned"),
        ("-40000", "signed"),
        ("1.5", "unsigned"),
        ("ABC", "ascii_char"),
        ("4", "ascii_value"),
        ("4 300", "ascii_value"),
        ("x", "float32_ABCD"),
        ("1.5", "int32_ABCD"),
        ("", "unsigned"),
    ]:
        with pytest.raises(ValueFormatError) as e:
            parse_formatted(text, fmt)
        assert repr(text) in str(e.value)
    with pytest.raises(ValueFormatError):
        parse_formatted(5, "hex")
    with pytest.raises(ModbusError):
        parse_formatted("1", "octal")


def test_integer_types_refuse_a_bool() -> None:
    with pytest.raises(ValueFormatError, match="bool"):
        encode_value(True, "uint16")


@pytest.mark.parametrize("huge", [10**5000, -(10**5000), 2**70], ids=["10**5000", "-10**5000", "2**70"])
def test_decode_values_names_a_huge_register_without_leaking_python_errors(huge):
    words = "registers\\[1\\] = (an|a negative) int of \\d+ bits \\(about \\d+ digits\\) is outside 0..65535"
    with pytest.raises(ModbusError, match=words):
        decode_values([1, huge], "uint16")


@pytest.mark.parametrize("length", [10**5000, -(10**5000), 2**70], ids=["10**5000", "-10**5000", "2**70"])
def test_text_to_registers_refuses_a_huge_length_by_its_size(length):
    with pytest.raises(ValueFormatError, match="length is a number of registers, 0..65536") as caught:
        text_to_registers("\x00", length)
    assert re.search("(an|a negative) int of", str(caught.value)) and len(str(caught.value)) < 200


@settings(max_examples=50, deadline=None)
@given(st.integers(19, 20_000), st.sampled_from([1, -1]), st.integers(0, 9))
def test_text_to_registers_and_decode_values_name_any_huge_int_in_a_short_message(digits, sign, tail):
    huge = sign * (10**digits + tail)
    for call in (lambda: text_to_registers("AB", huge), lambda: decode_values([huge], "uint16"),
                 lambda: registers_to_text([65, huge])):
        with pytest.raises(ValueFormatError) as caught:
            call()
        assert len(str(caught.value)) < 300
