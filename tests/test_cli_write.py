"""``modbus-edu write``: every write function, values in every display format poll reads, reference
numbers, a register map's point by name, the read-back; over TCP, RTU and ASCII; and pymodbus as the peer
on both sides (its client reads back what ``write`` wrote; its server is written to)."""

from __future__ import annotations

import socket
import struct

import pytest
from conftest_io import PymodbusServer, pymodbus_device

import modbus_edu as mb
from modbus_edu.cli import main
from modbus_edu.links.serial import SerialServer, TcpSerialPort

pymodbus_client = pytest.importorskip("pymodbus.client")


@pytest.fixture()
def device():
    """A plain device (unit 1) on Modbus/TCP at 127.0.0.1: (its slave, 'host:port')."""
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    with mb.TcpServer([slave]) as server:
        yield slave, f"127.0.0.1:{server.address[1]}"


def write(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(["write", *argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


@pytest.mark.parametrize("args, address, registers, function", [
    (["--address", "40001", "1234"], 0, [1234], "FC 6"),
    (["--address", "4x0002", "7"], 1, [7], "FC 6"),
    (["--address", "400003", "9"], 2, [9], "FC 6"),
    (["--address", "5", "--format", "signed", "--", "-2"], 5, [0xFFFE], "FC 6"),
    (["--address", "6", "--format", "hex", "0xBEEF"], 6, [0xBEEF], "FC 6"),
    (["--address", "7", "--format", "binary", "0000000100000010"], 7, [0x0102], "FC 6"),
    (["--address", "40011", "--format", "float32_ABCD", "123.456"], 10, [0x42F6, 0xE979], "FC 16"),
    (["--address", "40011", "--format", "float32_CDAB", "123.456"], 10, [0xE979, 0x42F6], "FC 16"),
    (["--address", "40011", "--format", "float32_BADC", "123.456"], 10, [0xF642, 0x79E9], "FC 16"),
    (["--address", "40011", "--format", "float32_DCBA", "123.456"], 10, [0x79E9, 0xF642], "FC 16"),
    (["--address", "20", "--format", "int32_CDAB", "--", "-2"], 20, [0xFFFE, 0xFFFF], "FC 16"),
    (["--address", "20", "--format", "uint32_ABCD", "305419896"], 20, [0x1234, 0x5678], "FC 16"),
    (["--address", "30", "--format", "float64_ABCD", "1.5"], 30, [0x3FF8, 0, 0, 0], "FC 16"),
    (["--address", "40", "1", "2", "3"], 40, [1, 2, 3], "FC 16"),
    (["--address", "40", "--function", "16", "5"], 40, [5], "FC 16"),
    (["--address", "50", "--scale", "0.1", "23.5"], 50, [235], "FC 6"),
    (["--address", "50", "--scale", "0.1", "--format", "int32_ABCD", "--", "-1.5"], 50, [0xFFFF, 0xFFF1],
     "FC 16"),
])
def test_write_registers_in_every_format(capsys, device, args, address, registers, function):
    slave, where = device
    code, out, _ = write(capsys, "--tcp", where, *args)
    assert code == 0
    assert slave.bank.holding_registers[address : address + len(registers)] == registers
    assert out.startswith(function + " wrote holding registers at address " + str(address))
    assert "read back:" in out and "differs" not in out


def test_write_coils_single_and_multiple(capsys, device):
    slave, where = device
    assert write(capsys, "--tcp", where, "--address", "00001", "on")[1].startswith("FC 5 wrote coils")
    assert slave.bank.coils[0] is True
    code, out, _ = write(capsys, "--tcp", where, "--address", "00011", "1", "0", "1", "true")
    assert code == 0 and out.startswith("FC 15 wrote coils at address 10: 1 0 1 1")
    assert slave.bank.coils[10:14] == [True, False, True, True]
    assert "read back: 1 0 1 1" in out
    code, out, _ = write(capsys, "--tcp", where, "--function", "5", "--address", "3", "off")
    assert code == 0 and slave.bank.coils[3] is False


def test_write_mask_and_read_write(capsys, device):
    slave, where = device
    slave.bank.holding_registers[4] = 0x1234
    code, out, _ = write(capsys, "--tcp", where, "--function", "22", "--address", "40005", "0xF0F0", "0x0005")
    assert code == 0 and slave.bank.holding_registers[4] == (0x1234 & 0xF0F0) | (0x0005 & ~0xF0F0 & 0xFFFF)
    code, out, _ = write(capsys, "--tcp", where, "--function", "23", "--address", "40101", "8", "9")
    assert code == 0 and slave.bank.holding_registers[100:102] == [8, 9]
    assert "FC 23 wrote 2 and read 2 holding registers at address 100: 8 9" in out


def test_write_a_map_point_by_name(capsys, device, tmp_path):
    slave, where = device
    path = tmp_path / "plant.csv"
    path.write_text("# numbering: reference\nname,table,address,type,order,scale,unit\n"
                    "setpoint,holding,40021,int16,ABCD,0.1,degC\nflow,input,30001,float32,CDAB,1,m3/h\n")
    code, out, _ = write(capsys, "--tcp", where, "--map", str(path), "setpoint=21.5")
    assert code == 0 and slave.bank.holding_registers[20] == 215
    code, _, err = write(capsys, "--tcp", where, "--map", str(path), "flow=3")
    assert code == 1 and "read-only" in err
    code, _, err = write(capsys, "--tcp", where, "--map", str(path), "nosuch=3")
    assert code == 1 and "no point named 'nosuch'" in err


def test_the_read_back_that_differs_fails():
    class Clamping(mb.Slave):
        def handle(self, frame, mode="rtu"):
            answer = super().handle(frame, mode)
            if self.bank.holding_registers[0] > 100:
                self.bank.holding_registers[0] = 100  # a device that limits what it is given
            return answer

    clamp = Clamping(unit=1, bank=mb.DataBank())
    with mb.TcpServer([clamp]) as server:
        assert main(["write", "--tcp", f"127.0.0.1:{server.address[1]}", "--address", "40001", "500"]) == 1


@pytest.mark.parametrize("args, message", [
    (["--address", "30001", "1"], "read-only"),
    (["--address", "10001", "1"], "read-only"),
    (["--address", "40001", "--function", "5", "1"],
     "is a reference to the holding registers, but --function 5"),
    (["--address", "00001", "--function", "6", "1"], "is a reference to the coils, but --function 6"),
    (["--address", "0", "--function", "3", "1"], "write uses --function 5, 6, 15, 16, 22 or 23"),
    (["--address", "0", "--function", "6", "1", "2"], "FC 6 writes one register"),
    (["--address", "0", "--format", "float32_ABCD", "x"], "is not a float32_ABCD value"),
    (["--address", "0", "70000"], "0..65535"),
    (["--address", "40000", "1"], "element numbers start at 1"),
    (["--address", "0", "--format", "int16_XYZW", "1"], "unknown --format"),
    (["1"], "give --address"),
    (["--address", "00001", "maybe"], "on/off"),
    (["--address", "0", "--function", "22", "1"], "two values"),
])
def test_write_bad_input_is_one_line(capsys, args, message):
    code = main(["write", "--tcp", f"127.0.0.1:{_closed_port()}", *args])
    err = capsys.readouterr().err
    assert code == 1, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("modbus-edu: error: ") and message in lines[0], err


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("mode", ["rtu", "ascii"])
def test_write_over_a_serial_url(capsys, mode):
    slave = mb.Slave(unit=7, bank=mb.DataBank())
    parity = "E" if mode == "ascii" else "N"  # write's default: 7E1 for ASCII, 8N1 for RTU
    with SerialServer([slave], TcpSerialPort("127.0.0.1", 0), baudrate=19200, parity=parity,
                      mode=mode) as server:
        host, port = server.port.address
        code, out, err = write(capsys, "--serial", f"socket://{host}:{port}", "--mode", mode, "--baud",
                               "19200", "--unit", "7", "--address", "40003", "--format", "float32_CDAB",
                               "--timeout", "2", "--retries", "1", "2.5")
    assert code == 0, err
    assert slave.bank.holding_registers[2:4] == list(mb.values.encode_value(2.5, "float32", "CDAB"))
    assert "read back: 2.5" in out


def test_pymodbus_client_reads_back_what_write_wrote(capsys, device):
    slave, where = device
    host, port = where.split(":")
    assert write(capsys, "--tcp", where, "--address", "40001", "--format", "float32_ABCD", "230.5")[0] == 0
    assert write(capsys, "--tcp", where, "--address", "00005", "on")[0] == 0
    client = pymodbus_client.ModbusTcpClient(host, port=int(port))
    try:
        assert client.connect()
        regs = client.read_holding_registers(0, count=2, device_id=1).registers
        assert struct.unpack(">f", struct.pack(">HH", *regs))[0] == 230.5
        assert client.read_coils(4, count=1, device_id=1).bits[0] is True
    finally:
        client.close()


@pytest.mark.parametrize("framer, wire", [("tcp", "--tcp"), ("rtu", "--serial"), ("ascii", "--serial")])
def test_write_to_a_pymodbus_server(capsys, framer, wire):
    """pymodbus's server is the peer: write (over MBAP, or RTU/ASCII carried over TCP), and pymodbus's
    own client reads the value back."""
    with PymodbusServer(pymodbus_device(1), framer=framer) as server:
        target = f"127.0.0.1:{server.port}" if wire == "--tcp" else f"socket://127.0.0.1:{server.port}"
        extra = [] if wire == "--tcp" else ["--mode", framer]
        code, out, err = write(capsys, wire, target, *extra, "--address", "40011", "--format", "int32_CDAB",
                               "--timeout", "2", "100000")
        assert code == 0, err
        assert "read back: 100000" in out
        code, out, err = write(capsys, wire, target, *extra, "--address", "00003", "on", "--timeout", "2")
        assert code == 0, err
        if framer == "tcp":
            client = pymodbus_client.ModbusTcpClient("127.0.0.1", port=server.port)
            try:
                assert client.connect()
                regs = client.read_holding_registers(10, count=2, device_id=1).registers
                assert mb.values.decode_value(regs, "int32", "CDAB") == 100000
                assert client.read_coils(2, count=1, device_id=1).bits[0] is True
            finally:
                client.close()
