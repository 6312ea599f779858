"""The Contract section of DESIGN.md: every name exists where it says, with the behaviour it describes.

Checks outside the repository rely on these names, so this file is the inside copy of that promise.
Two kinds of test:

* ``test_public_name`` -- the name is reachable as the contract spells it (``mb.X``,
  ``modbus_edu.devices.PowerMeter``, ``modbus_edu.widgets.X``);
* behaviour tests -- what the contract says the name does.  They find a name through :func:`api`, which
  prefers ``mb.X`` and falls back to the submodule that defines it, so behaviour is checked even while
  ``__init__`` does not re-export a name yet (``test_public_name`` reports that separately).
"""

from __future__ import annotations

import importlib
import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import modbus_edu as mb

ROOT = Path(__file__).resolve().parent.parent

PDU_CLASSES = {
    "ReadCoilsRequest": ("address", "count"), "ReadCoilsResponse": ("bits",),
    "ReadDiscreteInputsRequest": ("address", "count"), "ReadDiscreteInputsResponse": ("bits",),
    "ReadHoldingRegistersRequest": ("address", "count"), "ReadHoldingRegistersResponse": ("registers",),
    "ReadInputRegistersRequest": ("address", "count"), "ReadInputRegistersResponse": ("registers",),
    "WriteSingleCoilRequest": ("address", "value"), "WriteSingleCoilResponse": ("address", "value"),
    "WriteSingleRegisterRequest": ("address", "value"), "WriteSingleRegisterResponse": ("address", "value"),
    "WriteMultipleCoilsRequest": ("address", "values"), "WriteMultipleCoilsResponse": ("address", "count"),
    "WriteMultipleRegistersRequest": ("address", "values"),
    "WriteMultipleRegistersResponse": ("address", "count"),
    "ExceptionResponse": ("function", "code"),
}

CORE_NAMES = ["crc16", "lrc", "ModbusError", "ModbusExceptionError", *PDU_CLASSES, "RtuFrame", "AsciiFrame",
              "TcpFrame", "DataBank"]
# names that belong to the roles, links, devices and widgets work
LATER_NAMES = ["Slave", "Master", "TcpServer", "tcp_link", "serial_link", "loopback_serial"]
WIDGETS = ["FrameBuilder", "FrameDecoder", "CrcExplorer", "TestTool", "MeterDashboard"]

_HOMES = ("modbus_edu.crc", "modbus_edu.pdu", "modbus_edu.framing", "modbus_edu.errors",
          "modbus_edu.datamodel", "modbus_edu.slave", "modbus_edu.master", "modbus_edu.links",
          "modbus_edu.links.tcp", "modbus_edu.links.serial")


def api(name: str):
    """``mb.<name>``, else the submodule that defines it (see the module docstring)."""
    if hasattr(mb, name):
        return getattr(mb, name)
    for module_name in _HOMES:
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        if hasattr(module, name):
            return getattr(module, name)
    pytest.fail(f"modbus_edu has no {name!r} anywhere")


# --- the names --------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", CORE_NAMES + LATER_NAMES)
def test_public_name(name: str) -> None:
    assert hasattr(mb, name), f"mb.{name} is part of the contract: re-export it from modbus_edu/__init__.py"


def test_devices_power_meter_name() -> None:
    from modbus_edu.devices import PowerMeter  # noqa: F401


@pytest.mark.parametrize("name", WIDGETS)
def test_widget_name(name: str) -> None:
    widgets = importlib.import_module("modbus_edu.widgets")
    assert hasattr(widgets, name), f"modbus_edu.widgets.{name} is part of the contract"


# --- checksums and errors ---------------------------------------------------------------------------
def test_crc16_and_lrc() -> None:
    assert api("crc16")(b"123456789") == 0x4B37
    assert api("crc16")(b"123456789").to_bytes(2, "little") == b"\x37\x4b"
    assert api("lrc")(bytes.fromhex("050610010200")) == 0xE2


def test_modbus_error_is_the_base_of_every_library_error() -> None:
    errors = importlib.import_module("modbus_edu.errors")
    ModbusError = api("ModbusError")
    assert issubclass(ModbusError, Exception)
    classes = [obj for obj in vars(errors).values() if inspect.isclass(obj) and issubclass(obj, Exception)
               and obj.__module__ == errors.__name__]
    assert len(classes) > 10
    for cls in classes:
        assert issubclass(cls, ModbusError), cls
    assert issubclass(api("ModbusExceptionError"), ModbusError)


# --- PDUs -------------------------------------------------------------------------------------------
T, F = True, False
EXAMPLES = {
    "ReadCoilsRequest": ({"address": 19, "count": 37}, "01 00 13 00 25"),
    "ReadCoilsResponse": ({"bits": [T, F, T, T, F, F, T, T]}, "01 01 CD"),
    "ReadDiscreteInputsRequest": ({"address": 196, "count": 22}, "02 00 C4 00 16"),
    "ReadDiscreteInputsResponse": ({"bits": [F, F, T, T, F, T, F, T]}, "02 01 AC"),
    "ReadHoldingRegistersRequest": ({"address": 107, "count": 3}, "03 00 6B 00 03"),
    "ReadHoldingRegistersResponse": ({"registers": [0x022B, 0, 100]}, "03 06 02 2B 00 00 00 64"),
    "ReadInputRegistersRequest": ({"address": 8, "count": 1}, "04 00 08 00 01"),
    "ReadInputRegistersResponse": ({"registers": [10]}, "04 02 00 0A"),
    "WriteSingleCoilRequest": ({"address": 172, "value": True}, "05 00 AC FF 00"),
    "WriteSingleCoilResponse": ({"address": 172, "value": False}, "05 00 AC 00 00"),
    "WriteSingleRegisterRequest": ({"address": 1, "value": 3}, "06 00 01 00 03"),
    "WriteSingleRegisterResponse": ({"address": 1, "value": 3}, "06 00 01 00 03"),
    "WriteMultipleCoilsRequest": ({"address": 19, "values": [T, F, T, T, F, F, T, T, T, F]},
                                  "0F 00 13 00 0A 02 CD 01"),
    "WriteMultipleCoilsResponse": ({"address": 19, "count": 10}, "0F 00 13 00 0A"),
    "WriteMultipleRegistersRequest": ({"address": 1, "values": [10, 258]}, "10 00 01 00 02 04 00 0A 01 02"),
    "WriteMultipleRegistersResponse": ({"address": 1, "count": 2}, "10 00 01 00 02"),
    "ExceptionResponse": ({"function": 3, "code": 2}, "83 02"),
}


@pytest.mark.parametrize("name", list(PDU_CLASSES))
def test_pdu_classes_take_the_spec_fields_as_keywords(name: str) -> None:
    cls = api(name)
    kwargs, wire = EXAMPLES[name]
    assert tuple(kwargs) == PDU_CLASSES[name]
    pdu = cls(**kwargs)
    encoded = pdu.encode()
    assert isinstance(encoded, bytes)
    assert encoded == bytes.fromhex(wire)
    assert encoded[0] == pdu.function_code  # function code first
    # == compares by value
    assert pdu == cls(**kwargs)
    if name == "ExceptionResponse":
        assert pdu != cls(function=3, code=3)
    for field in PDU_CLASSES[name]:
        assert hasattr(pdu, field)


def test_coils_are_bools_and_registers_are_ints() -> None:
    coil = api("WriteSingleCoilRequest")(address=172, value=True)
    assert coil.value is True
    assert coil.encode()[3:5] == b"\xff\x00"  # a single coil goes on the wire as FF 00 / 00 00
    assert api("WriteSingleCoilRequest")(address=172, value=False).encode()[3:5] == b"\x00\x00"
    bits = api("ReadCoilsResponse")(bits=[1, 0, 1]).bits
    assert all(type(b) is bool for b in bits)
    registers = api("ReadHoldingRegistersResponse")(registers=[0, 65535]).registers
    assert all(type(r) is int for r in registers)
    with pytest.raises(api("ModbusError")):
        api("ReadHoldingRegistersResponse")(registers=[65536])
    with pytest.raises(api("ModbusError")):
        api("WriteSingleRegisterRequest")(address=0, value=-1)


def test_read_bits_response_decoded_from_bytes_holds_the_padding() -> None:
    frame = api("RtuFrame")(unit=1, pdu=api("ReadCoilsResponse")(bits=[True, False, True])).encode()
    decoded = api("RtuFrame").decode(frame, role="response").pdu
    assert len(decoded.bits) == 8  # 8 x byte count, padding included
    assert decoded.bits == (True, False, True, False, False, False, False, False)


# --- frames -----------------------------------------------------------------------------------------
def test_frames() -> None:
    request = api("ReadHoldingRegistersRequest")(address=0, count=1)
    rtu = api("RtuFrame")(unit=1, pdu=request).encode()
    assert rtu == bytes.fromhex("010300000001840A")
    assert api("RtuFrame").decode(rtu, role="request").pdu == request
    write = api("WriteSingleRegisterRequest")(address=0x1001, value=0x200)
    ascii_frame = api("AsciiFrame")(unit=5, pdu=write)
    assert ascii_frame.encode() == b":050610010200E2\r\n"
    assert api("AsciiFrame").decode(b":050610010200E2\r\n", role="response").unit == 5
    tcp = api("TcpFrame")(transaction_id=0x0118, unit=1, pdu=request).encode()
    assert tcp == bytes.fromhex("011800000006010300000001")
    response = api("TcpFrame").decode(bytes.fromhex("01180000000501030204D2"), role="response")
    assert (response.transaction_id, response.unit, response.pdu.registers) == (0x0118, 1, (1234,))


@pytest.mark.parametrize("name", ["RtuFrame", "AsciiFrame", "TcpFrame"])
def test_frame_decode_role_keyword(name: str) -> None:
    cls = api(name)
    assert inspect.signature(cls.decode).parameters["role"].default in ("request", inspect.Parameter.empty)
    with pytest.raises(api("ModbusError")):
        cls.decode(b"\x01\x03", role="request")


# --- the data bank and the slave ----------------------------------------------------------------------
def test_databank_is_dense_and_zeroed() -> None:
    bank = api("DataBank")()
    for kind in ("coils", "discrete_inputs", "input_registers", "holding_registers"):
        table = getattr(bank, kind)
        assert list(table.read(0, 4)) in ([0, 0, 0, 0], [False] * 4)
        assert list(table.read(65535, 1)) in ([0], [False])
        assert list(table.read(30000, 2)) in ([0, 0], [False] * 2)


def _slave_with_value():
    bank = api("DataBank")()
    bank.holding_registers.write(0, [1234, 5678])
    return api("Slave")(unit=1, bank=bank), bank


@pytest.mark.parametrize("mode", ["rtu", "ascii", "tcp"])
def test_slave_handle(mode: str) -> None:
    slave, bank = _slave_with_value()
    request_pdu = api("ReadHoldingRegistersRequest")(address=0, count=2)
    if mode == "tcp":
        request = api("TcpFrame")(transaction_id=7, unit=1, pdu=request_pdu).encode()
        frame_cls = api("TcpFrame")
    else:
        frame_cls = api("RtuFrame") if mode == "rtu" else api("AsciiFrame")
        request = frame_cls(unit=1, pdu=request_pdu).encode()
    answer = slave.handle(request, mode=mode)
    assert isinstance(answer, bytes)
    response = frame_cls.decode(answer, role="response")
    assert response.unit == 1
    assert response.pdu.registers == (1234, 5678)
    if mode == "tcp":
        assert response.transaction_id == 7
    # another unit: no answer
    if mode == "tcp":
        other = api("TcpFrame")(transaction_id=7, unit=2, pdu=request_pdu).encode()
    else:
        other = frame_cls(unit=2, pdu=request_pdu).encode()
    assert slave.handle(other, mode=mode) is None


def test_slave_broadcast_acts_and_never_answers() -> None:
    slave, bank = _slave_with_value()
    write = api("RtuFrame")(unit=0, pdu=api("WriteSingleRegisterRequest")(address=5, value=42)).encode()
    assert slave.handle(write, mode="rtu") is None
    assert list(bank.holding_registers.read(5, 1)) == [42]


def test_slave_exception_response() -> None:
    bank = api("DataBank")(sparse=True)
    bank.holding_registers.declare(0, 2)
    slave = api("Slave")(unit=1, bank=bank)
    request = api("RtuFrame")(unit=1, pdu=api("ReadHoldingRegistersRequest")(address=100, count=1)).encode()
    answer = api("RtuFrame").decode(slave.handle(request, mode="rtu"), role="response")
    assert answer.pdu == api("ExceptionResponse")(function=3, code=2)  # illegal data address


# --- master over the loopback wire ----------------------------------------------------------------------
def test_master_over_loopback_serial() -> None:
    slave, bank = _slave_with_value()
    link = api("loopback_serial")([slave], baudrate=9600, parity="N", stopbits=1, mode="rtu")
    master = api("Master")(link)
    assert master.read_holding_registers(unit=1, address=0, count=2) == [1234, 5678]
    master.write_single_register(unit=1, address=10, value=7)
    master.write_multiple_registers(unit=1, address=11, values=[8, 9])
    assert master.read_holding_registers(unit=1, address=10, count=3) == [7, 8, 9]
    master.write_single_coil(unit=1, address=3, value=True)
    master.write_multiple_coils(unit=1, address=4, values=[True, False, True])
    assert master.read_coils(unit=1, address=3, count=4) == [True, True, False, True]
    assert master.read_discrete_inputs(unit=1, address=0, count=2) == [False, False]
    assert master.read_input_registers(unit=1, address=0, count=2) == [0, 0]
    assert isinstance(link.clock.now, float) and link.clock.now > 0


def test_loopback_timing_is_the_arithmetic_of_the_design() -> None:
    # FC3 for 1 register at 9600 8N1: (8 + 3.5 + 7 + 3.5) x 10 / 9600 s per transaction
    slave, _ = _slave_with_value()
    link = api("loopback_serial")([slave], baudrate=9600, parity="N", stopbits=1, mode="rtu")
    master = api("Master")(link)
    times = []
    for _ in range(11):
        master.read_holding_registers(unit=1, address=0, count=1)
        times.append(link.clock.now)
    per_transaction = (times[-1] - times[0]) / 10
    assert per_transaction == pytest.approx((8 + 3.5 + 7 + 3.5) * 10 / 9600, rel=1e-9)


def test_master_raises_on_exception_responses() -> None:
    bank = api("DataBank")(sparse=True)
    bank.holding_registers.declare(0, 2)
    slave = api("Slave")(unit=1, bank=bank)
    master = api("Master")(api("loopback_serial")([slave], mode="rtu"))
    assert master.read_holding_registers(unit=1, address=0, count=2) == [0, 0]
    with pytest.raises(api("ModbusExceptionError")) as info:
        master.read_holding_registers(unit=1, address=100, count=1)
    assert info.value.code == 2


def test_loopback_serial_ascii() -> None:
    slave, _ = _slave_with_value()
    master = api("Master")(api("loopback_serial")([slave], mode="ascii"))
    assert master.read_holding_registers(unit=1, address=0, count=1) == [1234]


# --- real sockets and ports -------------------------------------------------------------------------
def test_tcp_server_and_tcp_link() -> None:
    slave, _ = _slave_with_value()
    with api("TcpServer")([slave], host="127.0.0.1", port=0) as server:
        host, port = server.address
        assert host == "127.0.0.1" and port > 0
        link = api("tcp_link")(host, port)
        try:
            master = api("Master")(link)
            assert master.read_holding_registers(unit=1, address=0, count=2) == [1234, 5678]
        finally:
            link.close()


def test_serial_link_through_a_pyserial_url() -> None:
    link = api("serial_link")("loop://", baudrate=19200, parity="E", stopbits=1, mode="rtu")
    try:
        assert link.mode == "rtu"
    finally:
        link.close()


# --- the power meter ---------------------------------------------------------------------------------
@pytest.mark.parametrize(("trial", "vl1", "al1"), [(1, 403.6, 304.9), (2, 412.6, 288.9)])
def test_power_meter(trial: int, vl1: float, al1: float) -> None:
    from modbus_edu.devices import PowerMeter

    meter = PowerMeter(unit=1, trial=trial)
    assert isinstance(meter, api("Slave"))  # devices are Slaves
    master = api("Master")(api("loopback_serial")([meter], baudrate=19200, mode="rtu"))
    for address, expected, factor in ((0x00, vl1, 10), (0x02, al1, 1000)):
        high, low = master.read_holding_registers(unit=1, address=address, count=2)
        raw = round(expected * factor)
        assert raw in ((high << 16) | low, (low << 16) | high)


# --- widgets -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", WIDGETS)
def test_widgets_are_ipywidgets(name: str) -> None:
    ipywidgets = pytest.importorskip("ipywidgets")
    widgets = importlib.import_module("modbus_edu.widgets")
    widget = getattr(widgets, name)()
    assert isinstance(widget, ipywidgets.Widget)
    if name in ("FrameBuilder", "FrameDecoder"):
        assert isinstance(widget.frame, bytes)


# --- the command line ---------------------------------------------------------------------------------
def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "modbus_edu", *args], capture_output=True, text=True,
                          timeout=60, cwd=ROOT)


def test_cli_crc_and_lrc() -> None:
    crc = run_cli("crc", "31 32 33 34 35 36 37 38 39")
    assert crc.returncode == 0, crc.stderr
    assert "4B37" in crc.stdout.upper()
    lrc = run_cli("lrc", "05 06 10 01 02 00")
    assert lrc.returncode == 0, lrc.stderr
    assert "E2" in lrc.stdout.upper()


@pytest.mark.parametrize("command", ["crc", "lrc", "decode", "build", "serve", "poll"])
def test_cli_subcommands_exist(command: str) -> None:
    result = run_cli(command, "--help")
    assert result.returncode == 0, result.stderr
    assert command in result.stdout


@pytest.mark.parametrize("args", [("decode", "zz"), ("crc", "0x"), ("decode", "01 03 00 00 00 01 85 0A")])
def test_cli_errors_are_one_line_without_traceback(args) -> None:
    result = run_cli(*args)
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr


def test_cli_is_installed_as_modbus_edu() -> None:
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert project["project"]["scripts"]["modbus-edu"].startswith("modbus_edu")
