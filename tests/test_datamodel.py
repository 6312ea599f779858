"""DataBank tables (dense and sparse) and reference numbers."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import modbus_edu as mb
from modbus_edu.datamodel import (
    ADDRESS_SPACE,
    TABLE_KINDS,
    DataBank,
    Reference,
    Table,
    format_reference,
    parse_reference,
    table_kind,
)
from modbus_edu.errors import (
    DataModelError,
    IllegalAddressError,
    ModbusError,
    ReferenceNumberError,
    ValueRangeError,
)

BITS = ("coils", "discrete_inputs")
REGISTERS = ("input_registers", "holding_registers")


# --- the four tables -------------------------------------------------------------------------------
def test_dense_bank_has_four_zeroed_tables():
    bank = DataBank()
    assert [t.kind for t in bank.tables] == list(TABLE_KINDS)
    for kind in TABLE_KINDS:
        t = getattr(bank, kind)
        assert t.kind == kind
        assert len(t) == ADDRESS_SPACE
        assert t.addresses() == range(65536)
    assert bank.coils.read(0, 3) == [False, False, False]
    assert bank.holding_registers.read(65533, 3) == [0, 0, 0]
    assert bank.snapshot() == {k: {} for k in TABLE_KINDS}


def test_kinds_bits_and_access_rights():
    bank = DataBank()
    assert bank.coils.is_bits and bank.discrete_inputs.is_bits
    assert not bank.input_registers.is_bits and not bank.holding_registers.is_bits
    assert bank.coils.writable and bank.holding_registers.writable
    assert not bank.discrete_inputs.writable and not bank.input_registers.writable


def test_the_device_may_write_read_only_tables():
    bank = DataBank()
    bank.input_registers.write(0, [1, 2])
    bank.discrete_inputs[5] = True
    assert bank.input_registers.read(0, 2) == [1, 2]
    assert bank.discrete_inputs[5] is True


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_edge_addresses_0_and_65535(kind):
    t = DataBank().table(kind)
    v = True if t.is_bits else 65535
    t[0] = v
    t[65535] = v
    assert t[0] == v and t[65535] == v
    assert t.read(65535, 1) == [v]
    assert t.read(0, 1) == [v]
    assert t.read(65534, 2) == [t[65534], v]
    whole = t.read(0, 65536)
    assert len(whole) == 65536 and whole[0] == v and whole[-1] == v
    assert t.read(65535, 0) == []


@pytest.mark.parametrize(
    "address,count",
    [(-1, 1), (65536, 1), (65535, 2), (0, 65537), (65000, 600)],
)
@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_out_of_range_raises_illegal_address(kind, address, count):
    t = DataBank().table(kind)
    with pytest.raises(IllegalAddressError) as e:
        t.read(address, count)
    msg = str(e.value)
    assert "65535" in msg
    with pytest.raises(IllegalAddressError):
        t.write(address, [0] * max(count, 1))


def test_range_message_teaches():
    with pytest.raises(IllegalAddressError, match=r"from address 65530: that would run to address 65539"):
        DataBank().holding_registers.read(65530, 10)
    with pytest.raises(IllegalAddressError, match=r"address 70000 is outside the table.*0 to 65535"):
        DataBank().holding_registers[70000]


def test_bad_address_types():
    t = DataBank().holding_registers
    with pytest.raises(IllegalAddressError, match="reference number"):
        t.read("40001", 1)
    with pytest.raises(IllegalAddressError):
        t.read(1.0, 1)
    with pytest.raises(IllegalAddressError):
        t[True]
    with pytest.raises(DataModelError, match="count"):
        t.read(0, -1)
    with pytest.raises(DataModelError, match="count"):
        t.read(0, "3")


def test_register_values_checked():
    t = DataBank().holding_registers
    t.write(0, [0, 65535, 1234])
    for bad in (-1, 65536, 1.5, 2.0, "1", None):
        with pytest.raises(ValueRangeError, match=r"address 11 .*0\.\.65535"):
            t.write(10, [5, bad])
    assert t.read(0, 3) == [0, 65535, 1234]
    assert t.read(10, 2) == [0, 0]  # nothing written on error
    with pytest.raises(ValueRangeError):
        t[3] = 70000


def test_bit_values_checked():
    t = DataBank().coils
    t.write(0, [True, 0, 1, False])
    assert t.read(0, 4) == [True, False, True, False]
    assert all(type(b) is bool for b in t.read(0, 4))
    for bad in (2, -1, 0.5, "on", None):
        with pytest.raises(ValueRangeError, match=r"coil at address 9 takes a bit"):
            t.write(8, [True, bad])
    assert t.read(8, 2) == [False, False]


def test_write_needs_a_sequence():
    t = DataBank().holding_registers
    with pytest.raises(DataModelError, match=r"table\[address\] = value"):
        t.write(0, 5)
    with pytest.raises(DataModelError):
        t.write(0, "12")
    t.write(0, (x for x in (1, 2)))
    t.write(0, [])  # nothing to do
    assert t.read(0, 2) == [1, 2]


def test_slices():
    t = DataBank().holding_registers
    t[10:13] = [1, 2, 3]
    assert t[10:13] == [1, 2, 3]
    assert t.read(10, 3) == [1, 2, 3]
    assert len(t[65530:]) == 6
    with pytest.raises(DataModelError, match="3 addresses but 2 values"):
        t[0:3] = [1, 2]
    with pytest.raises(DataModelError, match="step"):
        t[0:10:2]
    with pytest.raises(DataModelError):
        t[5:2]
    with pytest.raises(IllegalAddressError):
        t[65530:65537]


def test_bank_table_by_name_and_function_code():
    bank = DataBank()
    expected = {
        1: bank.coils,
        2: bank.discrete_inputs,
        3: bank.holding_registers,
        4: bank.input_registers,
        5: bank.coils,
        6: bank.holding_registers,
        15: bank.coils,
        16: bank.holding_registers,
    }
    for fc, table in expected.items():
        assert bank.table(fc) is table
    for kind in TABLE_KINDS:
        assert bank.table(kind) is getattr(bank, kind)
    assert bank.table("Holding Registers") is bank.holding_registers
    for bad in (7, 0, 128, "registers", None, 3.0, True):
        with pytest.raises(DataModelError):
            bank.table(bad)
    assert table_kind(3) == "holding_registers"


def test_pdu_function_codes_work_if_present():
    pdu = pytest.importorskip("modbus_edu.pdu")
    bank = DataBank()
    assert bank.table(pdu.FunctionCode.READ_INPUT_REGISTERS) is bank.input_registers
    assert bank.table(pdu.FunctionCode.WRITE_MULTIPLE_COILS) is bank.coils


def test_dense_tables_are_compact():
    import sys

    bank = DataBank()
    # 64 KiB of bits and 128 KiB of registers per table, not 65536 Python objects
    assert sys.getsizeof(bank.coils._data) < 70_000
    assert sys.getsizeof(bank.holding_registers._data) < 140_000


def test_dense_declare_only_sets():
    t = DataBank().holding_registers
    t.declare(100, 3, 7)
    assert t.read(99, 5) == [0, 7, 7, 7, 0]
    assert t.is_declared(0, 65536)
    assert not t.is_declared(65535, 2)
    assert not t.is_declared(-1)


# --- sparse --------------------------------------------------------------------------------------------
def test_sparse_bank_starts_empty():
    bank = DataBank(sparse=True)
    for t in bank.tables:
        assert len(t) == 0
        assert t.addresses() == []
        with pytest.raises(IllegalAddressError, match="not declared"):
            t.read(0, 1)
    assert "sparse" in repr(bank)


def test_sparse_declare_read_write():
    bank = DataBank(sparse=True)
    hr = bank.holding_registers
    hr.declare(10, 3)
    hr.declare(20, value=99)
    assert hr.addresses() == [10, 11, 12, 20]
    assert len(hr) == 4 and 11 in hr and 13 not in hr
    assert list(hr) == [10, 11, 12, 20]
    assert hr.read(10, 3) == [0, 0, 0]
    assert hr[20] == 99
    hr.write(10, [1, 2, 3])
    assert hr.read(10, 3) == [1, 2, 3]
    assert hr.is_declared(10, 3) and not hr.is_declared(10, 4)
    assert hr.snapshot() == {10: 1, 11: 2, 12: 3, 20: 99}
    assert hr.snapshot(nonzero_only=True) == {10: 1, 11: 2, 12: 3, 20: 99}
    # the other tables are untouched
    assert len(bank.input_registers) == 0


def test_sparse_names_first_undeclared_address():
    hr = DataBank(sparse=True).holding_registers
    hr.declare(10, 3)
    hr.declare(14)
    with pytest.raises(IllegalAddressError) as e:
        hr.read(10, 5)
    assert "holding register address 13 (reference 40014)" in str(e.value)
    assert "exception 02" in str(e.value)
    with pytest.raises(IllegalAddressError, match="address 9 "):
        hr.write(9, [1, 2])
    assert hr.read(10, 1) == [0]  # the failed write changed nothing
    with pytest.raises(IllegalAddressError, match="address 15 "):
        hr[15] = 1
    big = DataBank(sparse=True).input_registers
    with pytest.raises(IllegalAddressError, match=r"input register address 20000 \(reference 320001\)"):
        big[20000]


def test_sparse_declare_with_value_sequence():
    c = DataBank(sparse=True).coils
    c.declare(0, 3, [True, False, True])
    assert c.read(0, 3) == [True, False, True]
    with pytest.raises(DataModelError, match="2 values for 3 addresses"):
        c.declare(5, 3, [True, False])
    with pytest.raises(ValueRangeError):
        c.declare(5, 1, 7)
    assert not c.is_declared(5)


def test_sparse_edges():
    t = DataBank(sparse=True).discrete_inputs
    t.declare(0)
    t.declare(65535)
    t[65535] = True
    assert t.addresses() == [0, 65535]
    assert t.read(65535, 1) == [True]
    with pytest.raises(IllegalAddressError):
        t.declare(65535, 2)


def test_copy_and_equality():
    bank = DataBank(sparse=True)
    bank.add(40001, 5)
    other = bank.copy()
    assert other == bank
    other.set(40001, 6)
    assert other != bank and bank.get(40001) == 5
    assert DataBank() == DataBank()
    assert DataBank() != DataBank(sparse=True)


# --- reference numbers through the bank ----------------------------------------------------------------
def test_bank_add_set_get_like_source_002():
    bank = DataBank(sparse=True)
    assert bank.add(40001) == Reference("holding_registers", 0)
    bank.set(40001, 1234)
    assert bank.get(40001) == 1234
    assert bank.holding_registers[0] == 1234
    bank.add("00308")
    bank.set("00308", True)
    assert bank.coils[307] is True
    bank.add("10005", True)
    assert bank.discrete_inputs.read(4, 1) == [True]
    bank.add(30001, 7)
    assert bank.get("3x1") == 7
    with pytest.raises(IllegalAddressError, match="reference 40002"):
        bank.get(40002)
    with pytest.raises(ReferenceNumberError):
        bank.add(20001)


def test_from_references():
    bank = DataBank.from_references({"40001": 5, "00308": True, 30002: 9}, sparse=True)
    assert bank.snapshot() == {
        "coils": {307: True},
        "discrete_inputs": {},
        "input_registers": {1: 9},
        "holding_registers": {0: 5},
    }
    dense = DataBank.from_references({"40001": 5})
    assert dense.holding_registers.read(0, 2) == [5, 0]


# --- parse_reference / format_reference ------------------------------------------------------------------
@pytest.mark.parametrize(
    "ref,kind,address",
    [
        ("40001", "holding_registers", 0),
        (40001, "holding_registers", 0),
        ("400001", "holding_registers", 0),
        (400001, "holding_registers", 0),
        ("4x0001", "holding_registers", 0),
        ("4x1", "holding_registers", 0),
        ("4X00001", "holding_registers", 0),
        ("00308", "coils", 307),
        (308, "coils", 307),
        ("0x308", "coils", 307),
        ("000308", "coils", 307),
        ("10005", "discrete_inputs", 4),
        ("30001", "input_registers", 0),
        ("39999", "input_registers", 9998),
        ("465536", "holding_registers", 65535),
        ("4x65536", "holding_registers", 65535),
        (165536, "discrete_inputs", 65535),
        ("44098", "holding_registers", 4097),  # source 004: address 0x1001
        ("40108", "holding_registers", 107),
        (" 40001 ", "holding_registers", 0),
        (1, "coils", 0),
    ],
)
def test_parse_reference(ref, kind, address):
    r = parse_reference(ref)
    assert (r.kind, r.address) == (kind, address)
    assert r.number == address + 1
    assert parse_reference(r) is r


@pytest.mark.parametrize(
    "ref,match",
    [
        ("20001", "no 2x table"),
        (20001, "string '020001'"),
        ("50001", "not a table prefix"),
        ("60001", "file records"),
        ("40000", "start at 1"),
        (40000, "start at 1"),
        ("400000", "start at 1"),
        ("465537", r"1\.\.65536"),
        ("4x65537", r"1\.\.65536"),
        ("4x0", "start at 1"),
        ("308", "5 digits"),
        ("4000001", "5 digits"),
        (4000001, "too many digits"),
        (-40001, "not negative"),
        ("4x", "digits"),
        ("4xA", "decimal digits"),
        ("abcde", "digits"),
        ("", "digits"),
        ("4٠٠٠١", "digits"),
        (True, "int or a string"),
        (40001.0, "not float"),
        (None, "not NoneType"),
    ],
)
def test_parse_reference_errors(ref, match):
    with pytest.raises(ReferenceNumberError, match=match) as e:
        parse_reference(ref)
    assert isinstance(e.value, ModbusError)


@pytest.mark.parametrize(
    "kind,address,digits,style,text",
    [
        ("holding_registers", 0, 5, "plain", "40001"),
        ("holding_registers", 0, 6, "plain", "400001"),
        ("holding_registers", 0, 5, "x", "4x0001"),
        ("holding_registers", 0, 6, "x", "4x00001"),
        ("coils", 307, 5, "plain", "00308"),
        ("discrete_inputs", 4, 5, "plain", "10005"),
        ("input_registers", 9998, 5, "plain", "39999"),
        ("input_registers", 65535, 6, "plain", "365536"),
        (3, 107, 5, "plain", "40108"),
    ],
)
def test_format_reference(kind, address, digits, style, text):
    assert format_reference(kind, address, digits=digits, style=style) == text


def test_format_reference_errors():
    with pytest.raises(ReferenceNumberError, match=r"number 10000.*digits=6 -> 410000"):
        format_reference("holding_registers", 9999)
    with pytest.raises(ReferenceNumberError):
        format_reference("holding_registers", 65536, digits=6)
    with pytest.raises(ReferenceNumberError):
        format_reference("holding_registers", -1)
    with pytest.raises(ReferenceNumberError):
        format_reference("registers", 0)
    with pytest.raises(ReferenceNumberError):
        format_reference("coils", 0, digits=4)
    with pytest.raises(ReferenceNumberError):
        format_reference("coils", 0, style="X")


def test_reference_str_and_properties():
    assert str(Reference("holding_registers", 0)) == "40001"
    assert str(Reference("holding_registers", 9999)) == "410000"
    assert Reference("coils", 307).format(style="x") == "0x0308"
    assert Reference("input_registers", 0).prefix == 3
    with pytest.raises(ReferenceNumberError):
        Reference("registers", 0)
    with pytest.raises(ReferenceNumberError):
        Reference("coils", 65536)


kinds = st.sampled_from(TABLE_KINDS)


@settings(max_examples=400, deadline=None)
@given(kinds, st.integers(0, 65535), st.sampled_from([5, 6]), st.sampled_from(["plain", "x"]))
def test_reference_round_trip(kind, address, digits, style):
    if digits == 5 and address > 9998:
        with pytest.raises(ReferenceNumberError):
            format_reference(kind, address, digits=digits, style=style)
        return
    text = format_reference(kind, address, digits=digits, style=style)
    assert parse_reference(text) == Reference(kind, address)
    if style == "plain" and kind != "coils":
        assert parse_reference(int(text)) == Reference(kind, address)


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.integers(-10**7, 10**7), st.text(max_size=8)))
def test_parse_reference_never_leaks_python_errors(ref):
    try:
        r = parse_reference(ref)
    except ReferenceNumberError:
        return
    assert r.kind in TABLE_KINDS and 0 <= r.address <= 65535


@settings(max_examples=200, deadline=None)
@given(
    kinds,
    st.integers(-5, 65540),
    st.lists(st.integers(-2, 70000), max_size=20),
)
def test_table_write_read_never_leaks_python_errors(kind, address, values):
    t = Table(kind)
    try:
        t.write(address, values)
    except (IllegalAddressError, ValueRangeError):
        return
    expected = [bool(v) for v in values] if t.is_bits else values
    assert t.read(address, len(values)) == expected


def test_small_corners():
    bank = DataBank()
    t = bank.holding_registers
    assert repr(t) == "<Table holding_registers (dense, 65536 addresses)>"
    assert repr(bank) == "<DataBank dense: 4 tables x 65536 addresses>"
    assert t != "table" and bank != "bank"
    assert len(t.snapshot(nonzero_only=False)) == 65536
    with pytest.raises(DataModelError, match="slice stop"):
        t[0:"3"]
    with pytest.raises(DataModelError, match="count"):
        t.read(0, True)
    with pytest.raises(ReferenceNumberError, match="must be an int"):
        Reference("coils", 1.0)
    with pytest.raises(IllegalAddressError, match=r"holding register address 70000 is outside"):
        t.declare(70000)


def test_a_register_refuses_a_bool() -> None:
    # True would be stored as 1: a register is a number, not a flag
    bank = DataBank()
    with pytest.raises(ValueRangeError, match="bool"):
        bank.holding_registers.write(0, [1, True])
    assert bank.holding_registers.read(0, 2) == [0, 0]


def test_from_references_takes_a_mapping() -> None:
    with pytest.raises(DataModelError, match="mapping"):
        DataBank.from_references(5)


# --- files (FC 20/21) -----------------------------------------------------------------------------------
def test_a_dense_bank_answers_any_file_and_creates_it_on_first_write():
    bank = mb.DataBank()
    assert bank.files.read(65535, 9998, 2) == [0, 0]
    bank.files.write([(7, 3, [1, 2]), (7, 0, [9])])
    assert bank.files[7] == [9, 0, 0, 1, 2]
    assert bank.files.read(7, 4, 3) == [2, 0, 0]           # past the written end: zeros, as a table


def test_a_sparse_bank_has_only_the_files_put_there():
    from modbus_edu.errors import IllegalAddressError

    bank = mb.DataBank(sparse=True)
    bank.files[4] = [0] * 10
    assert bank.files.read(4, 8, 2) == [0, 0]
    for bad in [(4, 9, 2), (5, 0, 1)]:
        with pytest.raises(IllegalAddressError, match="do not exist"):
            bank.files.read(*bad)
    with pytest.raises(IllegalAddressError):
        bank.files.write([(4, 0, [1]), (5, 0, [1])])
    assert bank.files[4][0] == 0                              # nothing written when one record is refused


def test_file_memory_is_bounded_and_a_full_device_answers_exception_04():
    from modbus_edu.datamodel import FileMemoryError, FileRecords

    files = FileRecords(limit=20_000)
    files.write([(1, 0, [1] * 9_999), (2, 0, [2] * 10_000)])
    with pytest.raises(FileMemoryError, match="at most 20000"):
        files.write([(3, 9_000, [3] * 2)])
    files.write([(1, 0, [5] * 100)])                          # rewriting what exists needs no memory
    slave = mb.Slave(1, mb.DataBank())
    slave.bank.files.limit = 10
    master = mb.Master(mb.loopback_serial(slave))
    master.write_file_record(1, 1, 0, [1] * 10)
    with pytest.raises(mb.ModbusExceptionError) as caught:
        master.write_file_record(1, 2, 0, [1])
    assert caught.value.code == 4 and 2 not in slave.bank.files
