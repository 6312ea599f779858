"""Register maps: CSV loading, clear one-line errors, the poll planner, a simulated device read back."""

from importlib import resources

import pytest

import modbus_edu as mb
from modbus_edu.registermap import (
    MAX_READ_REGISTERS,
    Point,
    RegisterMapError,
    datasheet_to_address,
    load_map,
    plan_polls,
)

ENERGY = resources.files("modbus_edu.devices") / "maps" / "energy_meter_cdab.csv"


def test_energy_meter_map_converts_1_based_numbers():
    m = load_map(ENERGY, numbering="1-based")
    assert m["voltage_l1"].address == 0 and m["voltage_l1"].table == "input"
    assert m["voltage_l1"].order == "CDAB" and m["voltage_l1"].count == 2
    assert m["device_address"].address == 20 and m["device_address"].function == 3


def test_plan_is_fewest_legal_requests():
    m = load_map(ENERGY, numbering="1-based")
    polls = m.plan()
    # input: 0-11 contiguous, 52-53, 70-73 -> three FC4 reads; holding 20 -> one FC3 read
    assert [(p.function, p.address, p.count) for p in polls] == [
        (3, 20, 1),
        (4, 0, 12),
        (4, 52, 2),
        (4, 70, 4),
    ]
    assert [(p.function, p.address, p.count) for p in m.plan(max_gap=100)] == [(3, 20, 1), (4, 0, 74)]


def test_plan_never_exceeds_125_nor_splits_a_point():
    points = [Point(f"p{i}", "holding", 2 * i, "float32") for i in range(100)]
    polls = plan_polls(points)
    assert all(p.count <= MAX_READ_REGISTERS for p in polls)
    assert sum(len(p.points) for p in polls) == 100 and len(polls) == 2
    assert polls[0].count == 124


def test_simulated_device_from_map_read_with_planner():
    m = load_map(ENERGY, numbering="1-based")
    bank = mb.DataBank()
    values = {"voltage_l1": 230.5, "current_l3": 4.25, "frequency": 50.0, "device_address": 7}
    m.store(bank, values)
    link = mb.loopback_serial(mb.Slave(unit=7, bank=bank))
    got = m.read(mb.Master(link), unit=7)
    for k, v in values.items():
        assert got[k] == pytest.approx(v)


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("name,table,address\nx,input,0\n", "header has no 'type' column"),
        ("name,table,address,type\nx,coils,0,uint16\n", "line 2: table 'coils'"),
        ("name,table,address,type\nx,input,zero,uint16\n", "line 2: address 'zero' is not an integer"),
        ("name,table,address,type\nx,input,0,float16\n", "line 2: type 'float16'"),
        ("name,table,address,type,order\nx,input,0,float32,ACBD\n", "order 'ACBD'"),
        ("name,table,address,type\nx,input,0,uint16,9\n", "line 2: 5 fields, the header has 4"),
        ("name,table,address,type\nx,input,0,float32\ny,input,1,uint16\n", "'y' at address 1 overlaps 'x'"),
        ("name,table,address,type\nx,input,0,uint16\nx,input,5,uint16\n", "'x' is defined twice"),
        ("name,table,address,type\nx,input,65535,uint32\n", "runs past address 65535"),
        ("name,table,address,type,colour\nx,input,0,uint16,red\n", "unknown column 'colour'"),
    ],
)
def test_load_errors_are_one_line(text, fragment):
    with pytest.raises(RegisterMapError) as info:
        load_map(text, name="m.csv")
    msg = str(info.value)
    assert fragment in msg and "\n" not in msg and isinstance(info.value, mb.ModbusError)


def test_one_based_zero_is_an_error_and_missing_file():
    with pytest.raises(RegisterMapError, match="line 2: register number 0 .*outside 0..65535"):
        load_map("name,table,address,type\nx,input,0,uint16\n", numbering="1-based")
    with pytest.raises(RegisterMapError, match="cannot read register map"):
        load_map("/nonexistent/map.csv")


def test_datasheet_numbering():
    assert datasheet_to_address(1) == 0
    assert datasheet_to_address(40001, "reference") == 0
    assert datasheet_to_address(30010, "reference") == 9
    assert datasheet_to_address(400001, "reference") == 0
    with pytest.raises(RegisterMapError):
        datasheet_to_address(10001, "reference")


def test_power_meter_map_file_matches_the_meter():
    from modbus_edu.devices import PowerMeter
    from modbus_edu.devices.meter import METER_MAP, power_meter_map, read_meter

    m = power_meter_map()
    assert [(p.name, p.address, p.unit) for p in m] == [(e.name, e.address, e.unit) for e in METER_MAP]
    assert all(p.scale == pytest.approx(1 / e.scale) for p, e in zip(m, METER_MAP))
    master = mb.Master(mb.loopback_serial(PowerMeter(unit=1, trial=1), baudrate=PowerMeter.BAUDRATE))
    from_file = m.read(master, unit=1)
    expected = read_meter(master, unit=1)
    assert from_file == pytest.approx(expected)


# --- files as they come from spreadsheets and from hostile hands -------------------------------------------
_MAP = "name,table,address,type,order,scale,unit\nvoltage,input,0,float32,CDAB,1,V\n"


@pytest.mark.parametrize("prefix", [b"", b"\xef\xbb\xbf"], ids=["utf-8", "utf-8 with BOM"])
def test_utf8_maps_read_with_or_without_a_byte_order_mark(tmp_path, prefix):
    path = tmp_path / "map.csv"
    path.write_bytes(prefix + _MAP.encode())
    assert load_map(path)["voltage"].type == "float32"
    assert load_map("\ufeff" + _MAP)["voltage"].order == "CDAB"


@pytest.mark.parametrize(
    "data, fragment",
    [
        (_MAP.encode("utf-16"), "UTF-16"),
        (_MAP.encode("utf-16-le"), "byte 1 is 00"),
        (_MAP.replace("V\n", "\u00b0C\n").encode("latin-1"), "not UTF-8"),
        (bytes(range(256)) * 4, "byte 0 is 00"),
    ],
    ids=["utf-16 with BOM", "utf-16 without BOM", "latin-1", "binary"],
)
def test_other_encodings_are_refused_by_name(tmp_path, data, fragment):
    path = tmp_path / "map.csv"
    path.write_bytes(data)
    with pytest.raises(RegisterMapError, match=fragment) as info:
        load_map(path)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("length", [201, 5000, 200_000])
def test_an_over_long_field_is_a_clear_error(length):
    text = f"name,table,address,type,order,scale,unit\nvoltage,input,0,float32,CDAB,1,{'V' * length}\n"
    with pytest.raises(RegisterMapError, match=r"line 2: field 7 is|not readable as CSV") as info:
        load_map(text)
    assert len(str(info.value)) < 200


def test_a_duplicated_column_is_refused():
    with pytest.raises(RegisterMapError, match="'unit' appears twice"):
        load_map("name,table,address,type,unit,unit\nvoltage,input,0,uint16,V,V\n")


@pytest.mark.parametrize("scale", ["0", "-0", "inf", "-inf", "nan", "1e308", "-1e308", "5e-324", "1e-320"])
def test_absurd_scales_are_refused_at_load(scale):
    with pytest.raises(RegisterMapError, match="scale"):
        load_map(f"name,table,address,type,scale\nvoltage,input,0,uint16,{scale}\n")


@pytest.mark.parametrize("scale", [0, 0.0, float("nan"), float("inf"), 1e308, 5e-324, True, "1"])
def test_a_point_refuses_an_absurd_scale_so_store_never_divides_by_zero(scale):
    with pytest.raises(RegisterMapError, match="scale"):
        Point("voltage", "input", 0, "uint16", "ABCD", scale)
