"""RTU and ASCII over real byte streams, against pymodbus 3.16 and against ourselves.

A serial line carried over TCP (pyserial's ``socket://``) has no line timing: frames are cut by their
expected length (RTU) or by ``:`` .. CR LF (ASCII), exactly as the links do on a real port.

* our Master over ``serial_link("socket://...")`` -> a pymodbus server with the RTU / ASCII framer;
* a pymodbus client with the RTU / ASCII framer -> our :class:`SerialServer` on a :class:`TcpSerialPort`;
* our Master -> our SerialServer over the same kind of line;
* ``loop://`` (pyserial's loopback) for the framing of send / receive.
"""

from __future__ import annotations

import pytest
from conftest_io import FRAMERS, HOST, MAX_ALLOWED_VALUE, SIZE, PymodbusServer, pymodbus_device
from pymodbus.client import ModbusTcpClient
from pymodbus.pdu import ExceptionResponse as PymodbusException

from modbus_edu.errors import ConfigError, LinkError, ModbusExceptionError, ModbusTimeoutError
from modbus_edu.framing import AsciiFrame, RtuFrame
from modbus_edu.links.serial import SerialServer, TcpSerialPort, serial_link
from modbus_edu.master import Master
from modbus_edu.pdu import ReadHoldingRegistersResponse, WriteSingleRegisterRequest
from modbus_edu.slave import Slave

MODES = ("rtu", "ascii")


def _exercise_all_eight(master: Master, unit: int = 1) -> None:
    master.write_single_register(unit=unit, address=5, value=4321)                       # FC 6
    master.write_multiple_registers(unit=unit, address=10, values=[1, 2, 3, 40000])      # FC 16
    assert master.read_holding_registers(unit=unit, address=5, count=1) == [4321]        # FC 3
    assert master.read_holding_registers(unit=unit, address=10, count=4) == [1, 2, 3, 40000]
    master.write_single_coil(unit=unit, address=2, value=True)                           # FC 5
    master.write_multiple_coils(unit=unit, address=8, values=[True, True, False, True])  # FC 15
    assert master.read_coils(unit=unit, address=0, count=3) == [False, False, True]      # FC 1
    assert master.read_coils(unit=unit, address=8, count=4) == [True, True, False, True]


# --- our master -> pymodbus server (RTU / ASCII framer on a TCP port) ---------------------------------
@pytest.mark.parametrize("mode", MODES)
def test_master_over_socket_url_drives_pymodbus_serial_server(mode):
    device = pymodbus_device(1, discrete=[True, False, True], inputs=[11, 22, 33])
    with PymodbusServer(device, framer=mode) as server:
        with serial_link(f"socket://{HOST}:{server.port}", 19200, "E", 1, mode=mode) as link:
            assert link.mode == mode
            # no line timing over a socket: frames are cut by length / delimiters, silence is a backstop
            assert link.frame_gap == (1.0 if mode == "ascii" else pytest.approx(3.5 * 11 / 19200 + 0.1))
            master = Master(link, timeout=2.0)
            _exercise_all_eight(master)
            assert master.read_discrete_inputs(unit=1, address=0, count=3) == [True, False, True]  # FC 2
            assert master.read_input_registers(unit=1, address=0, count=3) == [11, 22, 33]         # FC 4
            with pytest.raises(ModbusExceptionError) as info:
                master.read_input_registers(unit=1, address=SIZE - 1, count=2)
            assert info.value.code == 0x02
            with pytest.raises(ModbusExceptionError) as info:
                master.write_single_register(unit=1, address=0, value=MAX_ALLOWED_VALUE + 1)
            assert info.value.code == 0x03
            assert master.stats.checksum_errors == 0 and master.stats.timeouts == 0


# --- pymodbus client (RTU / ASCII framer) -> our SerialServer -------------------------------------------
@pytest.mark.parametrize("mode", MODES)
def test_pymodbus_serial_client_drives_our_serial_server(mode):
    slave = Slave(unit=3)
    for i in range(4):
        slave.bank.input_registers[i] = 100 * i
        slave.bank.discrete_inputs[i] = bool(i & 1)
    with SerialServer(slave, TcpSerialPort(HOST, 0), mode=mode) as server:
        port = server.port.address[1]
        client = ModbusTcpClient(HOST, port=port, framer=FRAMERS[mode], timeout=2, retries=0)
        assert client.connect()
        try:
            assert not client.write_coil(1, True, device_id=3).isError()                    # FC 5
            assert not client.write_coils(4, [True, False, True], device_id=3).isError()    # FC 15
            assert client.read_coils(0, count=7, device_id=3).bits[:7] == [                  # FC 1
                False, True, False, False, True, False, True]
            assert client.read_discrete_inputs(0, count=4, device_id=3).bits[:4] == [       # FC 2
                False, True, False, True]
            assert not client.write_register(9, 999, device_id=3).isError()                 # FC 6
            assert not client.write_registers(20, [5, 6, 7], device_id=3).isError()         # FC 16
            assert client.read_holding_registers(9, count=1, device_id=3).registers == [999]  # FC 3
            assert client.read_holding_registers(20, count=3, device_id=3).registers == [5, 6, 7]
            assert client.read_input_registers(0, count=4, device_id=3).registers == [      # FC 4
                0, 100, 200, 300]
            bad = client.read_holding_registers(65535, count=2, device_id=3)  # runs past 65535
            assert isinstance(bad, PymodbusException) and bad.exception_code == 0x02
            assert client.read_exception_status(device_id=3).status == 0  # FC 7: nothing to report
            bad = client.diag_getclear_modbus_response(device_id=3)  # FC 8/0x15 (Modbus Plus): not here
            assert isinstance(bad, PymodbusException) and bad.exception_code == 0x01
        finally:
            client.close()
    assert slave.bank.holding_registers.read(20, 3) == [5, 6, 7]
    assert server.counters.responses == 12
    assert slave.counters.checksum_errors == 0


# --- our master -> our serial server -------------------------------------------------------------------
@pytest.mark.parametrize("mode", MODES)
def test_master_and_serial_server_over_a_tcp_carried_line(mode):
    a, b = Slave(unit=1), Slave(unit=2)
    b.bank.holding_registers[0] = 0xB0B
    with SerialServer([a, b], TcpSerialPort(HOST, 0), mode=mode) as server:
        host, port = server.port.address
        with serial_link(f"socket://{host}:{port}", mode=mode) as link:
            master = Master(link, timeout=1.0)
            _exercise_all_eight(master, unit=1)
            assert master.read_holding_registers(unit=2, address=0, count=1) == [0xB0B]
            # a unit nobody serves: on a serial bus nobody answers, the master times out
            master.timeout = 0.2
            with pytest.raises(ModbusTimeoutError):
                master.read_holding_registers(unit=7, address=0, count=1)
            assert server.counters.no_slave == 1
            # broadcast: both slaves write, nobody answers
            master.write_single_register(unit=0, address=100, value=77)
            master.timeout = 1.0
            assert master.read_holding_registers(unit=2, address=100, count=1) == [77]
            assert a.bank.holding_registers[100] == 77


def test_rtu_master_skips_junk_on_the_line():
    """Noise before a response: the RTU splitter drops bytes until a frame's CRC checks."""
    slave = Slave(unit=1)
    slave.bank.holding_registers[0] = 1234
    with SerialServer(slave, TcpSerialPort(HOST, 0), mode="rtu") as server:
        host, port = server.port.address
        with serial_link(f"socket://{host}:{port}", mode="rtu") as link:
            master = Master(link, timeout=1.0)
            assert master.read_holding_registers(unit=1, address=0, count=1) == [1234]
            # junk sent from the slave's side (as noise would be) ahead of the next response
            server.port.write(b"\xff\x00\x13")
            assert master.read_holding_registers(unit=1, address=0, count=1) == [1234]


# --- loop:// -------------------------------------------------------------------------------------------
def test_loop_url_rtu_frames_come_back_whole():
    response = RtuFrame(unit=1, pdu=ReadHoldingRegistersResponse(registers=(1, 2, 3))).encode()
    with serial_link("loop://", 115200, mode="rtu") as link:
        assert "115200 baud 8N1" in link.description
        assert link.receive(0) is None
        link.send(response)
        assert link.receive(1.0) == response
        assert link.receive(0) is None
        # two frames written back to back are cut apart by their lengths
        link.send(response + response)
        assert link.receive(1.0) == response
        assert link.receive(1.0) == response
        # junk in front of a frame is skipped and counted
        link.send(b"\x00\xfe" + response)
        assert link.receive(1.0) == response
        assert link.discarded == 2


def test_loop_url_ascii_frames_and_a_request_role():
    request = AsciiFrame(unit=5, pdu=WriteSingleRegisterRequest(address=0x1001, value=0x0200)).encode()
    assert request == b":050610010200E2\r\n"  # source 004's exchange
    with serial_link("loop://", 9600, "E", 1, mode="ascii", role="request") as link:
        assert "7E1" in link.description  # ASCII: 7 data bits unless told otherwise
        link.send(b"noise" + request)
        assert link.receive(1.0) == request


def test_loop_url_receive_times_out_with_none():
    with serial_link("loop://", mode="rtu") as link:
        assert link.receive(0.05) is None
        link.send(b"\x01\x03")  # half a frame never completes
        assert link.receive(0.05) is None
    with pytest.raises(LinkError, match="closed"):
        link.receive(0)


# --- errors that teach ------------------------------------------------------------------------------------
def test_bad_settings_are_config_errors():
    with pytest.raises(ConfigError, match="'rtu' or 'ascii'"):
        serial_link("loop://", mode="tcp")
    with pytest.raises(ConfigError, match="parity"):
        serial_link("loop://", parity="X")
    with pytest.raises(ConfigError, match="baudrate"):
        serial_link("loop://", baudrate=0)
    with pytest.raises(ConfigError, match="RTU needs 8 data bits"):
        serial_link("loop://", bytesize=7, mode="rtu")


def test_missing_port_is_a_link_error():
    with pytest.raises(LinkError, match="cannot open serial port '/dev/modbus_edu_no_such_port'"):
        serial_link("/dev/modbus_edu_no_such_port")


def test_socket_url_with_nobody_listening_is_a_link_error():
    port = TcpSerialPort(HOST, 0)
    free = port.address[1]
    port.close()
    with pytest.raises(LinkError, match="is a server listening there"):
        serial_link(f"socket://{HOST}:{free}")


def test_real_port_silence_rule_uses_t35_plus_latency():
    # not opened: the rule is computed from the settings only
    from modbus_edu.links.serial import _frame_gap, _timing

    t = _timing(9600, "N", 1, "rtu", None)
    assert _frame_gap("/dev/ttyUSB0", t, 0.0) == pytest.approx(3.5 * 10 / 9600)
    assert _frame_gap("COM3", _timing(115200, "N", 1, "rtu", None), 0.0) == pytest.approx(0.00175)
    assert _frame_gap("COM3", t, None) == pytest.approx(3.5 * 10 / 9600 + 0.020)
    assert _frame_gap("socket://127.0.0.1:1", t, None) == pytest.approx(3.5 * 10 / 9600 + 0.100)
    assert _frame_gap("COM3", _timing(9600, "N", 1, "ascii", None), None) == 1.0


# --- SerialServer on a URL it opens itself ------------------------------------------------------------------
def test_serial_server_opens_a_socket_url_and_answers_raw_rtu():
    import socket

    listener = socket.create_server((HOST, 0))
    try:
        port = listener.getsockname()[1]
        slave = Slave(unit=1, processing_time=0.05)  # a slow device: really waits 50 ms
        slave.bank.holding_registers[0] = 0x1234
        with SerialServer(slave, f"socket://{HOST}:{port}", 19200, "E", 1, mode="rtu") as server:
            line, _ = listener.accept()
            with line:
                line.settimeout(2)
                line.sendall(bytes.fromhex("01 03 00 00 00 01 84 0A"))
                answer = b""
                while len(answer) < 7:
                    answer += line.recv(7 - len(answer))
                assert answer == RtuFrame(
                    unit=1, pdu=ReadHoldingRegistersResponse(registers=(0x1234,))
                ).encode()
                assert "socket://" in repr(server) and "19200 baud 8E1 RTU running" in repr(server)
            assert server.counters.as_dict() == {"frames": 1, "responses": 1, "no_slave": 0, "failures": 0}
        assert "closed" in repr(server)
        server.close()  # harmless twice
        with pytest.raises(LinkError, match="closed"):
            server.start()
    finally:
        listener.close()


def test_serial_server_rejects_what_is_not_a_port():
    with pytest.raises(ConfigError, match="pyserial URL or an open pyserial-like object"):
        SerialServer(Slave(), object())


def test_a_serial_line_listening_beyond_loopback_warns_and_loopback_does_not(caplog, monkeypatch):
    import logging

    import modbus_edu.links.serial as serial_module
    from modbus_edu.links.serial import TcpSerialPort

    with caplog.at_level(logging.WARNING, logger="modbus_edu.serial"):
        TcpSerialPort("127.0.0.1").close()
    assert "no authentication" not in caplog.text
    # it really binds 127.0.0.1: the test only makes the port believe the address is reachable
    monkeypatch.setattr(serial_module, "is_loopback_host", lambda host: False)
    with caplog.at_level(logging.WARNING, logger="modbus_edu.serial"):
        TcpSerialPort("127.0.0.1").close()
    assert "beyond this computer" in caplog.text and "no authentication" in caplog.text
